r"""Finite-deformation contact kinematics: consistent linearization and moving obstacles.

References: the tangent :math:`J = \partial R/\partial x` of
:class:`~alcontact.contact.systems._full_space.FiniteContact` (body tangent, contact stiffness and the
curvature term :math:`\sum_i w_i t_{N,i} \nabla^2 g_i`) equals the central finite
difference of the residual to 1e-6 relative (the difference error is
:math:`O(h^2)`, about 1e-8 here); a translated obstacle has the gap, normal, projection
and Hessian of the original at the shifted point (exact, to round-off 1e-14).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact import penalties
from alcontact.contact import ContactProblem, Support, obstacles
from alcontact.contact.systems import FiniteContact
from alcontact.contact.laws import make_law
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic


@pytest.mark.parametrize("obstacle", [
    obstacles.Circle(center=(0.5, 1.35), radius=0.4),
    obstacles.Circle(center=(0.5, -0.5), radius=2.0, inside=False),
    obstacles.HalfSpace([0.0, 0.9], [0.2, -1.0]),
])
def test_tangent_matches_finite_differences(obstacle):
    """Directional derivative of R equals J v within 1e-6 relative (module doc)."""
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    body = Hyperelastic(mesh, Material(E=100.0, nu=0.3, plane="strain"))
    problem = ContactProblem(body, obstacle, "top", supports=(Support("bottom"),), kinematics="finite")
    dc = FiniteContact(problem)
    rng = np.random.default_rng(0)
    x = 0.03 * rng.standard_normal(dc.free.size)
    dc.cand = np.flatnonzero(dc.movable)  # every point of the boundary
    law = make_law(penalties.make("rockafellar"), np.full(dc.cand.size, 0.04))
    lam = np.full(dc.cand.size, 10.0)  # all points loaded: every curvature term counts
    g = dc.gaps(x)
    assert np.all(law.traction(g, lam) > 0)
    v = rng.standard_normal(dc.free.size)
    h = 1e-6
    fd = (dc.residual(law, lam, x + h * v) - dc.residual(law, lam, x - h * v)) / (2 * h)
    Jv = dc.jacobian(law, lam, x) @ v
    assert np.linalg.norm(fd - Jv) <= 1e-6 * np.linalg.norm(Jv)


def test_translated_obstacle_is_the_shifted_original():
    """gap, normal, projection and Hessian of translate(ob, c) at x are those of ob at x - c (1e-14)."""
    base = obstacles.Circle(center=(0.0, 1.0), radius=0.5)
    c = np.array([0.3, -0.2])
    moved = obstacles.translate(obstacles.translate(base, [0.1, 0.0]), [0.2, -0.2])
    x = np.random.default_rng(1).uniform(-1, 2, size=(20, 2))
    g0, n0 = base.evaluate(x - c)
    g1, n1 = moved.evaluate(x)
    assert np.allclose(g1, g0, atol=1e-14, rtol=0) and np.allclose(n1, n0, atol=1e-14, rtol=0)
    assert np.allclose(moved.project(x), base.project(x - c) + c, atol=1e-14, rtol=0)
    assert np.allclose(moved.gap_hessian(x), base.gap_hessian(x - c), atol=1e-14, rtol=0)
    assert isinstance(moved, obstacles.Translated) and moved.base is base
    with pytest.raises(Exception, match="offset"):
        obstacles.translate(base, [1.0, 2.0, 3.0])


def test_bad_step_input_names_the_way_out():
    """Wrong obstacle path, step times or cut-back count: InputError naming the parameter."""
    from alcontact.contact import solve_finite
    from alcontact.errors import InputError

    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2)
    body = Hyperelastic(mesh, Material(E=100.0, nu=0.3, plane="strain"))
    problem = ContactProblem(body, obstacles.HalfSpace([0.0, 0.0], [0.0, 1.0]), "bottom",
                             supports=(Support("left", (0,), 0.0), Support("top", (1,), -0.1)), kinematics="finite")
    with pytest.raises(InputError, match="obstacle_path"):
        solve_finite(problem, "ssn", steps=2, obstacle_path=lambda t: [0.0, 0.0, 1.0])
    with pytest.raises(InputError, match="step times"):
        solve_finite(problem, "ssn", steps=[0.5, 0.25])
    with pytest.raises(InputError, match="max_cutbacks"):
        solve_finite(problem, "ssn", steps=2, max_cutbacks=-1)
