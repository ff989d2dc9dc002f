"""Subcommands of the ``qdsega`` command line, one module each."""
