"""Training runs: resolved configuration, the run folder, and its figures."""
