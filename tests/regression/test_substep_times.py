"""Issue 20, item 7: ``times`` of a load-stepped solution holds the sub-steps of cut-backs; say so.

A 60 % compression in one requested step with at most 4 Newton iterations per subproblem fails whole
and is halved (the case of tests/verification/test_finite_compression.py): the solution's ``times``
has the inserted sub-steps, ``requested`` marks them, ``requested_times`` is the requested ``[1.0]``,
and a problem-file run labels them in ``summary.json``, ``steps.csv`` and ``report.md``.
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Support, obstacles, solve_finite
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.io import load_problem
from alcontact.runner import run_setup

TOML = """
[problem]
name = "compression-with-cutbacks"
[mesh]
generator = "rectangle"
bounds = [0.0, 1.0, 0.0, 1.0]
cells = [2, 2]
[material]
E = 1000.0
nu = 0.3
model = "neo-hookean"
[[support]]
boundary = "left"
components = [0]
[[support]]
boundary = "top"
components = [1]
value = -0.6
ramp = [[0.0, 0.0], [1.0, 1.0]]
[loading]
steps = 1
[obstacle]
type = "half-space"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[contact]
boundary = "bottom"
kinematics = "finite"
[solver]
maxiter_newton = 4
subproblems = "exact"
"""


def test_times_holds_the_substeps_and_requested_marks_them():
    body = Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2), Material(E=1000.0, nu=0.3, plane="strain"))
    problem = ContactProblem(body, obstacles.HalfSpace([0.0, 0.0], [0.0, 1.0]), "bottom",
                             supports=(Support("left", (0,), 0.0), Support("top", (1,), -0.6)), kinematics="finite")
    fs = solve_finite(problem, "simo-laursen", steps=1, maxiter_newton=4, subproblems="exact")
    assert fs.success, fs.message
    assert len(fs.times) >= 2 and np.isclose(fs.times[-1], 1.0)
    assert list(fs.requested) == [False] * (len(fs.times) - 1) + [True]
    np.testing.assert_allclose(fs.requested_times, [1.0])


def test_problem_file_run_labels_the_substeps(tmp_path):
    p = tmp_path / "p.toml"
    p.write_text(TOML, encoding="utf-8")
    res = run_setup(load_problem(p), tmp_path / "o")
    s = json.loads((tmp_path / "o" / "summary.json").read_text(encoding="utf-8"))
    assert s["status"] == "converged" and s["cutbacks"] >= 1
    n = len(s["step_times"])
    assert n >= 2 and s["step_requested"] == [False] * (n - 1) + [True]
    assert s["step_requested"] == [bool(x) for x in res.raw.requested]
    with open(tmp_path / "o" / "steps.csv", newline="", encoding="utf-8") as fh:
        assert [int(r["requested"]) for r in csv.DictReader(fh)] == [0] * (n - 1) + [1]
    report = (tmp_path / "o" / "report.md").read_text(encoding="utf-8")
    assert f"{n - 1} of the {n} accepted steps (marked *) are sub-steps that cut-backs inserted" in report
