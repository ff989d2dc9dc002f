import xml.etree.ElementTree as ET

import numpy as np
import pytest

from qdsega.assembly.mass_properties import link_mass_properties
from qdsega.errors import FormationError


def _link(collisions: str) -> ET.Element:
    return ET.fromstring(f'<link name="x">{collisions}</link>')


def test_box_inertia_matches_the_closed_form(tmp_path):
    link = _link(
        '<collision><origin xyz="-0.05 0 0"/><geometry><box size="0.1 0.05 0.04"/></geometry>'
        "</collision>"
    )
    props = link_mass_properties(link, 0.2, folder=tmp_path)
    a, b, c = 0.1, 0.05, 0.04
    expected = 0.2 / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    assert props.mass_kg == pytest.approx(0.2)
    assert props.center_of_mass_m == pytest.approx([-0.05, 0.0, 0.0])
    assert props.inertia_kg_m2 == pytest.approx(expected, rel=1e-9, abs=1e-15)


def test_two_shapes_share_the_mass_by_volume(tmp_path):
    box = '<geometry><box size="0.1 0.1 0.1"/></geometry>'
    link = _link(
        f'<collision><origin xyz="0 0 0"/>{box}</collision>'
        f'<collision><origin xyz="0.3 0 0"/>{box}</collision>'
    )
    props = link_mass_properties(link, 1.0, folder=tmp_path)
    assert props.center_of_mass_m == pytest.approx([0.15, 0.0, 0.0])
    # Parallel axes: two 0.5 kg cubes 0.15 m from the centre of mass.
    assert props.inertia_kg_m2[1, 1] == pytest.approx(2 * (0.5 * 0.02 / 12 + 0.5 * 0.15**2))


def test_cylinder_inertia_is_close_to_the_closed_form(tmp_path):
    link = _link(
        '<collision><geometry><cylinder radius="0.02" length="0.1"/></geometry></collision>'
    )
    props = link_mass_properties(link, 0.3, folder=tmp_path)
    r, h = 0.02, 0.1
    assert props.inertia_kg_m2[2, 2] == pytest.approx(0.3 * r * r / 2, rel=0.02)
    assert props.inertia_kg_m2[0, 0] == pytest.approx(0.3 * (3 * r * r + h * h) / 12, rel=0.02)


@pytest.mark.parametrize(
    "geometry",
    [
        '<box size="0.1 0 0.1"/>',
        '<box size="0.1 0.1"/>',
        '<sphere radius="-1"/>',
        "<capsule/>",
        '<box size="0.1 nan 0.1"/>',
        '<box size="0.1 inf 0.1"/>',
        '<sphere radius="1e9"/>',
        '<cylinder radius="0.02" length="11"/>',
    ],
)
def test_bad_geometry_is_rejected(tmp_path, geometry):
    with pytest.raises(FormationError):
        link_mass_properties(
            _link(f"<collision><geometry>{geometry}</geometry></collision>"), 1.0, folder=tmp_path
        )


@pytest.mark.parametrize("origin", ['xyz="nan 0 0"', 'xyz="0 0 1e6"', 'rpy="0 inf 0"'])
def test_unbounded_origins_are_rejected(tmp_path, origin):
    collision = f'<collision><origin {origin}/><geometry><box size="1 1 1"/></geometry></collision>'
    with pytest.raises(FormationError, match="must be in"):
        link_mass_properties(_link(collision), 1.0, folder=tmp_path)
