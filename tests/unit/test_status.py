"""One status table for contact and optimization (alcontact.status.Status).

The old member names of both enums keep working, the same failure has the same code
in both, the contact codes recorded in results folders are unchanged, labels are
unchanged, and the inner solvers' reason strings map onto the table.

Reaches inside the package: builds ``optim._inner.InnerResult`` to map every inner solver reason
onto the status table (no public constructor).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact import errors, status
from alcontact.contact import ContactStatus
from alcontact.optim import Status as OptimStatus
from alcontact.optim import minimize
from alcontact.optim._inner import InnerResult
from alcontact.runner import _ADVICE, what_to_try
from alcontact.status import INNER_REASONS, Status

#: Codes of the former ContactStatus, written to summary.json as ``status_code``.
CONTACT_CODES = {"CONVERGED": 1, "NO_CONTACT": -1, "MAXITER": -2, "NEWTON_FAILED": -3, "NONFINITE": -4,
                 "PENALTY_LIMIT": -5}
#: Members of the former optim Status, with the sign of their code.
OPTIM_SIGNS = {"CONVERGED_KKT": 1, "UNCONSTRAINED_CONVERGED": 1, "MAXITER": -1, "INNER_FAILED": -1,
               "NONFINITE": -1, "PENALTY_LIMIT": -1, "UNBOUNDED": -1}
#: Contact and optim names of the same outcome.
SAME = [("CONVERGED", "CONVERGED_KKT"), ("NEWTON_FAILED", "INNER_FAILED"), ("MAXITER", "MAXITER"),
        ("NONFINITE", "NONFINITE"), ("PENALTY_LIMIT", "PENALTY_LIMIT")]


def test_one_enum():
    assert ContactStatus is Status and OptimStatus is Status


def test_contact_codes_unchanged():
    for name, code in CONTACT_CODES.items():
        assert int(ContactStatus[name]) == code


def test_optim_names_keep_their_sign():
    for name, sign in OPTIM_SIGNS.items():
        assert np.sign(int(OptimStatus[name])) == sign


@pytest.mark.parametrize("contact_name, optim_name", SAME)
def test_same_failure_same_code(contact_name, optim_name):
    assert ContactStatus[contact_name] is OptimStatus[optim_name]


def test_distinct_outcomes_distinct_codes():
    canonical = list(Status)
    assert len({int(s) for s in canonical}) == len(canonical)
    assert {s.name for s in canonical} >= {"NO_CONTACT", "UNBOUNDED", "UNCONSTRAINED_CONVERGED"}


def test_every_member_is_in_the_documented_table():
    doc = status.__doc__
    for name, member in Status.__members__.items():
        row = next((line for line in doc.splitlines() if line.split() and line.split()[0] == member.name), None)
        assert row is not None, member.name
        assert str(int(member)) in row.split(), (name, row)
        if name != member.name:  # an alias is listed in its canonical row
            assert f"({name})" in row or f"{name})" in row, (name, row)


def test_labels():
    """Positive codes are "converged"; failures are the kebab-case name, as before the merge;
    every contact failure label has its own advice in the runner."""
    assert {s.label for s in Status if s > 0} == {"converged"}
    expected = {"NO_CONTACT": "no-contact", "MAXITER": "maxiter", "NEWTON_FAILED": "newton-failed",
                "NONFINITE": "nonfinite", "PENALTY_LIMIT": "penalty-limit"}
    for name, label in expected.items():
        assert ContactStatus[name].label == label
        assert label in _ADVICE and what_to_try(ContactStatus[name]) == _ADVICE[label]
    assert what_to_try(ContactStatus.CONVERGED) == ""
    assert Status.CONVERGED.success and not Status.MAXITER.success


@pytest.mark.parametrize("reason", sorted(INNER_REASONS) + ["something-new"])
def test_inner_reasons_map_onto_the_table(reason):
    res = InnerResult(np.zeros(1), 0.0, 1, reason, 0.0)
    assert res.code is Status.from_inner(reason)
    assert res.ok == (reason in ("converged", "small-step"))  # the inner solvers' accepted reasons
    if reason == "something-new":
        assert res.code is Status.NEWTON_FAILED


def test_optim_failure_uses_the_shared_code_and_raises():
    """A run stopped by maxiter=1 reports the table's MAXITER (the code contact uses too)."""
    from scipy.optimize import NonlinearConstraint

    con = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0)
    res = minimize(lambda x: x @ x, [1.0, 2.0], jac=lambda x: 2 * x, hess=lambda x: 2 * np.eye(2),
                   constraints=con, options={"maxiter": 1})
    assert res.status is ContactStatus.MAXITER and int(res.status) == CONTACT_CODES["MAXITER"]
    assert res.status.label == "maxiter" and not res.success
    with pytest.raises(errors.ConvergenceError, match="MAXITER"):
        res.raise_for_status()
