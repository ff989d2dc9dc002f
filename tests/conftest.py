"""Shared fixtures: a scratch project folder, the CLI in a subprocess."""

from __future__ import annotations

import os
import shutil
import textwrap
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from qdsega.description.shipped import UNITS_DIR


@pytest.fixture
def project(tmp_path: Path) -> Path:
    """A scratch project folder holding a copy of the shipped units/ and an assemblies/."""
    shutil.copytree(UNITS_DIR, tmp_path / "units")
    (tmp_path / "assemblies").mkdir()
    return tmp_path


@pytest.fixture
def write_formation(project: Path) -> Callable[[str, str], Path]:
    """Write ``text`` (dedented) as ``assemblies/<name>.yaml`` using the project's units."""

    def write(text: str, name: str = "robot") -> Path:
        file = project / "assemblies" / f"{name}.yaml"
        file.write_text(textwrap.dedent(text), encoding="utf-8")
        return file

    return write


@pytest.fixture
def cli() -> Callable[..., object]:
    from helpers import run_cli

    return run_cli


@pytest.fixture(autouse=True, scope="session")
def _reference_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    """Searched reference gaits go to a scratch cache, not the user's (subprocesses inherit
    it through the environment)."""
    os.environ["QDSEGA_CACHE"] = str(tmp_path_factory.mktemp("qdsega-cache"))


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished, evaluated run (snake5 in memo mode, seconds of training), made once for all
    test processes (:func:`made_once`); copy it (:func:`shutil.copytree`) before changing it.
    What train and evaluate printed is beside it, in ``printed.txt``."""
    from helpers import TINY_TRAINING, made_once, run_cli

    def make(folder: Path) -> None:
        (folder / "tiny.yaml").write_text(TINY_TRAINING)
        trained = run_cli(
            "train", "snake5", "--sim", "memo", "--generations", "1",
            "--config", folder / "tiny.yaml", "--out", folder / "snake5",
        )  # fmt: skip
        assert trained.returncode == 0, trained.stderr
        evaluated = run_cli("evaluate", folder / "snake5", "--reference-trials", "0")
        assert evaluated.returncode == 0, evaluated.stderr
        printed = trained.stdout + trained.stderr + evaluated.stdout
        (folder / "printed.txt").write_text(printed)

    return made_once(tmp_path_factory, "tiny-run", make) / "snake5"


@pytest.fixture(scope="session")
def quadruped_repertoire(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A repertoire of quadruped gaits filled in exact physics under memo mode's rules (40
    trials into 8 cells), built by the library, made once for all test processes
    (:func:`made_once`); copy it before changing it."""
    from helpers import made_once

    from qdsega.adaptation.repertoire import RepertoireSettings, build_repertoire
    from qdsega.description import load_formation, resolve_formation
    from qdsega.training.config import resolve_config

    def make(folder: Path) -> None:
        quadruped = load_formation(resolve_formation("quadruped"))
        rules = resolve_config(overrides={"sim": "memo"}, formation=quadruped).rules()
        settings = RepertoireSettings(evaluations=40, cells=8)
        build_repertoire(quadruped, folder / "quadruped", rules=rules, settings=settings, workers=1)

    return made_once(tmp_path_factory, "quadruped-repertoire", make) / "quadruped"


@pytest.fixture(scope="session")
def local_ray() -> Iterator[Any]:
    """A local Ray instance in this test process, started once for every test that uses
    ``--ray local`` here (their runs find it up), with one thread each for linear algebra as
    :func:`qdsega.driver.run_jobs` would start it; stopped when the session ends."""
    ray = pytest.importorskip("ray", reason="Ray is an optional extra: pip install -e '.[ray]'")
    from qdsega.driver import one_thread_each
    from qdsega.workers.ray_cluster import LOCAL, connect

    with one_thread_each():  # read by the raylet and the workers it starts
        connected = connect(LOCAL)
    yield connected
    ray.shutdown()


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The slow tests first, in their order, then the rest: two processes then end together,
    the short tests filling in, instead of one long test running alone at the end."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)
