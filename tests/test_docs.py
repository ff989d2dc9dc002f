"""The docs' examples run as written: the worked example of docs/formations.md and every
Python snippet of the README, docs/gymnasium.md and docs/worlds.md (learning on a tiny
budget)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from helpers import TINY_TRAINING, run_cli

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

ROOT = Path(__file__).resolve().parents[1]
GUIDE = ROOT / "docs" / "formations.md"


def _section(title: str) -> str:
    text = GUIDE.read_text(encoding="utf-8")
    start = text.index(f"## {title}")
    return text[start : text.index("\n## ", start + 1)]


def test_worked_example_runs_as_written(tmp_path):
    section = _section("Worked example")
    formation = re.search(r"```yaml\n(.*?)```", section, re.S).group(1)
    commands = re.search(r"```bash\n(.*?)```", section, re.S).group(1)
    (tmp_path / "assemblies").mkdir()
    (tmp_path / "assemblies" / "my_snake.yaml").write_text(formation)
    (tmp_path / "tiny.yaml").write_text(TINY_TRAINING)
    for line in commands.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("printf"):
            text = shlex.split(line.split(">")[0])[1].encode().decode("unicode_escape")
            (tmp_path / line.split(">")[1].strip()).write_text(text)
            continue
        for command in line.split("&&"):
            args = shlex.split(command)
            assert args[0] == "qdsega", command
            if args[1] == "train":  # the same command, on a budget a test can afford
                args += ["--generations", "1", "--config", "tiny.yaml"]
            if args[1] == "evaluate":  # the classic gaits only, no CMA-ES search
                args += ["--reference-trials", "0"]
            result = run_cli(*args[1:], cwd=tmp_path)
            assert result.returncode == 0, (command, result.stderr)
    run = tmp_path / "runs" / "my_snake-memo-seed0"
    assert (run / "evaluation.json").is_file() and (run / "learning_curve.png").is_file()
    assert (tmp_path / "wave.gif").stat().st_size > 1000
    assert "my_snake" in (tmp_path / "out" / "my_snake.urdf").read_text()


@pytest.mark.parametrize("page", ["README.md", "docs/gymnasium.md", "docs/worlds.md"])
def test_python_snippets_run_as_written(page, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)  # snippets name files of the checkout (assemblies/...)
    snippets = re.findall(r"```python\n(.*?)```", (ROOT / page).read_text(), re.S)
    assert snippets, page
    namespace = {"__name__": "snippet"}  # a page's snippets go on from one another
    for snippet in snippets:
        # Learning on a budget a test can afford: one rollout (docs/gymnasium.md's PPO).
        snippet = re.sub(r"total_timesteps=[\d_]+", "total_timesteps=1", snippet)
        exec(compile(snippet, page, "exec"), namespace)


def test_the_world_format_example_loads(tmp_path):
    from qdsega.description import load_world

    text = (ROOT / "docs" / "worlds.md").read_text()
    section = text[text.index("## The format") :]
    example = re.search(r"```yaml\n(.*?)```", section, re.S).group(1)
    (tmp_path / "course.yaml").write_text(example)
    world = load_world(tmp_path / "course.yaml")
    assert world.name == "obstacle_course" and len(world.boxes) == 1 and world.stairs is not None
