"""The assembler's own URDF checks, each made to fail on a crafted URDF."""

import re

import pytest

from qdsega.assembly import assemble
from qdsega.assembly.urdf_checks import check_urdf
from qdsega.description import load_formation
from qdsega.errors import FormationError


@pytest.fixture(scope="module")
def snake():
    formation = load_formation("assemblies/snake5.yaml")
    return formation, assemble(formation).urdf


def test_the_shipped_urdf_passes(snake):
    formation, urdf = snake
    check_urdf(urdf, formation)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('<link name="u3">', '<link name="u2">', "duplicate link/joint name 'u2'"),
        ('<joint name="u3_joint"', '<joint name="u2"', "duplicate link/joint name 'u2'"),
        ('<parent link="u2" />', '<parent link="ghost" />', "unknown parent link 'ghost'"),
        ('<child link="u3" />', '<child link="u4" />', "link 'u4' has two parent joints"),
        ('<child link="u2" />', '<child link="u1" />', "cycle through link 'u1'"),
        ('<mass value="0.15" />', '<mass value="0" />', "mass must be positive"),
        ('ixx="6.25e-05"', 'ixx="-6.25e-05"', "not positive definite"),
        ('ixx="6.25e-05"', 'ixx="0.01"', "triangle inequality"),
        ('lower="-1.57079633"', 'lower="2"', "limits not ordered"),
        ('effort="2.5"', 'effort="0"', "effort limit must be positive"),
        ('<parent link="u2" />', "", "joint 'u3_joint' has no <parent>"),
        ('<child link="u3" />', '<child name="u3" />', "joint 'u3_joint': <child> has no 'link'"),
        ('<mass value="0.15" />', "", "link 'u1' has no <mass>"),
        ('ixx="6.25e-05"', "", "link 'u1': <inertia> has no 'ixx'"),
        ('lower="-1.57079633"', "", "joint 'u2_joint': level -20 deg outside limits"),
    ],
)
def test_each_check_fails_on_a_crafted_urdf(snake, old, new, message):
    formation, urdf = snake
    assert old in urdf
    with pytest.raises(FormationError, match=re.escape(message)):
        check_urdf(urdf.replace(old, new, 1), formation)


def test_a_cycle_is_found(snake):
    formation, urdf = snake
    # u1 becomes a child of u5: every link has a parent, so there is no root at all.
    cyclic = urdf.replace(
        "</robot>",
        '<joint name="loop" type="fixed"><parent link="u5" /><child link="u1" /></joint></robot>',
    )
    with pytest.raises(FormationError, match="exactly one root link"):
        check_urdf(cyclic, formation)
    # A detached loop beside a valid tree: u4 -> u5 -> u4.
    detached = urdf.replace(
        '<parent link="u3" />\n    <child link="u4" />',
        '<parent link="u5" />\n    <child link="u4" />',
    )
    with pytest.raises(FormationError, match="cycle through link"):
        check_urdf(detached, formation)


def test_levels_outside_the_urdf_limits_are_found(snake):
    formation, urdf = snake
    narrowed = urdf.replace('upper="1.57079633"', 'upper="0.1"')
    with pytest.raises(FormationError, match="level 10 deg outside limits"):
        check_urdf(narrowed, formation)
