"""Helpers shared by tests (import as ``from helpers import ...``)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from qdsega import ASSEMBLIES_DIR, UNITS_DIR

SHIPPED_FORMATIONS = sorted(ASSEMBLIES_DIR.glob("*.yaml"))
SHIPPED_UNITS = sorted(p for p in UNITS_DIR.iterdir() if p.is_dir() and p.name != "__pycache__")


def run_cli(*args: str | Path, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``qdsega ARGS`` in a subprocess; capture text output."""
    return subprocess.run(
        [sys.executable, "-m", "qdsega.cli", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
        check=False,
    )
