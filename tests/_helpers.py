"""Helpers shared by the test files: small problem builders, agreement checks, CLI plumbing.

``tests/`` is on ``sys.path`` (pytest puts the directory of ``tests/conftest.py`` there),
so a test file imports these as ``from _helpers import ...``. Each check states what it
compares and to which tolerance; the tolerance is the caller's (its docstring says why).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from typer.testing import CliRunner

from alcontact import penalties as P
from alcontact.contact import ContactProblem
from alcontact.contact.problem import LoadCase, LoadHistory, Ramp
from alcontact.contact.problem import Pressure, Traction
from alcontact.contact.obstacles import HalfSpace
from alcontact.fem import LinearElasticity, Material, meshes, rigid_body_modes

# ---------------------------------------------------------------------------- CLI
#: a CLI runner with lines wide enough that messages are not wrapped, and no colour codes
runner = CliRunner(env={"COLUMNS": "400", "NO_COLOR": "1"})


def flat(text: str) -> str:
    """``text`` with every run of white space (line breaks of the console) one blank."""
    return " ".join(text.split())


def assert_check_rejects(result, expected) -> None:
    """``alcontact check`` refused (exit code 2, no traceback, "nothing was solved") naming every text of
    ``expected`` on stderr."""
    msg = flat(result.stderr)
    assert result.exit_code == 2, result.output
    assert "nothing was solved" in msg and "Traceback" not in result.output
    for text in expected:
        assert text in msg, (text, msg)


# ---------------------------------------------------------------------------- problems
#: Coulomb coefficient and pressure of :func:`held_block`
HELD_MU, HELD_P = 0.3, 10.0


def held_block(dim: int, ratio: float, *, pressure: float = HELD_P, n: int = 4):
    """Block [-1, 1]^(d-1) x [0, 0.5] on the plane x_d = 0 with no support (held by the obstacle only).

    E = 1000, nu = 0 (plane strain in 2D); a pressure on the top (ramped over t in [0, 0.5],
    then held), then a tangential traction Q = ``ratio`` mu P along x (2D) or (x + y)/sqrt 2 (3D)
    ramped over t in [0.5, 1]; friction mu = 0.3, 4 uniform steps.

    Returns
    -------
    (problem, history, area, q)
        ``area`` the top area A, ``q`` the applied traction vector (the obstacle carries N = P A
        and the tangential force -q A while the body sticks).
    """
    if dim == 2:
        mesh = meshes.rectangle(-1.0, 1.0, 0.0, 0.5, n, 2)
        tdir, area = np.array([1.0, 0.0]), 2.0
    else:
        mesh = meshes.box(-1.0, 1.0, -1.0, 1.0, 0.0, 0.5, n, n, 2)
        tdir, area = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0), 4.0
    model = LinearElasticity(mesh, Material(E=1000.0, nu=0.0, plane="strain"))
    obstacle = HalfSpace(point=(0.0,) * dim, normal=tuple(np.eye(dim)[-1]))
    Q = ratio * HELD_MU * HELD_P
    press = LoadCase(Pressure("top", pressure), Ramp((0.0, 0.5), (0.0, 1.0), hold_after=True), name="pressure")
    shear = LoadCase(Traction("top", tuple((Q * tdir).tolist())), Ramp((0.5, 1.0), (0.0, 1.0)), tangential=True,
                     name="shear")
    prob = ContactProblem(model=model, obstacle=obstacle, contact_boundary="bottom", supports=(), friction=HELD_MU)
    return prob, LoadHistory((press, shear), LoadHistory.uniform(4)), area, Q * tdir


_HELD_BLOCK_TOML = """
[problem]
name = "{name}"
[mesh]
generator = "{generator}"
bounds = {bounds}
cells = {cells}
[material]
E = 1000.0
nu = 0.0
[[load]]
type = "pressure"
boundary = "top"
value = 10.0
ramp = [[0.0, 0.0], [0.5, 1.0], [1.0, 1.0]]
[[load]]
type = "traction"
boundary = "top"
vector = {vector}
ramp = [[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]]
tangential = true
[loading]
steps = 4
[obstacle]
type = "half-space"
point = {point}
normal = {normal}
[contact]
boundary = "bottom"
friction = 0.3
"""


def held_block_toml(dim: int, q: float) -> str:
    """:func:`held_block` (n = 4) as a problem file, with the traction vector [q, 0] (2D) or [q, q, 0] (3D)."""
    if dim == 2:
        return _HELD_BLOCK_TOML.format(name="held-by-friction", generator="rectangle", bounds="[-1.0, 1.0, 0.0, 0.5]",
                                       cells="[4, 2]", vector=f"[{q}, 0.0]", point="[0.0, 0.0]",
                                       normal="[0.0, 1.0]")
    return _HELD_BLOCK_TOML.format(name="held-by-friction-3d", generator="box",
                                   bounds="[-1.0, 1.0, -1.0, 1.0, 0.0, 0.5]", cells="[4, 4, 2]",
                                   vector=f"[{q}, {q}, 0.0]", point="[0.0, 0.0, 0.0]", normal="[0.0, 0.0, 1.0]")


# ---------------------------------------------------------------------------- penalties, objectives
@dataclass(frozen=True)
class Softplus(P.PenaltyBase):
    """User penalty p = 2 mu (log(1 + e^y) - log 2): (P1),(P2),(P3),(P5) but bounded p'."""

    name: str = "user-softplus"
    doc: str = "user softplus penalty"
    properties: ClassVar[frozenset[str]] = frozenset({"P1", "P2", "P3", "P5"})

    def _p(self, y, mu):
        return 2.0 * mu * (np.logaddexp(0.0, y) - math.log(2.0))

    def _dp(self, y, mu):
        return 2.0 * mu / (1.0 + np.exp(-y))

    def _d2p(self, y, mu):
        s = 1.0 / (1.0 + np.exp(-y))
        return 2.0 * mu * s * (1.0 - s)


#: the penalties of :func:`user_penalties`: family-P methods of the user generator "frac", and Softplus
USER_PENALTIES = ("frac-met1", "frac-met2", "user-softplus")


@contextlib.contextmanager
def user_penalties(theta: P.Theta) -> Iterator[None]:
    """Register the user generator ``theta`` as "frac" and :class:`Softplus` as "user-softplus" while the
    block runs; always unregister them."""
    P.register_theta("frac", theta)
    P.register("user-softplus", Softplus, doc="user softplus penalty")
    try:
        yield
    finally:
        P.unregister_theta("frac")
        P.unregister("user-softplus")


def sq(x):
    """f(x) = |x|^2 (minimum 0 at x = 0)."""
    return float(x @ x)


def sq_grad(x):
    """Gradient 2 x of :func:`sq`."""
    return 2.0 * x


def sq_hess(x):
    """Hessian 2 I of :func:`sq`."""
    return 2.0 * np.eye(x.size)


# ---------------------------------------------------------------------------- agreement checks
def assert_rigid_modes_in_kernel(model, K) -> None:
    """Every rigid-body mode r of ``model`` satisfies max|K r| < 1e-10 max|K| (the stiffness does not
    see rigid motions)."""
    pts, dofs = model.all_node_dofs()
    modes, _ = rigid_body_modes(pts)
    for j in range(modes.shape[-1]):
        r = np.zeros(model.ndofs)
        r[dofs.ravel()] = modes[:, :, j].ravel()
        assert np.abs(K @ r).max() < 1e-10 * abs(K).max()


def assert_same_contact_solution(sol, ref, rtol: float) -> None:
    """Two frictionless solutions of the same discrete problem: displacements and total contact force
    within ``rtol`` of the reference's largest, the same number of outer iterations."""
    assert sol.result.success and ref.result.success, sol.result.message
    du = np.max(np.abs(sol.u - ref.u)) / np.max(np.abs(ref.u))
    f_ref = np.max(np.abs(ref.total_contact_force))
    df = np.max(np.abs(sol.total_contact_force - ref.total_contact_force)) / f_ref
    assert du <= rtol
    assert df <= rtol
    assert sol.result.outer_iterations == ref.result.outer_iterations


def assert_same_friction_steps(sol, ref, tol: float, *, displacements: bool = False) -> None:
    """Two frictional solutions of the same discrete problem, step by step: the same number of steps,
    pressures and tangential tractions within ``tol`` of the step's largest pressure (with
    ``displacements``, u within ``tol`` of the largest displacement too), and the same open / stick /
    slip state at every point."""
    assert len(sol.steps) == len(ref.steps)
    for s, r in zip(sol.steps, ref.steps):
        pref = float(np.max(r.pressure))
        if displacements:
            assert np.max(np.abs(s.u - r.u)) <= tol * np.max(np.abs(r.u)), r.t
        assert np.max(np.abs(s.pressure - r.pressure)) <= tol * pref, r.t
        assert np.max(np.abs(s.traction_t - r.traction_t)) <= tol * pref, r.t
        np.testing.assert_array_equal(s.state, r.state)


def assert_same_finite_solution(sol, ref, rtol: float) -> None:
    """Two finite-kinematics solutions at the same times: reaction forces and displacements within
    ``rtol`` of the reference's largest."""
    assert np.allclose(sol.times, ref.times)
    assert np.max(np.abs(sol.forces - ref.forces)) <= rtol * np.max(np.abs(ref.forces))
    assert np.max(np.abs(sol.u - ref.u)) <= rtol * np.max(np.abs(ref.u))


def assert_quadratic_pairs(pairs) -> None:
    """Terminal Newton pairs (e_k, e_k+1): at least two, e_k+1 <= 1e3 e_k^2 and order
    log e_k+1 / log e_k >= 1.5 (quadratic convergence)."""
    assert len(pairs) >= 2
    ratios = [b / a**2 for a, b in pairs]
    assert max(ratios) <= 1e3, ratios
    orders = [np.log(b) / np.log(a) for a, b in pairs]
    assert min(orders) >= 1.5, orders
