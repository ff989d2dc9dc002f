"""``python -m qdsega``: the same command line as ``qdsega``."""

from qdsega.cli import main

raise SystemExit(main())
