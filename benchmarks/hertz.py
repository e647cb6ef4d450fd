"""Hertz contact benchmark: every frictionless algorithm and penalty, several mesh sizes.

For each case (2D cylinder at about 10k, 100k, 500k DOFs; 3D sphere at about 100k and
1M DOFs) and each algorithm/penalty the script records outer iterations, Newton
iterations, linear solves (triangular solve pairs with the one stiffness factor), wall
time, and the ratio of the contact solve to one linear elastic solve of the same mesh
(a fresh factorization + one solve with the same solver, :func:`plain_linear_solve`)
measured in the same run, plus the accuracy against Hertz.
Writes ``<out>/hertz.csv`` and ``<out>/hertz.md``.

Usage::

    python benchmarks/hertz.py [--out DIR] [--cases 2d-10k 2d-100k ...] [--variants ssn simo-laursen ...]

Timings are ratios within one run; machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import csv
import io
import logging
import statistics
import sys
import time
from pathlib import Path

from alcontact.contact import solve
from alcontact.io.results import write_text_atomic
from alcontact.problems import hertz

#: name -> (builder, keyword arguments)
CASES = {
    "2d-10k": (hertz.hertz_2d, dict(n_per_a=32, growth=1.15)),
    "2d-28k": (hertz.hertz_2d, dict(n_per_a=64, growth=1.15)),
    "2d-84k": (hertz.hertz_2d, dict(n_per_a=128, growth=1.15)),
    "2d-277k": (hertz.hertz_2d, dict(n_per_a=256, growth=1.15)),
    "2d-984k": (hertz.hertz_2d, dict(n_per_a=512, growth=1.15)),
    "2d-100k": (hertz.hertz_2d, dict(n_per_a=64, growth=1.02)),
    "2d-500k": (hertz.hertz_2d, dict(n_per_a=128, growth=1.01)),
    "3d-100k": (hertz.hertz_3d, dict(n_per_a=6, growth=1.07)),
    "3d-100k-direct": (hertz.hertz_3d, dict(n_per_a=6, growth=1.07)),  # condensed path, Schur build
    "3d-1M": (hertz.hertz_3d, dict(n_per_a=16, growth=1.04)),
}
DEFAULT_CASES = ["2d-10k", "2d-100k", "2d-500k", "3d-100k"]
#: contact options per case: the 3D 1M-DOF factor (~30 GB) does not fit in memory, so that
#: case runs the factorization-free AMG path ("auto" would choose it too; stated explicitly)
CASE_OPTIONS = {"3d-1M": {"linear_solver": "amg"},
                "3d-100k-direct": {"linear_solver": "mkl-pardiso"}}

#: (label, algorithm, penalty, extra options)
VARIANTS = [
    ("ssn", "ssn", None, {}),
    ("penalty", "penalty", None, {}),
    ("simo-laursen", "simo-laursen", None, {}),
    ("exp-met1", "family-p", "exp-met1", {}),
    ("exp-met2", "family-p", "exp-met2", {}),
    ("log-met1", "family-p", "log-met1", {}),
    ("log-met2", "family-p", "log-met2", {}),
    ("quad-met2", "family-p", "quad-met2", {}),
    ("exp-met1/fixed-eta", "family-p", "exp-met1", {"eta_scaling": "fixed"}),
    ("log-met2/fixed-eta", "family-p", "log-met2", {"eta_scaling": "fixed"}),
]

FIELDS = ["case", "dofs", "candidates", "variant", "algorithm", "penalty", "status", "outer_iterations",
          "newton_iterations", "linear_solves", "cg_iterations", "wall_s", "linear_solve_s", "plain_linear_s",
          "ratio", "a_err_pct", "p0_err_pct", "penetration_over_h"]


def plain_linear_solve(prob, linear_solver="auto") -> float:
    """Seconds of one linear elastic solve of ``prob``'s mesh: a fresh factorization + one solve.

    The same solver as the contact solve (``"auto"`` resolved as the contact solve does: AMG
    for large 3D models, else the fast direct one), no Schur block, no reuse: this is the
    "one linear solve" the contact solve is compared with.
    """
    from alcontact.contact._iterative import linear_solver_name

    model = prob.model
    fixed, values = prob.dirichlet()
    backend = linear_solver_name(linear_solver, model)  # what the contact solve resolves "auto" to
    model.clear_factorization()
    t0 = time.perf_counter()
    fac = model.factorize(fixed, backend=backend, reuse=False)
    fac.solve_full(prob.load_vector(), values)
    return time.perf_counter() - t0


def _row(case, label, prob, sol, plain):
    ref = prob.reference
    P = ref.load(sol.normal_force)
    a = sol.contact_half_width(axis=0, center=prob.meta["center"])
    r = sol.result
    t = sol.timings
    return {
        "case": case, "dofs": prob.model.ndofs, "candidates": sol.extra["candidates"], "variant": label,
        "algorithm": r.algorithm, "penalty": r.penalty, "status": r.status.label,
        "outer_iterations": r.outer_iterations, "newton_iterations": r.newton_iterations,
        "linear_solves": r.linear_solves, "cg_iterations": sol.extra.get("cg_iterations", ""),
        "wall_s": round(t["total_s"], 4),
        "linear_solve_s": round(t["linear_solve_s"], 4), "plain_linear_s": round(plain, 4),
        "ratio": round(t["total_s"] / plain, 3),
        "a_err_pct": round(100 * (a / ref.half_width(P) - 1), 3) if P > 0 else "",
        "p0_err_pct": round(100 * (sol.peak_pressure / ref.peak_pressure(P) - 1), 3) if P > 0 else "",
        "penetration_over_h": f"{r.penetration:.2e}",
    }


def _markdown(rows):
    out = ["# Hertz benchmark", "",
           "Contact solve time over one linear elastic solve (a fresh factorization + one solve with the same "
           "solver, no Schur block) of the same mesh, measured in the same run (the smaller of two measurements, "
           "before and after the variants). "
           "Iterations: outer / Newton; solves: triangular solve pairs with the single stiffness factorization "
           "(the Delassus operator comes from the Schur complement with MKL PARDISO and costs none).", ""]
    for case in dict.fromkeys(r["case"] for r in rows):
        sub = [r for r in rows if r["case"] == case]
        out += [f"## {case} ({sub[0]['dofs']} DOFs, {sub[0]['candidates']} contact candidates)", "",
                f"one linear solve: {sub[0]['plain_linear_s']} s", "",
                "| variant | status | outer | Newton | solves | wall s | contact/linear | a err % | p0 err % |",
                "|---|---|---|---|---|---|---|---|---|"]
        for r in sub:
            out.append(f"| {r['variant']} | {r['status']} | {r['outer_iterations']} | {r['newton_iterations']} | "
                       f"{r['linear_solves']} | {r['wall_s']} | {r['ratio']} | {r['a_err_pct']} | {r['p0_err_pct']} |")
        if any(r["cg_iterations"] != "" for r in sub):
            out += ["", "No factorization (linear_solver='amg'): solves are AMG-preconditioned CG solves, CG "
                    "iterations " + ", ".join(f"{r['variant']} {r['cg_iterations']}" for r in sub) + "; the "
                    "linear solve is the AMG setup plus one CG solve to 1e-10."]
        ratios = [r["ratio"] for r in sub]
        out += ["", f"median contact/linear ratio: {statistics.median(ratios):.2f}", ""]
    return "\n".join(out) + "\n"


def run(out_dir=None, cases=None, variants=None, log=print) -> Path:
    """Run the benchmark; return the folder with ``hertz.csv`` and ``hertz.md``."""
    out = Path(out_dir or Path(__file__).parent / "out")
    out.mkdir(parents=True, exist_ok=True)
    cases = cases or DEFAULT_CASES
    chosen = [v for v in VARIANTS if variants is None or v[0] in variants]
    rows = []
    for case in cases:
        builder, kw = CASES[case]
        t0 = time.perf_counter()
        prob = builder(**kw)
        log(f"{case}: {prob.model.ndofs} DOFs (mesh {time.perf_counter() - t0:.1f} s)")
        case_opts = CASE_OPTIONS.get(case, {})
        backend = case_opts.get("linear_solver", "auto")
        prob.model.stiffness()  # assembled once, outside both timings
        plain = plain_linear_solve(prob, backend)
        log(f"  one linear solve {plain:.2f} s")
        sols = []
        for label, alg, pen, opts in chosen:
            prob.model.clear_factorization()  # every variant pays its factorization (no reuse across variants)
            sols.append((label, solve(prob, alg, pen, **{**case_opts, **opts})))
        # shared machines: the smaller of two measurements, one before and one after the variants
        plain = min(plain, plain_linear_solve(prob, backend))
        log(f"  one linear solve (min of 2) {plain:.2f} s")
        for label, sol in sols:
            row = _row(case, label, prob, sol, plain)
            rows.append(row)
            log(f"  {label:20s} {row['status']:14s} outer={row['outer_iterations']:3d} "
                f"newton={row['newton_iterations']:4d} solves={row['linear_solves']:5d} cg_its={row['cg_iterations']} "
                f"wall={row['wall_s']:.2f}s ratio={row['ratio']:.2f}")
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS)
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(out / "hertz.csv", buf.getvalue())
    write_text_atomic(out / "hertz.md", _markdown(rows))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--cases", nargs="*", choices=list(CASES), default=None)
    ap.add_argument("--variants", nargs="*", choices=[v[0] for v in VARIANTS], default=None)
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    path = run(args.out, args.cases, args.variants)
    print(f"wrote {path / 'hertz.csv'} and {path / 'hertz.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
