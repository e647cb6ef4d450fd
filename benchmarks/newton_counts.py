"""Newton, outer and linear-solve counts of the small cases whose counts the tests used to pin.

The tests assert what a solve must get right (forces against the reference, convergence,
equilibrium); how many Newton systems, outer iterations or assembly + linear solves it takes
is a measure of algorithmic quality, recorded here (machine-independent counts) next to the
bound the test used to assert, so that a change of cost shows in the report instead of
failing a physics test. The counts that are a documented promise stay asserted in the tests
(the issue's target of at most 5 Newton systems per load step on average for the reference
and Algorithm 6.1, ``tests/verification/test_finite_newton_cost.py``).

Cases (the tests' problems, with the tests' settings; the measurements and the history of each
count are in the module docs of the tests named in the ``former_test`` column):

- ``hc8``: :func:`alcontact.problems.half_cylinder.half_cylinder` ``(8, order=2, curved=False)``
  (578 DOFs, neo-Hookean, :math:`\\delta/R = 0.4` in 20 load steps): the reference ``ssn``,
  Algorithm 6.1, the pure penalty with its stiffness continued over the steps, Algorithm 6.3
  (``exp-met1``, ``quad-met1``, ``log-met1``);
- ``hc8-curved``: the same with the curved P2 boundary (the default), Algorithm 6.3 with the
  log-barrier penalties ``log-met1``, ``log-met2``;
- ``hc24`` (``--full``): ``(24, order=2, curved=False)``, the reference over the 20 steps, and
  Algorithm 6.1 over the first 8 of them (:math:`\\delta/R = 0.16` in 8 steps);
- ``hemisphere-4``: :func:`alcontact.problems.hemisphere.hemisphere` ``(4, order=1)`` (375 DOFs,
  5 load steps): the reference and Algorithm 6.1;
- ``hertz-2d-8``: :func:`alcontact.problems.hertz.hertz_2d` ``(order=1, n_per_a=8, growth=1.3)``,
  Algorithm 6.3 with ``log-met2``: Newton steps of the first MET 2 subproblem after the penalty start;
- ``finite-ironing``: ``examples/finite_ironing.toml`` with ``algorithm = "penalty"``.

Writes ``<out>/newton_counts.csv`` (one row per count: case, variant, metric, value, the former
bound and the test that asserted it) and ``<out>/newton_counts.md``.

Usage::

    python benchmarks/newton_counts.py [--out DIR] [--full]
"""

from __future__ import annotations

import argparse
import csv
import io
import sys
from pathlib import Path

import numpy as np

from alcontact.contact import solve
from alcontact.io.results import write_text_atomic

ROOT = Path(__file__).resolve().parents[1]
FIELDS = ["case", "dofs", "variant", "metric", "value", "former_bound", "within", "former_test"]
NEWTON_COST = "tests/verification/test_finite_newton_cost.py"
MET_COST = "tests/verification/test_finite_met_penalty_cost.py"


def _accepted(sol):
    """The frames of the accepted load steps (a run that reached none has one frame of its start, t = 0)."""
    return [f for f in sol.frames if f.t > 0]


def _row(rows, case, dofs, variant, metric, value, bound, test):
    value = float(value)
    rows.append({"case": case, "dofs": dofs, "variant": variant, "metric": metric, "value": round(value, 4),
                 "former_bound": "" if bound is None else bound,
                 "within": "" if bound is None else ("yes" if value <= bound else "NO"), "former_test": test})


def _stepped(rows, case, problem, variant, steps, pins, **kw):
    """One load-stepped solve; ``pins``: (metric, bound, test) with metric one of :data:`METRICS`."""
    algorithm, _, penalty = variant.partition("/")
    sol = solve(problem, algorithm, penalty or None, steps=steps, **kw)
    frames = _accepted(sol)
    dofs = int(problem.model.ndofs)
    _row(rows, case, dofs, variant, "status_code", int(sol.status), None, "")
    _row(rows, case, dofs, variant, "steps", len(frames), None, "")
    for metric, bound, test in pins:
        _row(rows, case, dofs, variant, metric, METRICS[metric](sol, frames), bound, test)
    print(case, variant, sol.status.label, {m: METRICS[m](sol, frames) for m, *_ in pins}, flush=True)
    return sol


METRICS = {
    "newton_mean": lambda sol, fr: np.mean([f.newton_iterations for f in fr]),
    "newton_max": lambda sol, fr: max(f.newton_iterations for f in fr),
    "newton_step1": lambda sol, fr: fr[0].newton_iterations,
    "newton_mean_from_step2": lambda sol, fr: np.mean([f.newton_iterations for f in fr[1:]]),
    "linear_solves_mean": lambda sol, fr: np.mean([f.linear_solves for f in fr]),
    "outer_max_from_step2": lambda sol, fr: max(f.outer_iterations for f in fr[1:]),
    "outer_mean_from_step2": lambda sol, fr: np.mean([f.outer_iterations for f in fr[1:]]),
    "chord_steps": lambda sol, fr: sol.extra.get("chord_steps", 0),
}


def run(full: bool = False) -> list[dict]:
    from alcontact.app import run_setup
    from alcontact.io import load_problem
    from alcontact.problems import hertz
    from alcontact.problems.half_cylinder import half_cylinder
    from alcontact.problems.hemisphere import hemisphere

    rows: list[dict] = []
    hc8 = half_cylinder(8, order=2, curved=False)
    _stepped(rows, "hc8", hc8, "ssn", 20, [
        ("newton_mean", 4.0, NEWTON_COST + "::test_at_most_four_assembly_and_solves_per_step"),
        ("linear_solves_mean", 4.0, NEWTON_COST + "::test_at_most_four_assembly_and_solves_per_step"),
        ("newton_step1", 4, NEWTON_COST + "::test_entry_rule_on_the_first_contact_saves_newton")])
    _stepped(rows, "hc8", hc8, "simo-laursen", 20, [
        ("newton_mean", 3.25, NEWTON_COST + "::test_chord_steps_near_convergence_save_newton_systems"),
        ("linear_solves_mean", 4.0, NEWTON_COST + "::test_at_most_four_assembly_and_solves_per_step"),
        ("newton_step1", 4, NEWTON_COST + "::test_entry_rule_on_the_first_contact_saves_newton"),
        ("chord_steps", None, "")])
    _stepped(rows, "hc8", hc8, "penalty", 20, [
        ("newton_mean", 5.5, MET_COST + "::test_penalty_continuation_cuts_newton"),
        ("outer_max_from_step2", 3, MET_COST + "::test_penalty_continuation_cuts_newton"),
        ("outer_mean_from_step2", 2.5, MET_COST + "::test_penalty_continuation_cuts_newton")])
    for pen in ("exp-met1", "quad-met1", "log-met1"):
        _stepped(rows, "hc8", hc8, f"family-p/{pen}", 20, [
            ("newton_mean", 6.0, MET_COST + "::test_warm_penalty_start_cuts_newton")])
    curved = half_cylinder(8, order=2)
    for pen in ("log-met1", "log-met2"):
        _stepped(rows, "hc8-curved", curved, f"family-p/{pen}", 20, [
            ("newton_max", 40, "tests/verification/test_finite_log_barrier.py::"
                               "test_log_barrier_reaches_delta_04_with_reference_force")])
    if full:
        _stepped(rows, "hc24", half_cylinder(24, order=2, curved=False), "ssn", 20, [
            ("newton_mean", 4.5, NEWTON_COST + "::test_entry_rule_saves_active_set_steps")])
        _stepped(rows, "hc24-8-of-20", half_cylinder(24, order=2, delta=0.4 * 8 / 20, curved=False), "simo-laursen",
                 8, [("newton_mean", 4.5, NEWTON_COST + "::test_entry_rule_on_the_prediction_saves_newton_in_algorithm_6_1"),
                     ("newton_mean_from_step2", 4.0,
                      NEWTON_COST + "::test_entry_rule_on_the_prediction_saves_newton_in_algorithm_6_1")])
    hemi = hemisphere(4, order=1)
    for alg in ("ssn", "simo-laursen"):
        _stepped(rows, "hemisphere-4", hemi, alg, 5, [
            ("linear_solves_mean", 4.0, NEWTON_COST + "::test_hemisphere_3d_costs_at_most_four_solves_per_step")])
    prob = hertz.hertz_2d(order=1, n_per_a=8, growth=1.3)
    met = solve(prob, "family-p", "log-met2")
    _row(rows, "hertz-2d-8", int(prob.model.ndofs), "family-p/log-met2", "status_code", int(met.status), None, "")
    _row(rows, "hertz-2d-8", int(prob.model.ndofs), "family-p/log-met2", "newton_first_met_subproblem",
         met.result.history[1].newton_iterations, 10,
         "tests/unit/test_condensed_steps.py::test_barrier_penalty_first_subproblem_starts_next_to_the_penalty_solution")
    print("hertz-2d-8 log-met2", met.status.label, met.result.history[1].newton_iterations, flush=True)
    pen = run_setup(load_problem(ROOT / "examples" / "finite_ironing.toml"), algorithm="penalty").summary
    newton = pen["step_newton_iterations"]
    _row(rows, "finite-ironing", int(pen.get("dofs", 0)), "penalty", "status_code", int(pen["status_code"]), None, "")
    _row(rows, "finite-ironing", int(pen.get("dofs", 0)), "penalty", "newton_mean", np.mean(newton), 45,
         "tests/regression/test_finite_penalty_equilibrium.py::test_finite_ironing_penalty_is_in_equilibrium")
    print("finite-ironing penalty", pen["status"], float(np.mean(newton)), flush=True)
    return rows


def report(rows, command: str) -> str:
    md = ["# Newton and linear-solve counts of the small test cases", "",
          "Counts the tests used to assert, measured by `benchmarks/newton_counts.py` (machine-independent; "
          "the module docs of the tests named below have what each count measured before and why). "
          "`former bound`: the bound the test asserted; `within`: whether this run is within it. "
          "Documented promises stay asserted in the tests.", "", f"Generated by `{command}`.", "",
          "| case | DOFs | variant | metric | value | former bound | within | former test |",
          "|---|---:|---|---|---:|---:|---|---|"]
    for r in rows:
        md.append(f"| {r['case']} | {r['dofs']} | {r['variant']} | {r['metric']} | {r['value']:g} | "
                  f"{r['former_bound']} | {r['within']} | {r['former_test'].split('::')[-1]} |")
    return "\n".join(md) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "benchmarks"))
    ap.add_argument("--full", action="store_true", help="also the n = 24 half-cylinder runs (a few minutes)")
    args = ap.parse_args(argv)
    rows = run(args.full)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS)
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(out / "newton_counts.csv", buf.getvalue())
    command = "python benchmarks/newton_counts.py" + (" --full" if args.full else "")
    write_text_atomic(out / "newton_counts.md", report(rows, command))
    bad = [r for r in rows if r["within"] == "NO"]
    print(f"wrote {out / 'newton_counts.md'}; {len(bad)} counts above their former bound")
    return 0


if __name__ == "__main__":
    sys.exit(main())
