"""Frictional contact benchmark: Algorithms 6.2 / 6.4 and the semi-smooth Newton reference.

Cases: the 2D Cattaneo-Mindlin cylinder (normal then tangential load) and a 3D
sphere under normal then tangential load (half model). For every algorithm and
family-P penalty the script records, per load step, the outer and Newton
iterations, and per run the linear solves, cut-backs, wall time and the ratio of
the whole load-stepped solve to one linear elastic solve of the same mesh
(factorization + one solve, measured in the same run). Writes
``<out>/friction.csv`` (one row per step), ``<out>/friction_runs.csv`` and
``<out>/friction.md``.

Usage::

    python benchmarks/friction.py [--out DIR] [--cases mindlin-2d sphere-3d] [--variants ...]
"""

from __future__ import annotations

import argparse
import csv
import io
import logging
import sys
import time
from pathlib import Path

import numpy as np

from alcontact.contact import problem_at, solve_friction
from alcontact.io.results import write_text_atomic
from alcontact.problems import friction as fp

CASES = {
    "mindlin-2d": (fp.cattaneo_mindlin_2d, dict(n_per_a=16)),
    "sphere-3d": (fp.sphere_shear_3d, dict(n_per_a=4)),
}

VARIANTS = [
    ("ssn", "ssn", None),
    ("simo-laursen (6.2)", "simo-laursen", None),
    ("exp-met1 (6.4)", "family-p", "exp-met1"),
    ("exp-met2 (6.4)", "family-p", "exp-met2"),
    ("log-met1 (6.4)", "family-p", "log-met1"),
    ("log-met2 (6.4)", "family-p", "log-met2"),
    ("quad-met2 (6.4)", "family-p", "quad-met2"),
]

STEP_FIELDS = ["case", "variant", "step", "t", "outer_iterations", "newton_iterations", "cutbacks",
               "normal_force", "tangential_force", "stick", "slip"]
RUN_FIELDS = ["case", "dofs", "variant", "status", "steps", "outer_iterations", "newton_iterations",
              "linear_solves", "cutbacks", "wall_s", "linear_solve_s", "ratio", "Q_over_muP"]


def _linear_solve_seconds(prob, hist) -> float:
    frozen = problem_at(prob, hist, hist.times[-1])
    fixed, vals = frozen.dirichlet()
    t0 = time.perf_counter()
    fac = frozen.model.factorize(fixed)
    fac.solve_full(frozen.load_vector(), vals)
    t = time.perf_counter() - t0
    frozen.model.clear_factorization()  # the frictional runs pay their own factorization
    return t


def run(out_dir=None, cases=None, variants=None, log=print) -> Path:
    """Run the benchmark; return the output folder."""
    out = Path(out_dir or Path(__file__).parent / "out")
    out.mkdir(parents=True, exist_ok=True)
    chosen = [v for v in VARIANTS if variants is None or v[0].split()[0] in variants or v[0] in variants]
    step_rows, run_rows = [], []
    for case in cases or list(CASES):
        builder, kw = CASES[case]
        prob, hist = builder(**kw)
        t_lin = _linear_solve_seconds(prob, hist)
        log(f"{case}: {prob.model.ndofs} DOFs, {len(hist.times)} load steps, linear solve {t_lin:.2f} s")
        for label, alg, pen in chosen:
            sol = solve_friction(prob, hist, alg, pen)
            wall = sol.timings["total_s"]
            fin = sol.steps[-1] if sol.steps else None
            ok = fin is not None and fin.normal_force > 0 and sol.friction > 0
            q = float(np.linalg.norm(fin.tangential_force)) / (sol.friction * fin.normal_force) if ok else float("nan")
            for k, st in enumerate(sol.steps):
                step_rows.append({
                    "case": case, "variant": label, "step": k + 1, "t": round(st.t, 6),
                    "outer_iterations": st.outer_iterations, "newton_iterations": st.newton_iterations,
                    "cutbacks": st.cutbacks, "normal_force": f"{st.normal_force:.6g}",
                    "tangential_force": f"{float(np.linalg.norm(st.tangential_force)):.6g}",
                    "stick": int(np.sum(st.state == 1)), "slip": int(np.sum(st.state == 2)),
                })
            row = {
                "case": case, "dofs": prob.model.ndofs, "variant": label, "status": sol.status.label,
                "steps": len(sol.steps), "outer_iterations": sol.outer_iterations,
                "newton_iterations": sol.newton_iterations, "linear_solves": sol.linear_solves,
                "cutbacks": sol.cutbacks, "wall_s": round(wall, 3), "linear_solve_s": round(t_lin, 3),
                "ratio": round(wall / t_lin, 2), "Q_over_muP": round(q, 4),
            }
            run_rows.append(row)
            log(f"  {label:20s} {row['status']:12s} outer={row['outer_iterations']:4d} "
                f"newton={row['newton_iterations']:5d} solves={row['linear_solves']:5d} "
                f"wall={wall:.2f}s ratio={row['ratio']:.2f} Q/muP={q:.3f}")
    for name, fields, rows in (("friction.csv", STEP_FIELDS, step_rows), ("friction_runs.csv", RUN_FIELDS, run_rows)):
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
        write_text_atomic(out / name, buf.getvalue())
    md = ["# Friction benchmark", "",
          "Whole load-stepped solve over one linear elastic solve of the same mesh (same run). "
          "Outer / Newton iterations summed over the steps; per-step counts in friction.csv.", ""]
    for case in dict.fromkeys(r["case"] for r in run_rows):
        sub = [r for r in run_rows if r["case"] == case]
        md += [f"## {case} ({sub[0]['dofs']} DOFs, {sub[0]['steps']} steps)", "",
               "| variant | status | outer | Newton | outer/step | solves | cut-backs | wall s | ratio | Q/muP |",
               "|---|---|---|---|---|---|---|---|---|---|"]
        for r in sub:
            per = r["outer_iterations"] / max(r["steps"], 1)
            md.append(f"| {r['variant']} | {r['status']} | {r['outer_iterations']} | {r['newton_iterations']} | "
                      f"{per:.1f} | {r['linear_solves']} | {r['cutbacks']} | {r['wall_s']} | {r['ratio']} | "
                      f"{r['Q_over_muP']} |")
        md.append("")
    write_text_atomic(out / "friction.md", "\n".join(md) + "\n")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--cases", nargs="*", choices=list(CASES), default=None)
    ap.add_argument("--variants", nargs="*", default=None)
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    path = run(args.out, args.cases, args.variants)
    print(f"wrote {path / 'friction.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
