"""The built wheel works anywhere: installed into a fresh virtual environment and run from a
folder outside the checkout, it finds its own units and formations."""

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import venv
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

CHECKOUT = Path(__file__).resolve().parent.parent
SOURCES = ("pyproject.toml", "README.md", "LICENSE", "qdsega", "units", "assemblies", "worlds")
"""What the wheel is built from: copied, so that the build leaves nothing in the checkout."""

TINY_TRAINING = "agent:\n  genetic: {population: 2}\nlocal_search: 1\ntask: {trial_steps: 4}\n"


def _run(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    result = subprocess.run(
        [str(a) for a in args],
        cwd=cwd,
        env=environment,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    print(f"$ {' '.join(str(a) for a in args)}\n{result.stdout}{result.stderr}")
    assert result.returncode == 0, result.stderr
    return result


def _build_wheel(folder: Path) -> Path:
    source = folder / "source"
    source.mkdir(parents=True)
    for name in SOURCES:
        if (CHECKOUT / name).is_dir():
            ignore = shutil.ignore_patterns("__pycache__")
            shutil.copytree(CHECKOUT / name, source / name, ignore=ignore)
        else:
            shutil.copy2(CHECKOUT / name, source / name)
    _run(sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--quiet",
         ".", "-w", folder / "dist", cwd=source)  # fmt: skip
    (wheel,) = (folder / "dist").glob("qdsega-*.whl")
    return wheel


def _fresh_environment(folder: Path) -> Path:
    """A new virtual environment that borrows this one's dependencies (a .pth line), but
    none of its .pth files: the editable install of the checkout stays invisible."""
    venv.create(folder, with_pip=False)
    python = folder / "bin" / "python"
    site_packages = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    borrowed = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
    Path(site_packages, "dependencies.pth").write_text("\n".join(sorted(borrowed)) + "\n")
    return python


def test_wheel_installs_and_runs_outside_the_checkout(tmp_path):
    wheel = _build_wheel(tmp_path / "build")
    names = set(zipfile.ZipFile(wheel).namelist())
    shipped = [*(CHECKOUT / "qdsega").rglob("*.py"), *(CHECKOUT / "qdsega").rglob("*.json")]
    for file in shipped:  # code and shipped reference gaits
        assert file.relative_to(CHECKOUT).as_posix() in names, f"{file} is not in the wheel"
    assert "qdsega/py.typed" in names  # type hints for the users' checkers
    assert any(name.endswith(".dist-info/licenses/LICENSE") for name in names), names
    for folder, package in (
        ("units", "qdsega/units"),
        ("assemblies", "qdsega/assemblies"),
        ("worlds", "qdsega/worlds"),
    ):
        for file in (CHECKOUT / folder).rglob("*"):
            if file.is_file() and "__pycache__" not in file.parts:
                assert f"{package}/{file.relative_to(CHECKOUT / folder).as_posix()}" in names

    python = _fresh_environment(tmp_path / "env")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    _run(python, "-m", "pip", "install", "--no-deps", "--no-index", "--ignore-installed",
         "--quiet", wheel, cwd=elsewhere)  # fmt: skip
    found = _run(
        python,
        "-c",
        "import qdsega; from qdsega.description.shipped import UNITS_DIR; "
        "print(qdsega.__file__, UNITS_DIR)",
        cwd=elsewhere,
    )
    module, units = found.stdout.split()
    assert Path(module).is_relative_to(tmp_path / "env") and Path(units).is_relative_to(
        tmp_path / "env"
    )

    declared = re.search(r'^version = "(.+)"$', (CHECKOUT / "pyproject.toml").read_text(), re.M)
    versions = _run(python, "-m", "qdsega", "--version", cwd=elsewhere)
    assert versions.stdout.strip() == f"qdsega {declared[1]}"  # pyproject.toml: its one source

    qdsega = tmp_path / "env" / "bin" / "qdsega"
    assembled = _run(qdsega, "assemble", "snake5", cwd=elsewhere)
    assert assembled.stdout.splitlines()[1].split()[:4] == ["snake5", "5", "4", "0"]
    assert (elsewhere / "snake5.urdf").is_file()
    (elsewhere / "tiny.yaml").write_text(TINY_TRAINING)
    _run(qdsega, "train", "snake5", "--sim", "memo", "--preset", "paper-snake",
         "--config", "tiny.yaml", "--generations", "1", "--trials", "2", "--workers", "1",
         "--out", "RUN", "--quiet", cwd=elsewhere)  # fmt: skip
    for name in ("config.yaml", "transitions.npz", "policy.npz", "summary.json"):
        assert (elsewhere / "RUN" / name).is_file(), name
