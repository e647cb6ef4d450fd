"""Issue 18: every example with every algorithm; a converged result satisfies every invariant it prints.

``summary.json`` / ``report.md`` print the equilibrium residuals (global balance and the largest
free-DOF residual, relative to the non-vanishing force scale of
:func:`alcontact.contact.solution._estimators.equilibrium`), the penetration and the complementarity of the
returned state. On a converged result each must be below its tolerance (the defaults; no example
sets them):

- penetration, complementarity: ``tol_penetration`` = ``tol_complementarity`` = 1e-8;
- equilibrium: ``newton_tol`` (1e-12) frictionless, raised to the measure's round-off floor 1e-11
  (``alcontact.contact._verify.ROUNDOFF_FLOOR``); with friction the reported tractions are the
  updated multipliers, which differ from those the displacement balances by the last multiplier
  change, so ``max(newton_tol, tol_multiplier)`` = 1e-8.

Every combination converges on the examples' own (coarse) meshes (:data:`KNOWN_FAILURES` would list those
that do not, each with its reason: none since the frictional barrier anchor on ``finite_ironing_friction``
stopped failing at its round-off floor, ``tests/regression/test_friction_roundoff_line_search.py``); the whole
file takes about 30 s.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from alcontact.contact import available_algorithms, friction_algorithms
from alcontact.io.config import load_problem
from alcontact.runner import run_setup

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TOL = 1e-8
NEWTON_TOL = 1e-11  # max(newton_tol 1e-12, round-off floor 1e-11)


#: combinations known not to converge, with the reason; strict: one that starts converging fails here
#: until it is removed (its invariants are then checked like the others')
KNOWN_FAILURES: dict[tuple[str, str], str] = {}


def _cases():
    out = []
    for path in sorted(EXAMPLES.glob("*.toml")):
        friction = float(tomllib.loads(path.read_text()).get("contact", {}).get("friction", 0.0)) > 0
        for alg in (friction_algorithms() if friction else available_algorithms()):
            why = KNOWN_FAILURES.get((path.stem, alg))
            marks = [pytest.mark.xfail(strict=True, reason=why)] if why else []
            out.append(pytest.param(path.stem, alg, friction, id=f"{path.stem}-{alg}", marks=marks))
    return out


@pytest.mark.parametrize("name, algorithm, friction", _cases())
def test_converged_result_satisfies_every_printed_invariant(name, algorithm, friction):
    setup = load_problem(EXAMPLES / f"{name}.toml")
    assert (setup.friction > 0) == friction  # the case list matches the file
    s = run_setup(setup, algorithm=algorithm).summary
    assert s["status"] == "converged", s["message"]
    eq_tol = max(NEWTON_TOL, TOL) if friction else NEWTON_TOL
    printed = {"penetration": (s["penetration"], TOL), "complementarity": (s["complementarity"], TOL),
               "equilibrium_residual": (s["equilibrium_residual"], eq_tol),
               "equilibrium_free_residual": (s["equilibrium_free_residual"], eq_tol)}
    bad = {k: v for k, v in printed.items() if not (v[0] is not None and math.isfinite(v[0]) and v[0] <= v[1])}
    assert not bad, bad
