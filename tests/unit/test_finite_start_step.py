"""FiniteContact.start_multiplier_step: the dual step of Algorithm 6.3's start with tight iterative products."""

from __future__ import annotations

from types import SimpleNamespace

from alcontact.contact import _finite
from alcontact.contact._finite import FiniteContact


class _Model(SimpleNamespace):
    start_multiplier_step = FiniteContact.start_multiplier_step


def _model(dual: bool, solver):
    seen = []

    def multiplier_step(law, lam, out):
        seen.append(getattr(solver, "resolve_rtol", None))
        return ("lam", "x")

    return _Model(dual_penalty_start=dual, solver=solver, multiplier_step=multiplier_step), seen


def test_iterative_products_are_tightened_then_restored():
    """An AMG-type solver (``resolve_rtol`` 1e-2) solves the start's dual step to _START_RESOLVE_RTOL (1e-8)
    and gets its own tolerance back; the dual step's result is returned."""
    solver = SimpleNamespace(resolve_rtol=1e-2)
    model, seen = _model(True, solver)
    assert model.start_multiplier_step(None, None, None) == ("lam", "x")
    assert seen == [_finite._START_RESOLVE_RTOL] and _finite._START_RESOLVE_RTOL == 1e-8
    assert solver.resolve_rtol == 1e-2


def test_direct_solver_and_switch_off():
    """A direct solver (no ``resolve_rtol``) is used as it is; with dual_penalty_start off: None (no dual step)."""
    model, seen = _model(True, SimpleNamespace())
    assert model.start_multiplier_step(None, None, None) == ("lam", "x") and seen == [None]
    model, seen = _model(False, SimpleNamespace(resolve_rtol=1e-2))
    assert model.start_multiplier_step(None, None, None) is None and seen == []
