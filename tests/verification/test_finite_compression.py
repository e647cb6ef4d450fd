r"""Finite deformation: homogeneous compression of a neo-Hookean block on a rigid plane.

Reference (semi-analytical): frictionless contact on the plane and a free lateral
face leave the deformation homogeneous, :math:`F = \mathrm{diag}(a, \lambda_v)` in
plane strain (:math:`F_{33} = 1`) and :math:`F = \mathrm{diag}(a, a, \lambda_v)` in
3D, with the vertical stretch :math:`\lambda_v = 1 - 0.3` prescribed by the top
displacement (30 % strain) and the lateral stretch :math:`a` the root of
:math:`P_{11}(a) = 0` (1D root solve), where for the neo-Hookean law
:math:`P = \mu(F - F^{-T}) + \lambda \ln J\,F^{-T}`. The contact force is the nominal
vertical stress times the reference area, :math:`-P_{vv} A_0`. P1 elements represent
the homogeneous field exactly, so every algorithm must reproduce it to 1e-8
relative (the pure penalty with its penetration tolerance tightened to 1e-11 h,
since its force error is the residual penetration over the block height).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from alcontact.contact import ContactProblem, Support, contact_penalties, obstacles, solve, solve_finite
from alcontact.errors import InputError, UnknownNameError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic

STRAIN = 0.3
ALGORITHMS = ([("ssn", None, {}), ("simo-laursen", None, {}), ("penalty", None, {"tol_penetration": 1e-11})]
              + [("family-p", name, {}) for name in contact_penalties()])


def _reference_force(body, dim: int, area: float) -> float:
    lam, mu = body.lam, body.mu
    lv = 1.0 - STRAIN
    nl = dim - 1  # lateral stretches equal to a

    def p_lateral(a):
        J = a**nl * lv
        return mu * (a - 1 / a) + lam * np.log(J) / a

    a = brentq(p_lateral, 1.0, 3.0, xtol=1e-15, rtol=1e-15)
    J = a**nl * lv
    return -(mu * (lv - 1 / lv) + lam * np.log(J) / lv) * area


def _block(dim: int):
    if dim == 2:
        mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 3, 3)
        supports = (Support("left", (0,), 0.0), Support("top", (1,), -STRAIN))
        plane = obstacles.HalfSpace([0.0, 0.0], [0.0, 1.0])
        bottom = "bottom"
    else:
        mesh = meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 2, 2, 2)
        supports = (Support("left", (0,), 0.0), Support("front", (1,), 0.0), Support("top", (2,), -STRAIN))
        plane = obstacles.HalfSpace([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        bottom = "bottom"
    body = Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain"))
    return ContactProblem(body, plane, bottom, supports=supports, kinematics="finite"), body


CASES = [(2, *a) for a in ALGORITHMS] + [(3, *a) for a in ALGORITHMS if a[1] in (None, "exp-met1", "log-met2")]


@pytest.mark.parametrize("dim,algorithm,penalty,extra", CASES)
def test_homogeneous_compression_force(dim, algorithm, penalty, extra):
    """Contact force = semi-analytical homogeneous solution within 1e-8 relative (module doc)."""
    problem, body = _block(dim)
    ref = _reference_force(body, dim, 1.0)
    sol = solve(problem, algorithm, penalty, steps=4, **extra)
    assert sol.status > 0, sol.result.message
    force = sol.total_contact_force[dim - 1]
    assert abs(force - ref) <= 1e-8 * ref
    # the lateral force vanishes (frictionless), and every load step was recorded
    assert abs(sol.total_contact_force[0]) <= 1e-8 * ref
    steps = sol.extra["load_steps"]
    assert len(steps) >= 4 and all(s.status > 0 for s in steps)
    assert np.isclose(steps[-1].t, 1.0)
    # global equilibrium (issue 12): contact force = reactions + loads, with the internal force f_int(u)
    eq = sol.equilibrium()
    assert eq.residual <= 1e-8 and eq.free_residual <= 1e-8, eq


def test_load_steps_are_monotone_and_analytical():
    """Each step's force equals the homogeneous solution at its strain (1e-8), ssn, plane strain."""
    problem, body = _block(2)
    fs = solve_finite(problem, "ssn", steps=5)
    assert fs.success
    lam, mu = body.lam, body.mu
    for s in fs.steps:
        lv = 1.0 - STRAIN * s.t
        a = brentq(lambda a: mu * (a - 1 / a) + lam * np.log(a * lv) / a, 1.0, 3.0, xtol=1e-15, rtol=1e-15)
        ref = -(mu * (lv - 1 / lv) + lam * np.log(a * lv) / lv)
        assert abs(s.force[1] - ref) <= 1e-8 * ref
    assert np.all(np.diff(fs.forces[:, 1]) > 0)


def test_finite_kinematics_needs_a_nonlinear_body():
    """A linear elastic body with kinematics='finite' is refused; unknown kinematics name the known ones."""
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2)
    lin = LinearElasticity(mesh, Material(E=1.0, nu=0.3))
    plane = obstacles.HalfSpace([0.0, 0.0], [0.0, 1.0])
    with pytest.raises(InputError, match="nonlinear body"):
        ContactProblem(lin, plane, "bottom", kinematics="finite")
    with pytest.raises(UnknownNameError, match="finite"):
        ContactProblem(lin, plane, "bottom", kinematics="large")


def test_cutback_recovers_a_failed_step():
    """A step too large for the Newton budget is halved until it converges (cut-back).

    60 % compression in one step with at most 4 Newton iterations per subproblem, every
    subproblem solved to ``newton_tol`` (the inexact subproblems of Algorithm 6.1 need
    fewer and pass this step whole): the full step fails, the halved increments succeed;
    reference: the homogeneous solution (1e-8 relative) at the end, with at least one
    recorded cut-back.
    """
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2)
    body = Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain"))
    strain = 0.6
    problem = ContactProblem(body, obstacles.HalfSpace([0.0, 0.0], [0.0, 1.0]), "bottom",
                             supports=(Support("left", (0,), 0.0), Support("top", (1,), -strain)),
                             kinematics="finite")
    fs = solve_finite(problem, "simo-laursen", steps=1, maxiter_newton=4, subproblems="exact")
    assert fs.success, fs.message
    assert sum(s.cutbacks for s in fs.steps) >= 1 and len(fs.steps) >= 2
    lv = 1.0 - strain
    lam, mu = body.lam, body.mu
    a = brentq(lambda a: mu * (a - 1 / a) + lam * np.log(a * lv) / a, 1.0, 5.0, xtol=1e-15, rtol=1e-15)
    ref = -(mu * (lv - 1 / lv) + lam * np.log(a * lv) / lv)
    assert np.isclose(fs.steps[-1].t, 1.0)
    assert abs(fs.steps[-1].force[1] - ref) <= 1e-8 * ref
    # too few cut-backs allowed: a negative status and the message says what to try
    bad = solve_finite(problem, "simo-laursen", steps=1, maxiter_newton=4, max_cutbacks=0, subproblems="exact")
    assert bad.status < 0 and "load steps" in bad.message


def test_load_history_drives_the_steps():
    """A LoadHistory ramping the top displacement gives the proportional-loading forces (1e-10 relative).

    Reference: :func:`solve_finite` without a history (every support scaled by t), whose
    forces equal the homogeneous solution (tested above); the symmetry support is held
    by the problem, the top displacement by a :class:`LoadCase` with a linear ramp.
    """
    from alcontact.contact import LoadCase, LoadHistory, Ramp

    problem, _ = _block(2)
    fs = solve_finite(problem, "ssn", steps=4)
    base = ContactProblem(problem.model, problem.obstacle, "bottom", supports=(Support("left", (0,), 0.0),),
                          kinematics="finite")
    hist = LoadHistory((LoadCase(Support("top", (1,), -STRAIN), Ramp((0.0, 1.0), (0.0, 1.0))),),
                       times=LoadHistory.uniform(4))
    fh = solve_finite(base, "ssn", steps=4, history=hist)
    assert fs.success and fh.success
    assert np.allclose(fh.forces, fs.forces, rtol=1e-10, atol=0.0)
