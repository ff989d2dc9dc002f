"""Shipped data by name: ``snake5`` means the packaged ``snake5.yaml``, ``stairs`` the
packaged world ``stairs.yaml``."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from qdsega.errors import FormationError, QdsegaError, WorldError


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

WORLDS_DIR = _data_folder("qdsega.worlds")
"""Shipped world files: ``worlds/`` of the checkout (``qdsega/worlds`` installed)."""


def shipped_formation_names() -> list[str]:
    """Names of the shipped formations, sorted (``hexapod``, ..., ``snake5``)."""
    return _names(ASSEMBLIES_DIR)


def shipped_world_names() -> list[str]:
    """Names of the shipped worlds, sorted (``corridor``, ..., ``tunnel``)."""
    return _names(WORLDS_DIR)


def shipped_unit_names() -> list[str]:
    """Names of the shipped unit types, sorted (``hub``, ``servo``)."""
    return sorted(file.parent.name for file in UNITS_DIR.glob("*/unit.yaml"))


def resolve_formation(argument: str | Path) -> Path:
    """The formation file a command-line argument means.

    An existing file, or anything with a folder or a suffix (``my.yaml``, ``robots/x``), is a
    path; any other bare name, such as ``snake5``, is the shipped formation of that name.

    Raises:
        FormationError: a bare name that no shipped formation has (the message lists them).
    """
    return _resolve(argument, ASSEMBLIES_DIR, "formation", FormationError)


def resolve_world(argument: str | Path) -> Path:
    """The world file a command-line argument means: a path, or a shipped world's name
    (``stairs``), as :func:`resolve_formation` tells them apart.

    Raises:
        WorldError: a bare name that no shipped world has (the message lists them).
    """
    return _resolve(argument, WORLDS_DIR, "world", WorldError)


def _names(folder: Path) -> list[str]:
    return sorted(file.stem for file in folder.glob("*.yaml"))


def _resolve(argument: str | Path, folder: Path, kind: str, error: type[QdsegaError]) -> Path:
    path = Path(argument)
    if path.is_file() or len(path.parts) != 1 or path.suffix:
        return path
    names = _names(folder)
    if path.name not in names:
        raise error(f"no such file, nor a shipped {kind} (shipped: {', '.join(names)})", file=path)
    return folder / f"{path.name}.yaml"
