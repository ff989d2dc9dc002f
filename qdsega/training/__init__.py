"""The run lifecycle: configuration, the run folder, training and resuming, checkpoints, warm
starts."""
