"""Finite-deformation friction runs on the one AL loop of the small-deformation solvers.

* The registry's finite ``simo-laursen`` / ``family-p`` entries run
  :func:`alcontact.contact.algorithms._coulomb._step_al` itself, on the step's system
  :class:`~alcontact.contact.algorithms._coulomb._FiniteALCtx`.
* The stopping test of that loop (:func:`~alcontact.contact.algorithms._coulomb._measures`) reads the
  finite state through ``_Local.aux``; on a real finite subproblem it gives the definitions
  of the finite stopping test exactly: penetration ``max g / h``, complementarity
  ``max |t_N min(g, 0)| / (p_ref h)``, multiplier change ``max(|t_N - lamN|, |t_T - lamT|) / p_ref``
  and the slip of the sticking points ``max |slip| / h`` (``p_ref = max t_N``).
* The declared differences of a system act as documented: ``full_predictor`` (both
  multipliers from the family-P predictor, counted as an outer iteration) and a failed
  subproblem without a state (an inverted element at the start) is a reported failure.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
import pytest

from alcontact import penalties as P
from alcontact.contact import ContactProblem, FrictionOptions, Support, obstacles
from alcontact.contact.algorithms import _coulomb as F
from alcontact.contact.algorithms import _frictionless as A
from alcontact.contact.systems import _full_space as FF
from alcontact.contact.laws import SLIP, STICK
from alcontact.contact.laws import eta_for_stiffness, make_law
from alcontact.optim import NewtonResult
from alcontact.contact.solution import ContactStatus
from alcontact.contact.stepping._steps import _StepData
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.status import Status


def test_finite_al_entries_run_the_one_friction_loop():
    """Same function object for both kinematics; the reference keeps its own step."""
    for name in ("simo-laursen", "family-p"):
        small = A.find_algorithm(name, friction=True, kinematics="small").run
        finite = A.find_algorithm(name, friction=True, kinematics="finite").run
        assert small is F._step_al and finite is F._step_al
    assert A.find_algorithm("ssn", friction=True, kinematics="finite").run is F._step_ssn_finite
    assert not hasattr(FF, "_measures") and not hasattr(FF, "_StepResult")


def _pressed_block_ctx():
    """A 4 x 4 neo-Hookean block pressed 10 % onto a plane moved sideways by 0.004: a finite step's system."""
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    problem = ContactProblem(Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain")),
                             obstacles.HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0)), "bottom",
                             supports=(Support("top"),), kinematics="finite")
    data = _StepData(problem, None, lambda t: np.array([0.004, 0.1]) * t)
    dc = FF.FiniteFrictionContact(problem, fixed=data.fixed)
    m, d = dc.points.shape
    x0 = np.zeros(dc.free.size)
    dc.configure(*data(0.0), x0)
    dc.accept(np.zeros(m))
    dc.place()
    y_prev = dc.surface_points(dc.expand(x0))
    eps_n = 1e4
    dc.configure(*data(1.0), x0, predictor_stiffness=eps_n)
    dc.set_history(y_prev, 0.3, eps_n, "multiplier")
    c = dc.cand.size
    opts = A.options_with(None, FrictionOptions, {}, "friction",
                          A.find_algorithm("simo-laursen", friction=True, kinematics="finite"))
    return F._FiniteALCtx(dc, np.full(c, 100.0), np.zeros((c, d)), dc.x0, eps_n, opts)


def test_measures_read_the_finite_state_by_its_definitions():
    """Module doc, second point: the shared measures equal the finite definitions (exactly)."""
    ctx = _pressed_block_ctx()
    law = make_law(P.make("rockafellar"), np.full(ctx.c, 1.0 / ctx.eps_n))
    out = ctx.subproblem(law, ctx.lamN, ctx.lamT, ctx.start)
    assert out.converged, out.message
    loc = out.state
    assert np.any(loc.tN > 0) and np.any(loc.state == STICK) and np.any(np.linalg.norm(loc.tT, axis=1) > 0)
    y, t, _, st = loc.aux
    got = F._measures(ctx, t, y, st, ctx.lamN, ctx.lamT)
    h, pref = ctx.fc.h, float(np.max(loc.tN))
    want = (float(np.max(loc.g)) / h, float(np.max(np.abs(loc.tN * np.minimum(loc.g, 0.0)))) / (pref * h),
            max(float(np.max(np.abs(loc.tN - ctx.lamN))), float(np.max(np.abs(loc.tT - ctx.lamT)))) / pref,
            float(np.max(np.linalg.norm(loc.slip, axis=1)[loc.state == STICK], initial=0.0)) / h)
    assert got == want
    # the force of the obstacle on the body: w (t_N nu - t_T), summing to the reaction's resultant
    R = ctx.forces(out.x, t)
    w = ctx.fc.weights[ctx.fc.cand]
    assert np.allclose(R, w[:, None] * (loc.tN[:, None] * loc.nu - loc.tT), rtol=1e-12, atol=0.0)


@dataclass
class _Stub:
    """An _ALSystem whose subproblem returns fixed tractions ``target`` (or fails without a state)."""

    target: np.ndarray  # (c, 1 + k)
    full_predictor: bool
    fail: bool = False
    calls: list = field(default_factory=list)

    label = "stub AL"
    second_order = False
    final_coupled = False
    eps_n = 1e3
    mu = 0.5
    tfree = None

    def __post_init__(self):
        c, n = self.target.shape
        self.fc = SimpleNamespace(h=0.1, spring=None)
        self.lamN, self.lamT, self.uTn = np.zeros(c), np.zeros((c, n - 1)), np.zeros((c, n - 1))
        self.opts = FrictionOptions()

    c = property(lambda self: self.target.shape[0])
    d = property(lambda self: self.target.shape[1])
    start = property(lambda self: np.zeros(3))

    def subproblem(self, law, lamN, lamT, z, coupled=False):
        self.calls.append((lamN.copy(), lamT.copy()))
        if self.fail:
            return NewtonResult(z, None, Status.NEWTON_FAILED, "inverted element at the starting state", 0, np.inf)
        y = np.zeros((self.c, self.d))  # closed, no slip
        aux = (y, self.target.copy(), None, np.full(self.c, SLIP))
        return NewtonResult(z + 1.0, SimpleNamespace(aux=aux), Status.CONVERGED, "converged", 2, 0.0)

    def iterate(self, out):
        return out.x

    def inside_domain(self, law, lamN, z):
        return z

    def forces(self, z, t):
        return t[:, :-1]


@pytest.mark.parametrize("full", [True, False])
def test_full_predictor_takes_both_multipliers_and_counts(full):
    """family-P, first order: with ``full_predictor`` the predictor's t_T starts the iterations and it is an
    outer iteration (2 subproblems, outer 1 + 1); without, t_T comes one iteration later (3 subproblems,
    outer 0 + 2)."""
    target = np.array([[2.0, 0.5, -0.25], [1.0, 0.0, 0.5]])
    ctx = _Stub(target, full)
    out = F._step_al(ctx, "exp-met1")
    assert out.ok and out.status == ContactStatus.CONVERGED
    assert out.outer == 2
    assert len(ctx.calls) == (2 if full else 3)
    assert np.array_equal(ctx.calls[1][1], target[:, 1:] if full else np.zeros((2, 2)))
    assert np.array_equal(out.t, target) and out.last_state.aux[1] is not None


def test_failed_subproblem_without_state_is_a_reported_failure():
    """An inverted element at the start leaves no state: NEWTON_FAILED, zero tractions, no exception."""
    ctx = _Stub(np.ones((2, 3)), True, fail=True)
    out = F._step_al(ctx, "rockafellar")
    assert not out.ok and out.status == ContactStatus.NEWTON_FAILED and out.status < 0
    assert "outer iteration 1" in out.message and out.last_state is None
    assert out.t.shape == (2, 3) and not np.any(out.t)


def test_inside_domain_moves_the_predictor_into_the_log_barrier_domain():
    """After the Simo-Laursen predictor from zero multipliers (first contact) the gaps lie at about the
    log-met1 bound eta b; the move puts every gap below 0.99 eta b, and leaves a start already inside (and a
    law without bound) unchanged."""
    ctx = _pressed_block_ctx()
    macaulay = make_law(P.make("rockafellar"), np.full(ctx.c, 1.0 / ctx.eps_n))
    pre = ctx.subproblem(macaulay, np.zeros(ctx.c), ctx.lamT, ctx.start)
    assert pre.converged, pre.message
    lamN = np.maximum(pre.state.tN, 1e-3 * np.max(pre.state.tN))
    pen = P.make("log-met1")
    law = make_law(pen, eta_for_stiffness(pen, lamN, ctx.eps_n))
    bound = law.gap_bound(lamN)
    assert np.any(ctx.fc.gaps(pre.x) >= 0.99 * bound)  # the predictor is outside: the move has work to do
    x = ctx.inside_domain(law, lamN, pre.x)
    assert np.all(ctx.fc.gaps(x) < 0.99 * bound)
    assert ctx.inside_domain(law, lamN, x) is x
    assert ctx.inside_domain(macaulay, lamN, pre.x) is pre.x
