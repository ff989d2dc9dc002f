"""``qdsega render`` through a subprocess: frames, formats and bad input."""

import imageio.v3 as iio
import numpy as np
from helpers import run_cli

from qdsega.analysis.video import GIF_COLOURS

SNAKE = "assemblies/snake5.yaml"


def _postures(tmp_path):
    file = tmp_path / "wave.csv"
    file.write_text("# a short wave\n4,4,4,4\n0,8,0,8\n8,0,8,0\n")
    return file


def test_mp4_has_the_requested_frames_and_shows_the_robot(tmp_path):
    out = tmp_path / "wave.mp4"
    result = run_cli(
        "render",
        SNAKE,
        "--postures",
        _postures(tmp_path),
        "-o",
        out,
        "--fps",
        "10",
        "--width",
        "160",
        "--height",
        "120",
    )
    assert result.returncode == 0, result.stderr
    assert "warning" not in result.stderr  # EGL loads here (Mesa llvmpipe, no GPU needed)
    frames = np.stack(list(iio.imiter(out, plugin="FFMPEG")))
    # 3 steps of 0.5 s at 10 fps, plus the first frame
    assert frames.shape == (16, 120, 160, 3)
    blue = (frames[..., 2] > 140) & (frames[..., 0] < 100)  # the servo units
    assert blue.mean(axis=(1, 2)).min() > 0.002
    assert frames.std() > 10  # not a blank picture


def test_gif_on_request_of_a_shipped_formation_by_name(tmp_path):
    out = tmp_path / "wave.gif"
    result = run_cli(
        "render",
        "snake5",
        "--postures",
        _postures(tmp_path),
        "-o",
        out,
        "--fps",
        "4",
        "--width",
        "64",
        "--height",
        "48",
    )
    assert result.returncode == 0, result.stderr
    frames = iio.imread(out)[..., :3]
    # 7 frames are filmed; GIF writers merge identical neighbours (the snake at rest)
    assert 2 <= len(frames) <= 7 and frames.shape[1:] == (48, 64, 3)
    colours = np.unique(frames.reshape(-1, 3), axis=0)
    assert 8 <= len(colours) <= GIF_COLOURS  # one palette for every frame


def test_bad_input_is_one_line_and_leaves_no_file(tmp_path):
    postures = _postures(tmp_path)
    cases = [
        (["render", SNAKE, "--postures", postures, "-o", tmp_path / "x.avi"], "must end in"),
        (["render", SNAKE, "-o", tmp_path / "x.mp4"], "needs --postures"),
        (["render", tmp_path / "no-run", "-o", tmp_path / "x.mp4"], "needs --postures"),
        (["render", SNAKE, "--postures", SNAKE, "-o", tmp_path / "x.mp4"], "cannot read"),
        (["render", "snak5", "--postures", postures, "-o", tmp_path / "x.mp4"], "shipped: "),
        (
            ["render", SNAKE, "--postures", postures, "-o", tmp_path / "x.mp4", "--fps", "0"],
            "fps must be",
        ),
    ]
    for args, message in cases:
        result = run_cli(*args)
        assert result.returncode == 2, (args, result.stderr)
        assert message in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["wave.csv"]


def test_without_egl_it_warns_once_and_still_renders(tmp_path, monkeypatch, capsys):
    from qdsega.cli import main
    from qdsega.simulation.bullet import BulletSimulation

    monkeypatch.setattr(BulletSimulation, "_load_egl", lambda self: False)
    out = tmp_path / "tiny.gif"
    status = main(
        ["render", SNAKE, "--postures", str(_postures(tmp_path)), "-o", str(out),
         "--fps", "2", "--width", "48", "--height", "32"]
    )  # fmt: skip
    captured = capsys.readouterr()
    assert status == 0
    assert captured.err == "qdsega render: warning: EGL unavailable, rendered with TinyRenderer\n"
    frames = iio.imread(out)
    assert frames.shape[1:] == (32, 48, 3) and frames.std() > 10


def test_by_default_the_video_is_640x480_and_the_body_fills_a_fair_part_of_it(tmp_path):
    postures = tmp_path / "rest.csv"
    postures.write_text(",".join(["0"] * 12) + "\n")  # hexapod: 12 joints, one step at rest
    out = tmp_path / "hexapod.mp4"
    result = run_cli("render", "hexapod", "--postures", postures, "-o", out, "--fps", "4")
    assert result.returncode == 0, result.stderr
    frame = iio.imread(out, index=0)
    assert frame.shape == (480, 640, 3)
    blue = (frame[..., 2] > 140) & (frame[..., 0] < 110)  # the servo units
    blue[:100] = False  # not the sky
    columns = np.flatnonzero(blue.any(axis=0))
    assert columns.max() - columns.min() > 0.4 * 640  # framed: a third at most before
