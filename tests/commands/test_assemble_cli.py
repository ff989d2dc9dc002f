"""``qdsega assemble`` through a subprocess: good output, and every class of bad input."""

import contextlib
import io
import textwrap

import pytest
import yourdfpy
from helpers import SHIPPED_FORMATIONS, run_cli

from qdsega.cli import main

GOOD = """\
name: robot
light: {distance_m: 3}
units_dir: ../units
units:
  - {name: head, unit: my_servo}
  - {name: tail, unit: my_servo, parent: head, connector: back, axis: yaw, levels_deg: [-10, 10]}
"""


@pytest.fixture(autouse=True)
def _own_servo(request):
    """In a scratch project, the servo is a unit type of the user's own, ``my_servo``: its
    files can be broken without clashing with the shipped servo."""
    if "project" in request.fixturenames:
        units = request.getfixturevalue("project") / "units"
        (units / "servo").rename(units / "my_servo")


def test_assembles_every_shipped_formation_and_prints_a_table(tmp_path):
    result = run_cli("assemble", *SHIPPED_FORMATIONS, "--out-dir", tmp_path)
    assert result.returncode == 0, result.stderr
    header, *rows = result.stdout.splitlines()
    assert header.split() == [
        "formation",
        "units",
        "joints",
        "legs",
        "mass_kg",
        "assemble_ms",
        "urdf",
    ]
    assert sorted(row.split()[0] for row in rows) == sorted(f.stem for f in SHIPPED_FORMATIONS)
    for file in SHIPPED_FORMATIONS:
        model = yourdfpy.URDF.load(tmp_path / f"{file.stem}.urdf", build_scene_graph=False)
        assert model.validate()


def test_same_input_gives_byte_identical_output(tmp_path):
    for name in ("a", "b"):
        result = run_cli("assemble", "assemblies/legged12.yaml", "-o", tmp_path / f"{name}.urdf")
        assert result.returncode == 0, result.stderr
    assert (tmp_path / "a.urdf").read_bytes() == (tmp_path / "b.urdf").read_bytes()


def _assert_rejected(project, formation_text, expected, *, line=None, subprocess=False):
    """Bad input: exit status 2, one line on stderr, no output. In-process unless asked."""
    file = project / "assemblies" / "robot.yaml"
    file.write_text(formation_text)
    out = project / "out" / "robot.urdf"
    if subprocess:
        result = run_cli("assemble", file, "-o", out, cwd=project)
        code, stdout, stderr = result.returncode, result.stdout, result.stderr
    else:
        with (
            contextlib.redirect_stdout(io.StringIO()) as stdout_buffer,
            contextlib.redirect_stderr(io.StringIO()) as stderr_buffer,
        ):
            code = main(["assemble", str(file), "-o", str(out)])
        stdout, stderr = stdout_buffer.getvalue(), stderr_buffer.getvalue()
    assert code == 2, stdout + stderr
    lines = stderr.splitlines()
    assert len(lines) == 1, stderr
    assert "Traceback" not in stderr
    assert expected in lines[0]
    if line is not None:
        assert f":{line}:" in lines[0]
    assert not out.exists()
    assert not out.parent.exists() or not any(out.parent.iterdir())
    return lines[0]


def test_yaml_syntax_error(project):
    text = GOOD + "  - {name: x, unit: [\n"
    message = _assert_rejected(project, text, "YAML syntax error", subprocess=True)
    assert "robot.yaml:" in message


def test_a_nul_character_is_one_line_with_the_file_and_its_line(project):
    text = GOOD.replace("head, unit: my_servo}", "he\x00ad, unit: my_servo}")
    message = _assert_rejected(
        project, text, "unacceptable character #x0000", line=5, subprocess=True
    )
    assert message.startswith(f"qdsega assemble: error: {project / 'assemblies' / 'robot.yaml'}:5:")
    assert "<unicode string>" not in message


def test_empty_file(project):
    _assert_rejected(project, "# nothing here\n", "file is empty")


def test_python_object_tags_are_refused(project):
    text = GOOD.replace("name: robot", "name: !!python/object/apply:os.system ['true']")
    _assert_rejected(project, text, "unsupported YAML tag", line=1)


@pytest.mark.parametrize(
    ("old", "new", "expected", "line"),
    [
        ("{distance_m: 3}", "{distance_m: three}", "light.distance_m: expected a number", 2),
        ("levels_deg: [-10, 10]", "levels_deg: 10", "units[1].levels_deg: expected a list", 6),
        ("name: robot", "name: [robot]", "name: expected non-empty text", 1),
        ("axis: yaw", "axis: sideways", "units[1].axis: expected one of roll, pitch, yaw", 6),
    ],
)
def test_wrong_types(project, old, new, expected, line):
    _assert_rejected(project, GOOD.replace(old, new), expected, line=line)


def test_unknown_key(project):
    text = GOOD.replace("axis: yaw", "axis: yaw, colour: red")
    _assert_rejected(project, text, "units[1].colour: unknown key", line=6)


def test_missing_parent(project):
    text = GOOD.replace("parent: head", "parent: neck")
    _assert_rejected(project, text, "units[1].parent: unknown parent unit 'neck'", line=6)


def test_cycle(project):
    text = GOOD + (
        "  - {name: a, unit: my_servo, parent: b, connector: back, axis: yaw, levels_deg: [0]}\n"
        "  - {name: b, unit: my_servo, parent: a, connector: back, axis: yaw, levels_deg: [0]}\n"
    )
    _assert_rejected(project, text, "is in a cycle", line=7)


def test_no_root_is_a_cycle(project):
    text = GOOD.replace(
        "{name: head, unit: my_servo}",
        "{name: head, unit: my_servo, parent: tail, connector: back, axis: yaw, levels_deg: [0]}",
    )
    _assert_rejected(project, text, "no root unit")


def test_duplicate_names(project):
    text = GOOD.replace("name: tail", "name: head")
    _assert_rejected(project, text, "units[1].name: duplicate unit name 'head'", line=6)


def test_duplicate_yaml_keys(project):
    text = GOOD.replace("light: {distance_m: 3}", "light: {distance_m: 3}\nlight: {distance_m: 4}")
    _assert_rejected(project, text, "light: duplicate key", line=3)


def test_levels_outside_limits(project):
    text = GOOD.replace("levels_deg: [-10, 10]", "levels_deg: [-10, 100]")
    _assert_rejected(project, text, "level 100 deg is outside the joint limits [-90, 90]", line=6)


def test_missing_unit_type(project):
    text = GOOD.replace("name: tail, unit: my_servo", "name: tail, unit: gearbox")
    _assert_rejected(project, text, "units[1].unit: unknown unit type 'gearbox'", line=6)


def test_zero_mass(project):
    unit = project / "units" / "my_servo" / "unit.yaml"
    unit.write_text(unit.read_text().replace("mass_kg: 0.15", "mass_kg: 0"))
    message = _assert_rejected(project, GOOD, "mass_kg: must be in (0, 100], got 0")
    assert "units/my_servo/unit.yaml:" in message


def test_negative_size(project):
    template = project / "units" / "my_servo" / "link.urdf"
    text = template.read_text().replace(
        '<box size="0.1 0.05 0.05"/>', '<box size="0.1 -0.05 0.05"/>'
    )
    template.write_text(text)
    message = _assert_rejected(project, GOOD, "box size must be in (0, 10]")
    assert "units/my_servo/link.urdf" in message


def test_zero_light_distance(project):
    _assert_rejected(
        project, GOOD.replace("distance_m: 3", "distance_m: 0"), "must be in (0, 10000]"
    )


def test_mesh_path_escaping_the_project(project):
    template = project / "units" / "my_servo" / "link.urdf"
    escaping = '<mesh filename="../../../outside.stl"/>'
    text = template.read_text().replace('<box size="0.096 0.05 0.05"/>', escaping)
    template.write_text(text)
    (project.parent / "outside.stl").write_text("solid x\nendsolid x\n")
    _assert_rejected(project, GOOD, "mesh path escapes the project folder")


def test_mesh_inside_the_unit_folder_is_copied_next_to_the_urdf(project, tmp_path):
    import trimesh

    folder = project / "units" / "my_servo"
    (folder / "meshes").mkdir()
    trimesh.creation.box(extents=(0.096, 0.05, 0.05)).export(folder / "meshes" / "housing.stl")
    template = folder / "link.urdf"
    text = template.read_text().replace(
        '<box size="0.096 0.05 0.05"/>', '<mesh filename="meshes/housing.stl"/>'
    )
    template.write_text(text)
    file = project / "assemblies" / "robot.yaml"
    file.write_text(GOOD)
    out = tmp_path / "built" / "robot.urdf"
    result = run_cli("assemble", file, "-o", out, cwd=project)
    assert result.returncode == 0, result.stderr
    assert (out.parent / "assets" / "my_servo" / "meshes" / "housing.stl").is_file()
    assert 'filename="assets/my_servo/meshes/housing.stl"' in out.read_text()


def test_output_flag_takes_one_formation(tmp_path):
    result = run_cli("assemble", *SHIPPED_FORMATIONS[:2], "-o", tmp_path / "x.urdf")
    assert result.returncode == 2
    assert "use --out-dir" in result.stderr
    assert textwrap.dedent(result.stderr).count("\n") == 1
