"""Axisymmetric against 3D: the neo-Hookean hemisphere on a rigid plane at finite deformation.

The same body, law and approach (``delta/R``, default 0.25, ``E = 1000``, ``nu = 0.3``, P2 with the
curved surface, uniform load steps of ``contact.solve``) modelled twice:

- as a body of revolution, :func:`alcontact.problems.hemisphere.hemisphere_axisym` (2D, r-z half-plane,
  forces totals over the revolution), on ``--ax`` meshes; the finest is the reference force;
- as the 3D quarter model of ``benchmarks/finite.py --problem hemisphere``,
  :func:`alcontact.problems.hemisphere.hemisphere` (force times 4), on ``--quarter`` meshes.

For each run: DOFs, status, load steps, Newton iterations (sum over the steps), the total normal
force, its relative difference from the reference and the CPU time (one thread; ratios measured in
one run). Writes ``<out>/axisym.csv``, ``<out>/axisym.json`` and ``<out>/axisym.md``.

Usage::

    OMP_NUM_THREADS=1 python benchmarks/axisym.py [--out docs/benchmarks] [--delta 0.25] [--steps 10]
                                                  [--ax 8 12 16 32 64] [--quarter 4 6 8]
"""

from __future__ import annotations

import argparse
import csv
import json
import platform
import sys
import time
from pathlib import Path

from alcontact.contact import solve
from alcontact.problems.hemisphere import hemisphere, hemisphere_axisym

FIELDS = ("model", "n", "order", "dofs", "status", "steps", "newton_iterations", "force", "rel_diff", "cpu_s")


def _run(model: str, n: int, order: int, delta: float, steps: int) -> dict:
    build, factor = (hemisphere_axisym, 1.0) if model == "axisymmetric" else (hemisphere, 4.0)
    t0 = time.process_time()
    problem = build(n, order=order, delta=delta)
    sol = solve(problem, steps=steps)
    cpu = time.process_time() - t0
    frames = [f for f in sol.frames if f.t > 0]  # the accepted load steps (a run that reached none: the start)
    return {"model": model, "n": n, "order": order, "dofs": int(problem.model.ndofs), "status": sol.status.label,
            "steps": len(frames), "newton_iterations": int(sum(f.newton_iterations for f in frames)),
            "force": factor * float(frames[-1].contact_force[1]), "cpu_s": cpu}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/benchmarks")
    ap.add_argument("--delta", type=float, default=0.25)
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--order", type=int, default=2)
    ap.add_argument("--ax", type=int, nargs="+", default=[8, 12, 16, 32, 64])
    ap.add_argument("--quarter", type=int, nargs="+", default=[4, 6, 8])
    args = ap.parse_args(argv)
    rows = []
    _run("axisymmetric", 4, args.order, args.delta, args.steps)  # imports and one-time lookups are no cost of a run
    for n in sorted(args.ax):
        rows.append(_run("axisymmetric", n, args.order, args.delta, args.steps))
        print(rows[-1], flush=True)
    for n in sorted(args.quarter):
        rows.append(_run("3d-quarter", n, args.order, args.delta, args.steps))
        print(rows[-1], flush=True)
    ref = rows[len(args.ax) - 1]  # the finest axisymmetric mesh
    for r in rows:
        r["rel_diff"] = r["force"] / ref["force"] - 1.0
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "axisym.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    meta = {"delta_over_R": args.delta, "steps": args.steps, "order": args.order, "python": sys.version.split()[0],
            "machine": platform.machine(), "reference": f"axisymmetric n={ref['n']}", "rows": rows}
    (out / "axisym.json").write_text(json.dumps(meta, indent=2) + "\n")
    ok_ax = [r for r in rows if r["model"] == "axisymmetric" and abs(r["rel_diff"]) <= 1e-3 and r is not ref]
    ok_3d = [r for r in rows if r["model"] == "3d-quarter" and abs(r["rel_diff"]) <= 1e-3]
    lines = [
        "# Axisymmetric against 3D: neo-Hookean hemisphere on a rigid plane",
        "",
        f"`OMP_NUM_THREADS=1 python benchmarks/axisym.py --delta {args.delta:g} --steps {args.steps} "
        f"--ax {' '.join(map(str, args.ax))} --quarter {' '.join(map(str, args.quarter))}`",
        "",
        f"R = 1, E = 1000, nu = 0.3, neo-Hookean, P{args.order} with the curved surface, delta/R = {args.delta:g} "
        f"in {args.steps} load steps. Force: the total normal force on the whole ball (axisymmetric: the "
        "body's own force, a total over the revolution; 3D: 4 times the quarter's). Reference: the finest "
        f"axisymmetric mesh (n = {ref['n']}, {ref['dofs']} DOFs, F = {ref['force']:.6f}). CPU seconds on one "
        "thread, build plus solve, all rows in one run.",
        "",
        "| model | n | DOFs | status | steps | Newton | force | rel. diff. | CPU s |",
        "|---|---:|---:|---|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r['model']} | {r['n']} | {r['dofs']} | {r['status']} | {r['steps']} | "
                     f"{r['newton_iterations']} | {r['force']:.6f} | {r['rel_diff']:+.2e} | {r['cpu_s']:.2f} |")
    lines.append("")
    if ok_ax and ok_3d:
        a, q = min(ok_ax, key=lambda r: r["cpu_s"]), min(ok_3d, key=lambda r: r["cpu_s"])
        lines.append(f"Cheapest runs within 1e-3 of the reference: axisymmetric n = {a['n']} ({a['dofs']} DOFs, "
                     f"{a['cpu_s']:.2f} s, {a['rel_diff']:+.1e}) and 3D quarter n = {q['n']} ({q['dofs']} DOFs, "
                     f"{q['cpu_s']:.2f} s, {q['rel_diff']:+.1e}): the two agree to "
                     f"{abs(a['force'] / q['force'] - 1):.1e}, at {q['cpu_s'] / a['cpu_s']:.0f}x less CPU time "
                     "for the body of revolution.")
    else:
        lines.append("No pair of runs within 1e-3 of the reference: refine (--ax, --quarter).")
    (out / "axisym.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
