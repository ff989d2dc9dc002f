"""Shipped formations by name: ``snake5`` means the packaged ``snake5.yaml``."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from qdsega.errors import FormationError


def _data_folder(package: str) -> Path:
    """The folder of data package ``package``; installs are plain files, never zipped."""
    folder = files(package)
    if not isinstance(folder, Path):
        raise ImportError(f"{package} is not a folder on disk ({folder}); install qdsega unzipped")
    return folder


UNITS_DIR = _data_folder("qdsega.units")
"""Shipped unit types, one folder each: ``units/`` of the checkout (``qdsega/units`` installed)."""

ASSEMBLIES_DIR = _data_folder("qdsega.assemblies")
"""Shipped formation files: ``assemblies/`` of the checkout (``qdsega/assemblies`` installed)."""


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
