"""Semi-smooth Newton on the AMG path: loose inner Uzawa solves for active sets that change.

``_equality_solve`` stops the inner Uzawa iteration at a relative multiplier update of
``_UZAWA_LOOSE`` when the outer active set is about to change; the set the outer iteration
accepts is still solved to ``_UZAWA_TOL``. Reference: the same solve with the early stop
switched off (``_UZAWA_LOOSE = 0``), every active set solved to ``_UZAWA_TOL`` (1e-8 relative
multiplier update). Tolerance: displacements and contact forces agree to 1e-6 relative (the
tolerance of the AMG path against the direct one in ``test_contact_iterative.py``), the
same outer iterations, and fewer CG solves.

Reaches inside the package: the Uzawa tolerance of the AMG reference
(``contact.systems._krylov._UZAWA_LOOSE``) is an internal constant, no option; the test sets it to
show what it guards.
"""

from __future__ import annotations

import pytest

from _helpers import assert_same_contact_solution
from alcontact.contact import solve
from alcontact.contact.systems import _krylov as _iterative
from alcontact.problems import blocks



@pytest.mark.parametrize("make", [lambda: blocks.signorini_block(n=8), lambda: blocks.patch_block(3, n=4)],
                         ids=["signorini-2d", "patch-3d"])
def test_loose_uzawa_same_solution_fewer_solves(make, monkeypatch):
    prob = make()
    loose = solve(prob, "ssn", linear_solver="amg")
    monkeypatch.setattr(_iterative, "_UZAWA_LOOSE", 0.0)
    tight = solve(prob, "ssn", linear_solver="amg")
    assert_same_contact_solution(loose, tight, 1e-6)
    assert loose.result.linear_solves <= tight.result.linear_solves
    if tight.result.outer_iterations > 1:  # an active set changed: its solve stopped early
        assert loose.result.linear_solves < tight.result.linear_solves
