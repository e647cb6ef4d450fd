"""What contact between bodies does not take yet is refused by name, before anything runs.

Two-body contact came in pieces: small-deformation mortar in 2D with Coulomb friction and several
pairs, 3D mortar (linear tetrahedra, frictionless), finite-deformation mortar in 2D (hyperelastic
P1 bodies, frictionless). Where the pieces do not overlap, a problem file or a ``ContactProblem``
must say so and name the key to change, never run a case no test covers: friction between 3D
bodies, finite deformation between 3D bodies, friction between bodies at finite deformation, and,
on the distributed path, pairs with different Coulomb coefficients.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from alcontact.app.distributed import refusal
from alcontact.errors import ConfigError
from alcontact.io.config import load_problem_text

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SPHERE = (EXAMPLES / "sphere_on_block.toml").read_text(encoding="utf-8")
SLAVE = 'boundary = "body1/bottom"  # the slave\nmaster = "body0/top"\n'


def _issue(text: str, key: str) -> str:
    with pytest.raises(ConfigError) as exc:
        load_problem_text(text, base_dir=EXAMPLES)
    message = str(exc.value)
    assert key in message, message
    return message


def test_the_3d_example_loads_as_shipped():
    """The base of the cases below is valid: only the changed key is refused."""
    setup = load_problem_text(SPHERE, base_dir=EXAMPLES)
    assert setup.problem.model.dim == 3 and setup.friction == 0.0


def test_friction_between_3d_bodies_is_refused():
    assert SLAVE in SPHERE
    message = _issue(SPHERE.replace(SLAVE, SLAVE + "friction = 0.3\n"), "contact.friction")
    assert "3D bodies" in message and "friction = 0.0" in message


def test_finite_deformation_between_3d_bodies_is_refused():
    message = _issue(SPHERE.replace(SLAVE, SLAVE + 'kinematics = "finite"\n'), "contact.kinematics")
    assert "3D bodies" in message and "kinematics = 'small'" in message


def test_friction_between_bodies_at_finite_deformation_is_refused_by_the_api():
    """``ContactProblem`` refuses it too (the Python API has no problem-file check in front of it)."""
    from alcontact.contact import BodySurface, Boundary, ContactPair, ContactProblem, Support
    from alcontact.errors import InputError
    from alcontact.fem import Hyperelastic, Material, meshes

    base = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1000.0, nu=0.3))
    top = Hyperelastic(meshes.rectangle(0, 1, 1, 2, 2, 2), Material(E=1000.0, nu=0.3))
    with pytest.raises(InputError, match="friction between two deformable bodies at kinematics='finite'"):
        ContactProblem(bodies=[base, top],
                       pairs=[ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"), friction=0.3)],
                       supports=[Support("body0/bottom"), Support("body1/top", value=[0.0, -0.1])],
                       kinematics="finite")


def test_distributed_path_refuses_pairs_with_different_coefficients():
    """The distributed path takes one coefficient for every pair (``problem.friction`` = the first pair's)."""
    one = SimpleNamespace(finite=False, pair_friction=[0.3, 0.3])
    two = SimpleNamespace(finite=False, pair_friction=[0.3, 0.1])
    assert refusal(one) is None
    message = refusal(two)
    assert message is not None and "mu = 0.1/0.3" in message and "same friction" in message
