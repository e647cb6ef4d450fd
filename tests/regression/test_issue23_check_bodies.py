"""Issue 23 (``alcontact check`` of several bodies): what is caught before any solve, with the key and the way out.

A block (body1) on a base (body0), two ``[[body]]`` tables with generated meshes, and a rigid
punch (``[obstacle] reference``). Each bad placement is one test: bodies that overlap by more
than an element (refused, naming the deepest slave point and the depth: here the geometry's
own 0.5), a small overlap (a warning), a body that nothing holds (refused, naming the body and
its free motion), a pair whose surfaces are beyond the search distance (a warning naming the
pair; the run then solves with the pair open), a master that faces away from the slave
(refused), and a force-driven rigid body away from the block or free to turn about its own
centre (refused, naming its free components). Never a traceback: every refusal is a
``ConfigError`` listing the issues.
"""

from __future__ import annotations

import logging

import pytest

from alcontact.errors import ConfigError
from alcontact.io.preflight import check_problem

TWO = """
[problem]
name = "block-on-base"

[[body]]
mesh = {{ generator = "rectangle", bounds = [0.0, 1.0, {b0}, {b1}], cells = [4, 4] }}
material = {{ E = 1000.0, nu = 0.3 }}
support = [{{ boundary = "bottom" }}]

[[body]]
mesh = {{ generator = "rectangle", bounds = [0.0, 1.0, {t0}, {t1}], cells = [3, 3] }}
material = {{ E = 500.0, nu = 0.3 }}
support = [{{ boundary = "left", components = [0] }}{more}]

[contact]
boundary = "body1/bottom"
master = "{master}"

[solver]
algorithm = "ssn"
"""


def _two(tmp_path, *, b=(0.0, 1.0), t=(1.0, 2.0), master="body0/top",
         more=', { boundary = "top", components = [1], value = -0.01 }'):
    path = tmp_path / "two.toml"
    path.write_text(TWO.format(b0=b[0], b1=b[1], t0=t[0], t1=t[1], master=master, more=more), encoding="utf-8")
    return path


def _refused(path) -> dict[str, str]:
    with pytest.raises(ConfigError) as exc:
        check_problem(path)
    return {i.path: i.message for i in exc.value.issues}


def test_touching_bodies_pass(tmp_path, caplog):
    with caplog.at_level(logging.WARNING):
        check_problem(_two(tmp_path))
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]


def test_bodies_overlapping_by_more_than_an_element_are_refused(tmp_path):
    issues = _refused(_two(tmp_path, t=(0.5, 1.5)))
    assert "overlap at the start" in issues["contact"], issues
    assert "lies 0.5 inside the master" in issues["contact"] and "move the bodies apart" in issues["contact"]


def test_a_small_overlap_is_a_warning(tmp_path, caplog):
    with caplog.at_level(logging.WARNING):
        check_problem(_two(tmp_path, t=(0.99, 1.99)))
    text = " ".join(r.getMessage() for r in caplog.records)
    assert "overlap at the start" in text and "lies 0.01 inside" in text and "interference fit" in text


def test_a_body_held_by_nothing_is_refused_with_its_motion(tmp_path):
    issues = _refused(_two(tmp_path, t=(1.5, 2.5), more=""))  # no vertical support, not touching the base
    assert "body[2]" in issues, issues
    assert "body 'body1' is held by nothing in u_y" in issues["body[2]"]
    assert "add a support on one of its boundaries" in issues["body[2]"]


def test_contact_holds_a_body_that_touches(tmp_path):
    check_problem(_two(tmp_path, more=""))  # no vertical support, but the block rests on the base


def test_a_pair_beyond_the_search_distance_is_a_warning_naming_it(tmp_path, caplog):
    with caplog.at_level(logging.WARNING):
        check_problem(_two(tmp_path, t=(5.0, 6.0)))
    text = " ".join(r.getMessage() for r in caplog.records)
    assert "'body1/bottom' on the boundary 'top'" in text and "cannot come into contact" in text


def test_a_master_facing_away_from_the_slave_is_refused(tmp_path):
    issues = _refused(_two(tmp_path, b=(0.8, 1.0), t=(1.0, 2.0), master="body0/bottom"))
    assert "face away" in issues["contact.master"], issues


PUNCH = """
[problem]
name = "punch"

[mesh]
generator = "rectangle"
bounds = [-2.0, 2.0, -2.0, 0.0]
cells = [8, 4]

[material]
E = 1000.0
nu = 0.3

[[support]]
boundary = "bottom"

[obstacle]
{shape}
reference = {ref}
force_y = -1.0

[contact]
boundary = "top"
"""
FLAT = 'type = "convex-polygon"\nvertices = [[-1.0, {y}], [1.0, {y}], [1.0, 2.0], [-1.0, 2.0]]'


def _punch(tmp_path, shape, ref):
    path = tmp_path / "punch.toml"
    path.write_text(PUNCH.format(shape=shape, ref=ref), encoding="utf-8")
    return path


def test_a_force_driven_rigid_body_away_from_the_block_is_refused(tmp_path):
    issues = _refused(_punch(tmp_path, FLAT.format(y=1.0), "[0.0, 1.0]"))
    assert "the rigid body 'body1' is held by nothing in u_y" in issues["obstacle"], issues


def test_a_resting_flat_punch_is_held_by_the_contact(tmp_path):
    check_problem(_punch(tmp_path, FLAT.format(y=0.0), "[0.0, 0.0]"))


def test_a_cylinder_free_to_turn_about_its_centre_is_refused(tmp_path):
    shape = 'type = "circle"\ncenter = [0.0, 1.0]\nradius = 1.0\nmoment = 0.0'
    issues = _refused(_punch(tmp_path, shape, "[0.0, 1.0]"))
    assert "held by nothing in rot_z" in issues["obstacle"], issues
