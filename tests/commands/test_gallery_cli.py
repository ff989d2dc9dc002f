"""``qdsega gallery``: one body and one world end to end, small; bad input."""

import imageio.v3 as iio
import pytest
from helpers import run_cli

from qdsega.cli import main


@pytest.mark.slow
def test_one_body_and_one_world_with_the_unit_diagrams_and_the_leg_states(tmp_path):
    out = tmp_path / "gallery"
    result = run_cli(
        "gallery", "--out", out, "--formation", "snake5", "--world", "corridor",
        "--width", "160", "--height", "120",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "warning" not in result.stderr
    assert result.stdout.splitlines()[:2] == [
        f"bodies: 2 pictures -> {out}/bodies/snake5.png, {out}/bodies.png",
        f"worlds: 2 pictures -> {out}/worlds/corridor.png, {out}/worlds.png",
    ]
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*.png"))
    assert written == [
        "bodies.png", "bodies/snake5.png", "leg_states.png", "unit_hub.png", "unit_servo.png",
        "worlds.png", "worlds/corridor.png",
    ]  # fmt: skip
    for still in ("bodies/snake5.png", "worlds/corridor.png"):
        picture = iio.imread(out / still, mode="RGB")
        assert picture.shape == (120, 160, 3)
        blue = (picture[..., 2] > 140) & (picture[..., 0] < 110)  # the servo units
        assert blue.mean() > 0.001, still  # the body shows (in the corridor: snake5, not quadruped)
    for file in written:
        assert (out / file).stat().st_size < 100_000, file


def test_a_bad_world_or_size_is_one_line_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "gallery"
    for args, message in [
        (["--world", "moon"], "nor a shipped world"),
        (["--formation", "snak5"], "nor a shipped formation"),
        (["--width", "8"], "at least 16x16"),
    ]:
        assert main(["gallery", "--out", str(out), *args]) == 2
        err = capsys.readouterr().err
        assert err.startswith("qdsega gallery: error: ") and message in err, err
        assert len(err.strip().splitlines()) == 1
    assert not out.exists()
