"""What a finished run shows: its evaluation in exact physics, figures, videos and the report."""
