"""A run folder's own copies of its formation and its world, so that a finished run never reads
the originals.

``RUN/formation/`` holds the formation file and, in ``units/``, every file of the unit types it
uses (``unit.yaml``, the link template, meshes), the user's own and the shipped ones alike,
laid out as in their project folder (the folder holding a units folder), so that
:func:`qdsega.description.load_formation` reads the same formation from the copy alone.
``RUN/formation.json`` records, written last:

* ``formation``, ``units_dir``: the formation file and the units folder inside ``formation/``;
* ``source_file``, ``source_dir``: the original formation file and the project folder of its
  first unit type (absolute); ``sources``: the original of every copied file (absolute; a
  record written before it existed finds them under ``source_dir``);
* ``files``: the sha256 (hex) of every copied file, by its path inside ``formation/``;
* ``sha256``: the formation's content hash, the sha256 of the lines ``<file sha256>  <path>``
  (sorted by path, each ending in a newline): the same for the same files anywhere.

Every command that needs a run's formation (``train --resume``, ``evaluate``, ``render``)
loads it with :func:`load_run_formation`: it checks the copy against its hashes and warns, in
one line, when the original has changed since.
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, World, load_formation, load_world
from qdsega.description.unit_type import mesh_files
from qdsega.errors import FormationError, QdsegaWarning, RunFolderError, WorldError
from qdsega.training.config import TrainingConfig
from qdsega.training.run_folder import RunFolder

_UNITS = "units"
"""The folder inside ``formation/`` that holds the copied unit types."""


@dataclass(frozen=True, kw_only=True)
class FormationRecord:
    """What ``formation.json`` holds (see the module's documentation)."""

    formation: str
    units_dir: str
    source_file: str
    source_dir: str
    files: dict[str, str]
    sources: dict[str, str] | None = None

    @property
    def sha256(self) -> str:
        """The formation's content hash (hex)."""
        return content_hash(self.files)

    def summary(self) -> dict[str, str]:
        """What ``summary.json`` says about the formation: the original file, the hash."""
        return {"formation_file": self.source_file, "formation_sha256": self.sha256}

    def source(self, path: str) -> Path:
        """Where the copied file ``path`` (inside ``formation/``) came from."""
        if path == self.formation:
            return Path(self.source_file)
        if self.sources is not None:
            return Path(self.sources[path])
        return Path(self.source_dir) / path


@dataclass(frozen=True)
class FormationSnapshot:
    """A formation's files read into memory, ready to be written into a run folder.

    Attributes:
        record: what ``formation.json`` will hold.
        contents: every file's bytes, by its path inside ``formation/``.
    """

    record: FormationRecord
    contents: dict[str, bytes]

    @classmethod
    def of(cls, formation: Formation) -> FormationSnapshot:
        """Read the files ``formation`` was loaded from.

        Raises:
            FormationError: a file cannot be read, or does not fit the copy's layout.
        """
        source = Path(formation.file).resolve()
        units_dir = formation.root.unit_type.folder.parent.resolve()
        unit_files: dict[str, Path] = {}
        for unit_type in {u.unit_type.name: u.unit_type for u in formation.units}.values():
            folder = unit_type.folder.resolve()
            inside = f"{_UNITS}/{unit_type.name}"
            for file in (
                folder / "unit.yaml",
                unit_type.template_file.resolve(),
                *mesh_files(unit_type.link_template, folder),
            ):
                path = os.path.normpath(f"{inside}/{os.path.relpath(file, folder)}")
                unit_files[Path(path).as_posix()] = file
        for path in unit_files:
            if Path(path).parts[0] in (source.name, ".."):
                message = f"cannot copy {path} beside the formation file into the run folder"
                raise FormationError(message, file=formation.file)
        files = {source.name: source, **unit_files}
        try:
            contents = {path: file.read_bytes() for path, file in files.items()}
        except OSError as exc:
            raise FormationError(f"cannot copy the formation: {exc}", file=formation.file) from None
        record = FormationRecord(
            formation=source.name,
            units_dir=_UNITS,
            source_file=str(source),
            source_dir=str(units_dir.parent),
            files={path: _sha256(data) for path, data in sorted(contents.items())},
            sources={path: str(file) for path, file in sorted(unit_files.items())},
        )
        return cls(record=record, contents=contents)

    def write(self, run: Path) -> None:
        """Write ``formation/`` and, last, ``formation.json`` into ``run``."""
        for path, data in self.contents.items():
            target = run / RunFolder.FORMATION_DIR / path
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        with replaced_atomically(run / RunFolder.FORMATION_RECORD) as partial:
            partial.write_text(json.dumps(asdict(self.record), indent=2) + "\n", encoding="utf-8")


def load_run_formation(
    run: Path, config: TrainingConfig, *, world: World | None = None
) -> Formation:
    """The formation of run folder ``run``, from its copy, with the light of ``world`` (None:
    the run's own), moved where ``config`` puts it. Warns
    (:class:`~qdsega.errors.QdsegaWarning`) when the original files have changed since the
    run copied them.

    Raises:
        RunFolderError: no copy, or one that does not match its hashes.
    """
    record = read_formation_record(run)
    copy = run / RunFolder.FORMATION_DIR
    for path, sha in record.files.items():
        file = copy / path
        if not file.is_file() or _sha256(file.read_bytes()) != sha:
            state = "is missing" if not file.is_file() else "differs from its sha256"
            copied = f"{RunFolder.FORMATION_DIR}/{path}"
            message = f"corrupt run folder ({copied} {state} in {RunFolder.FORMATION_RECORD})"
            raise RunFolderError(message, file=run)
    if Path(record.source_file).is_file():
        now = content_hash({path: _source_sha256(record.source(path)) for path in record.files})
        if now != record.sha256:
            warnings.warn(
                f"{record.source_file} or its unit files changed since this run copied them "
                f"(sha256 {now[:12]}, copy {record.sha256[:12]}); using the copy in {copy}",
                QdsegaWarning,
                stacklevel=2,
            )
    formation = load_formation(copy / record.formation, units_dir=copy / record.units_dir)
    place = load_run_world(run) if world is None else world
    return config.with_light(place.lights(formation))


def copy_world(world: World, run: Path) -> None:
    """Write the run's own copy of the world file it trains in (``world.yaml``); nothing for
    the flat plane that no file describes.

    Raises:
        WorldError: the world file cannot be read again.
    """
    if world.file is None:
        return
    try:
        data = world.file.read_bytes()
    except OSError as exc:
        raise WorldError(f"cannot copy the world: {exc}", file=world.file) from None
    with replaced_atomically(run / RunFolder.WORLD) as partial:
        partial.write_bytes(data)


def load_run_world(run: Path) -> World:
    """The world of run folder ``run``, from its copy; the flat plane where it has none.

    Raises:
        RunFolderError: a copy that does not read as a world.
    """
    file = run / RunFolder.WORLD
    if not file.is_file():
        return World()
    try:
        return load_world(file)
    except WorldError as exc:
        raise RunFolderError(f"corrupt run folder ({exc})", file=run) from None


def world_sha256(run: Path) -> str | None:
    """The sha256 (hex) of the run's copy of its world file, or None without one."""
    file = run / RunFolder.WORLD
    return _sha256(file.read_bytes()) if file.is_file() else None


def read_formation_record(run: Path) -> FormationRecord:
    """The run's ``formation.json``.

    Raises:
        RunFolderError: the file is missing or is not a record.
    """
    file = run / RunFolder.FORMATION_RECORD
    if not file.is_file():
        raise RunFolderError(
            f"no copy of the formation ({RunFolder.FORMATION_RECORD}): the run stopped before "
            "it was made, or an older qdsega wrote it; start the run again with "
            f"qdsega train FORMATION --out {run} --overwrite",
            file=run,
        )
    try:
        data: Any = json.loads(file.read_text(encoding="utf-8"))
        record = FormationRecord(**data)
    except (OSError, ValueError, TypeError) as exc:
        message = f"corrupt {RunFolder.FORMATION_RECORD} ({exc.__class__.__name__}: {exc})"
        raise RunFolderError(message, file=run) from None
    if not isinstance(record.files, dict) or record.formation not in record.files:
        message = f"corrupt {RunFolder.FORMATION_RECORD} (no formation file listed)"
        raise RunFolderError(message, file=run)
    return record


def content_hash(files: dict[str, str]) -> str:
    """The sha256 (hex) of the lines ``<sha256>  <path>`` of ``files``, sorted by path."""
    lines = "".join(f"{sha}  {path}\n" for path, sha in sorted(files.items()))
    return _sha256(lines.encode("utf-8"))


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _source_sha256(file: Path) -> str:
    """The sha256 of an original file, or "" when it cannot be read (gone)."""
    try:
        return _sha256(file.read_bytes())
    except OSError:
        return ""
