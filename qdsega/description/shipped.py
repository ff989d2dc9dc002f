"""Shipped formations by name: ``snake5`` means the packaged ``snake5.yaml``."""

from __future__ import annotations

from pathlib import Path

from qdsega import ASSEMBLIES_DIR
from qdsega.errors import FormationError


def shipped_formation_names() -> list[str]:
    """Names of the shipped formations, sorted (``hexapod``, ..., ``snake5``)."""
    return sorted(file.stem for file in ASSEMBLIES_DIR.glob("*.yaml"))


def resolve_formation(argument: str | Path) -> Path:
    """The formation file a command-line argument means.

    An existing file, or anything with a folder or a suffix (``my.yaml``, ``robots/x``), is a
    path; any other bare name, such as ``snake5``, is the shipped formation of that name.

    Raises:
        FormationError: a bare name that no shipped formation has (the message lists them).
    """
    path = Path(argument)
    if path.is_file() or len(path.parts) != 1 or path.suffix:
        return path
    names = shipped_formation_names()
    if path.name not in names:
        raise FormationError(
            f"no such file, nor a shipped formation (shipped: {', '.join(names)})", file=path
        )
    return ASSEMBLIES_DIR / f"{path.name}.yaml"
