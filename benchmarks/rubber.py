"""Nearly incompressible rubber at size: Newton per step and time per step, mixed against displacement.

Case: :func:`alcontact.problems.half_cylinder.half_cylinder` (neo-Hookean-type half-cylinder pressed to
``delta/R = 0.4``, plane strain, P2 on straight-sided triangles, 10 uniform load steps, ``simo-laursen``),
E = 1000, on the ``n x n`` mapped mesh (``2 (2n + 1)^2`` displacement DOFs). Rows per size:

* ``displacement``, ``nu = 0.45``: :class:`~alcontact.fem.Hyperelastic` with the split law
  ``W = c10 (I1b - 3) + K/2 (J - 1)^2`` (Mooney-Rivlin, c01 = 0, c10 = mu/2);
* ``mixed``, ``nu = 0.45``: :class:`~alcontact.fem.MixedHyperelastic` with the same law (the same
  material: where both work they agree to the discretization error, ``tests/verification``);
* ``mixed``, ``nu = 0.4999``: the mixed body with the isochoric neo-Hookean law (the displacement body
  needs dozens of cut-backs there: ``benchmarks/mixed_rubber.py``).

Per row: DOFs (the mixed body's include its ``(n + 1)^2`` pressures), status, cut-backs, Newton
iterations per step (mean, max), linear solves, the contact force, wall and CPU time per load step
(the process's CPU time: on a loaded shared machine the ratios of CPU times in one run are what to
compare), and the peak resident memory of the process so far. Writes ``<out>/rubber.csv``, ``.json``
and ``rubber.md``.

Usage::

    python benchmarks/rubber.py [--out docs/benchmarks] [--n 24 48 96]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import os
import platform
import resource
import time
from pathlib import Path

import numpy as np

from alcontact import contact
from alcontact.fem import Hyperelastic, Material, MixedHyperelastic, MooneyRivlin
from alcontact.problems.half_cylinder import half_cylinder

E = 1000.0
STEPS = 10


def _row(label, nu, n, body, base):
    t0, c0 = time.perf_counter(), time.process_time()
    sol = contact.solve(dataclasses.replace(base, model=body), "simo-laursen", steps=STEPS)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    newton = [f.newton_iterations for f in sol.frames]
    return {"body": label, "nu": nu, "n": n, "ndofs": int(body.ndofs), "status": sol.result.status.label,
            "steps": len(newton), "cutbacks": int(sum(f.cutbacks for f in sol.frames)),
            "newton_mean": float(np.mean(newton)), "newton_max": int(max(newton)),
            "linear_solves": int(sol.result.linear_solves), "force": float(sol.total_contact_force[1]),
            "wall_per_step_s": wall / len(newton), "cpu_per_step_s": cpu / len(newton),
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}


def run(ns) -> list[dict]:
    rows = []
    for n in ns:
        base = half_cylinder(n, order=2, curved=False, nu=0.45, delta=0.4)
        mesh = base.model.mesh
        law = MooneyRivlin(c10=E / (4.0 * 1.45))
        for label, nu, make in (
                ("displacement", 0.45, lambda: Hyperelastic(mesh, Material(E, 0.45, "strain"), order=2, model=law)),
                ("mixed", 0.45, lambda: MixedHyperelastic(mesh, E=E, nu=0.45, model=law)),
                ("mixed", 0.4999, lambda: MixedHyperelastic(mesh, E=E, nu=0.4999))):
            rows.append(_row(label, nu, n, make(), base))
            print(json.dumps(rows[-1]), flush=True)
    return rows


def report(rows: list[dict]) -> str:
    lines = ["# Nearly incompressible rubber at size: mixed u-p against displacement", "",
             f"`python benchmarks/rubber.py` on {platform.processor() or platform.machine()}, {os.cpu_count()} "
             "cores shared with other jobs (load average above the core count: wall times are noisy, the CPU "
             "times of one run and the counts are what to compare). Half-cylinder, plane strain, P2, "
             f"delta/R = 0.4 in {STEPS} load steps, simo-laursen, one thread.", "",
             "| body | nu | n | DOFs | status | cut-backs | Newton/step mean | max | linear solves | force | "
             "wall s/step | CPU s/step | peak RSS MB |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['body']} | {r['nu']} | {r['n']} | {r['ndofs']} | {r['status']} | {r['cutbacks']} | "
                     f"{r['newton_mean']:.1f} | {r['newton_max']} | {r['linear_solves']} | {r['force']:.6g} | "
                     f"{r['wall_per_step_s']:.2f} | {r['cpu_per_step_s']:.2f} | {r['peak_rss_mb']:.0f} |")
    lines += ["", "CPU time per step, mixed / displacement at nu = 0.45 (same run, same mesh):"]
    for n in sorted({r["n"] for r in rows}):
        d = next(r for r in rows if r["n"] == n and r["body"] == "displacement")
        m = next(r for r in rows if r["n"] == n and r["body"] == "mixed" and r["nu"] == 0.45)
        mi = next(r for r in rows if r["n"] == n and r["body"] == "mixed" and r["nu"] == 0.4999)
        lines.append(f"- n = {n} ({d['ndofs']} / {m['ndofs']} DOFs): {m['cpu_per_step_s'] / d['cpu_per_step_s']:.2f}; "
                     f"mixed at nu = 0.4999 / displacement at 0.45: {mi['cpu_per_step_s'] / d['cpu_per_step_s']:.2f}; "
                     f"force mixed / displacement at 0.45 - 1 = {m['force'] / d['force'] - 1:.2e}.")
    lines += ["", "Reading: where both formulations work (nu = 0.45) they give the same force (to the discretization "
              "error, shrinking with n) in as many or fewer Newton iterations per step; the mixed step costs more "
              "CPU time (its symmetric indefinite saddle-point factorization, about 12 % more unknowns and a "
              "denser pattern). At nu = 0.4999, where the displacement element locks and needs dozens of "
              "cut-backs (`benchmarks/mixed_rubber.py`), the mixed body keeps the same Newton counts and cost "
              "per step as at nu = 0.45, with no cut-back."]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/benchmarks")
    ap.add_argument("--n", type=int, nargs="+", default=[24, 48, 96])
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = run(tuple(args.n))
    with open(out / "rubber.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    (out / "rubber.json").write_text(json.dumps(rows, indent=1))
    (out / "rubber.md").write_text(report(rows))


if __name__ == "__main__":
    main()
