"""Nearly incompressible rubber in contact: the mixed u-p body against the displacement body.

Case: :func:`alcontact.problems.half_cylinder.half_cylinder` (plane strain, P2 on straight-sided
triangles, ``delta/R = 0.4``, 10 uniform load steps, ``simo-laursen``), E = 1000. Rows:

* ``nu = 0.45`` (both work), same split law ``W = c10 (I1b - 3) + K/2 (J - 1)^2`` (Mooney-Rivlin,
  c01 = 0): the displacement body (:class:`~alcontact.fem.Hyperelastic`) and the mixed body
  (:class:`~alcontact.fem.MixedHyperelastic`);
* ``nu = 0.4999``: the mixed body (isochoric neo-Hookean), and the displacement body (compressible
  neo-Hookean) on the smallest mesh only (it needs cut-backs and minutes).

Per row: DOFs, status, accepted steps, cut-backs, Newton iterations per accepted step (mean, max),
linear solves, contact force and wall time (a loaded shared machine: compare counts, and times only
within one run). Writes ``<out>/mixed_rubber.csv``, ``.json`` and ``.md``.

Usage::

    python benchmarks/mixed_rubber.py [--out docs/benchmarks] [--n 12 24]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from alcontact import contact
from alcontact.fem import Hyperelastic, Material, MixedHyperelastic, MooneyRivlin
from alcontact.problems.half_cylinder import half_cylinder

E = 1000.0


def _row(label, nu, n, body, base):
    t0 = time.perf_counter()
    sol = contact.solve(dataclasses.replace(base, model=body), "simo-laursen", steps=10)
    wall = time.perf_counter() - t0
    newton = [f.newton_iterations for f in sol.frames]
    return {"body": label, "nu": nu, "n": n, "ndofs": int(body.ndofs), "status": sol.result.status.label,
            "steps": len(newton), "cutbacks": int(sum(f.cutbacks for f in sol.frames)),
            "newton_mean": float(np.mean(newton)), "newton_max": int(max(newton)),
            "linear_solves": int(sol.result.linear_solves), "force": float(sol.total_contact_force[1]),
            "wall_s": round(wall, 2)}


def run(ns=(12, 24)) -> list[dict]:
    rows = []
    for n in ns:
        base = half_cylinder(n, order=2, curved=False, nu=0.45, delta=0.4)
        mesh = base.model.mesh
        law = MooneyRivlin(c10=E / (4.0 * 1.45))
        rows.append(_row("displacement", 0.45, n, Hyperelastic(mesh, Material(E, 0.45, "strain"), order=2, model=law),
                         base))
        rows.append(_row("mixed", 0.45, n, MixedHyperelastic(mesh, E=E, nu=0.45, model=law), base))
        rows.append(_row("mixed", 0.4999, n, MixedHyperelastic(mesh, E=E, nu=0.4999), base))
        if n == min(ns):
            rows.append(_row("displacement", 0.4999, n, Hyperelastic(mesh, Material(E, 0.4999, "strain"), order=2),
                             base))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/benchmarks")
    ap.add_argument("--n", type=int, nargs="+", default=[12, 24])
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = run(tuple(args.n))
    with open(out / "mixed_rubber.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    (out / "mixed_rubber.json").write_text(json.dumps(rows, indent=1))
    head = "| body | nu | n | DOFs | status | steps | cut-backs | Newton/step mean | max | linear solves | force | wall s |"
    lines = ["# Nearly incompressible half-cylinder: mixed u-p vs displacement body", "",
             "Written by `benchmarks/mixed_rubber.py` (its docstring describes the case). One run, one machine;",
             "counts are machine-independent, wall times only comparable within the table.", "",
             head, "|" + "---|" * 12]
    for r in rows:
        lines.append(f"| {r['body']} | {r['nu']} | {r['n']} | {r['ndofs']} | {r['status']} | {r['steps']} | "
                     f"{r['cutbacks']} | {r['newton_mean']:.2f} | {r['newton_max']} | {r['linear_solves']} | "
                     f"{r['force']:.4f} | {r['wall_s']} |")
    (out / "mixed_rubber.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
