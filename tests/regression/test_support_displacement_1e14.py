"""Issue 18, case 5: a support displacement of 1e14 (flat punch, bottom pulled away) was accepted and
reported converged, exit 0, with a contact force of 1945.6 made of round-off and an equilibrium
residual of 0.94 printed beside it.

Now the problem file is refused before solving (``support[2].value``: far beyond the body's size),
and a problem built through the API comes back ``NOT_VERIFIED``: the ``resolution`` measure of the
verification (round-off of the gaps at such positions, 8.9e-2 h, against ``tol_penetration`` 1e-8)
says the state cannot be trusted.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from alcontact.contact import ContactStatus, Support, solve
from alcontact.errors import ConfigError
from alcontact.io.config import load_problem, load_problem_text
from alcontact.io.preflight import check_problem

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "flat_punch.toml"


def test_problem_file_is_refused_before_solving(tmp_path):
    p = tmp_path / "punch.toml"
    p.write_text(EXAMPLE.read_text().replace("value = 0.01", "value = -1e14"))
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    msg = {i.path: i.message for i in exc.value.issues}["support[2].value"]
    assert "1e+14" in msg and "body's size" in msg and "units" in msg


def test_api_solve_is_not_converged():
    setup = load_problem(EXAMPLE)
    prob = setup.problem
    supports = tuple(dataclasses.replace(s, value=-1e14) if s.boundary == "bottom" else s for s in prob.supports)
    supports += (Support("bottom", (1,), -1e14),) if not any(s.boundary == "bottom" for s in supports) else ()
    sol = solve(dataclasses.replace(prob, supports=supports), "ssn")
    assert sol.status == ContactStatus.NOT_VERIFIED and not sol.result.success
    assert "resolution" in sol.result.message


def test_the_shipped_punch_is_unaffected():
    text = EXAMPLE.read_text()
    setup = load_problem_text(text, base_dir=EXAMPLE.parent)
    sol = solve(setup.problem, "ssn")
    assert sol.status == ContactStatus.CONVERGED
