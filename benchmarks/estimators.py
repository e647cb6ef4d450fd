"""Peak pressure and contact size estimators against Hertz, per element type and mesh.

For each case (Hertz cylinder in 2D, sphere in 3D; P1 and P2; a refinement sweep) the
script solves the frictionless problem (simo-laursen) and records, against the Hertz
solution for the load the model carries:

* ``p0_fit``: ``p0`` of the least-squares (L2) Hertz fit of the recovered pressure field
  (the reported ``peak_pressure``), ``a_fit``: ``a`` of the load-matched L2 fit (the
  reported ``contact_half_width``),
* ``a_free``, ``p0_load``: the other parameter of each fit (``a`` of the free fit, ``p0``
  of the load-matched fit),
* ``a_mom``: ``a`` from the second moment of the nodal forces,
  :math:`\sum_i r_i\rho_i^2 / \sum_i r_i = (2/5)a^2` (3D), :math:`a^2/4` (2D),
* ``p0_pts``, ``a_pts``: the same fit at the points, weighted by tributary areas,
* ``p0_max``: the raw largest nodal pressure (``peak_pressure_nodal_max``),
* ``a_edge``: the outermost loaded point interpolated along the symmetry line,
* ``sym_pct`` / ``interior_pct`` (3D): mean error of the recovered pressure at the points
  on the symmetry planes and at the other points, inside ``r < a/2``,
* ``equilibrium``: the global equilibrium residual :math:`|F_c + F_{ext} + R|/|F|`.

Writes ``<out>/estimators.csv``, ``<out>/estimators.json`` and ``<out>/estimators.md``.

Usage::

    python benchmarks/estimators.py [--out DIR] [--cases 2d-p1 2d-p2 3d-p1 3d-p2 3d-p2-80k]

The 3D P2 case at about 80k DOFs is a direct solve of a few minutes on a shared machine.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

from alcontact.contact import solve
from alcontact.contact.solution._estimators import fit_hertz, radial_coordinate
from alcontact.io.results import write_text_atomic
from alcontact.problems import hertz

#: case -> list of (builder, keyword arguments) of a refinement sweep
CASES = {
    "2d-p1": [(hertz.hertz_2d, dict(order=1, n_per_a=n)) for n in (8, 16, 32, 64)],
    "2d-p2": [(hertz.hertz_2d, dict(order=2, n_per_a=n)) for n in (4, 8, 16, 32)],
    "2d-p1-R100": [(hertz.hertz_2d, dict(order=1, n_per_a=n, radius=100.0)) for n in (2, 4, 8, 16, 32)],
    "2d-p2-R100": [(hertz.hertz_2d, dict(order=2, n_per_a=n, radius=100.0)) for n in (1, 2, 4, 8)],
    "3d-p1": [(hertz.hertz_3d, dict(order=1, n_per_a=n)) for n in (4, 6, 8)],
    "3d-p1-R100": [(hertz.hertz_3d, dict(order=1, n_per_a=n, size=6.0, growth=1.5, radius=100.0)) for n in (4, 6, 8)],
    "3d-p2-small": [(hertz.hertz_3d, dict(order=2, n_per_a=n, size=4.0, growth=1.6)) for n in (1, 1.5, 2)],
    "3d-p2": [(hertz.hertz_3d, dict(order=2, n_per_a=n)) for n in (1,)],
    "3d-p2-80k": [(hertz.hertz_3d, dict(order=2, n_per_a=2))],
}
DEFAULT_CASES = ["2d-p1", "2d-p2", "2d-p1-R100", "2d-p2-R100", "3d-p1", "3d-p1-R100", "3d-p2-small", "3d-p2",
                 "3d-p2-80k"]

FIELDS = ["case", "dim", "order", "n_per_a", "radius", "dofs", "status", "wall_s", "p0_fit_pct", "a_fit_pct",
          "a_free_pct", "p0_load_pct", "a_mom_pct", "p0_pts_pct", "a_pts_pct", "p0_max_pct", "a_edge_pct", "sym_pct",
          "interior_pct", "equilibrium", "fit_rms"]


def _pct(x, ref):
    return 100.0 * (float(x) / float(ref) - 1.0)


def run_one(case: str, builder, kw: dict) -> dict:
    prob = builder(**kw)
    t0 = time.perf_counter()
    sol = solve(prob)
    wall = time.perf_counter() - t0
    ref = prob.reference
    P = ref.load(sol.normal_force)
    a_ex, p0_ex = ref.half_width(P), ref.peak_pressure(P)
    fit = sol.hertz_fit()
    fit_load = sol.hertz_fit(amplitude="load")
    center = prob.meta["center"]
    rho = radial_coordinate(sol.points, center, 0 if prob.model.dim == 2 else None)
    f = sol.normal_nodal_forces * sol.active
    m2 = float(np.sum(f * rho**2) / np.sum(f))
    a_mom = float(np.sqrt(2.5 * m2) if prob.model.dim == 3 else 2.0 * np.sqrt(m2))
    row = {
        "case": case, "dim": prob.model.dim, "order": prob.model.order, "n_per_a": kw.get("n_per_a"),
        "radius": ref.radius, "dofs": prob.model.ndofs, "status": sol.result.status.label, "wall_s": round(wall, 2),
        "p0_fit_pct": _pct(sol.peak_pressure, p0_ex),
        "a_fit_pct": _pct(sol.contact_half_width(axis=0, center=center), a_ex),
        "a_free_pct": _pct(fit.a, a_ex), "p0_load_pct": _pct(fit_load.p0, p0_ex), "a_mom_pct": _pct(a_mom, a_ex),
        "p0_pts_pct": None, "a_pts_pct": None,
        "p0_max_pct": _pct(sol.peak_pressure_nodal_max, p0_ex),
        "a_edge_pct": _pct(sol.contact_half_width_edge(axis=0, center=center), a_ex),
        "sym_pct": None, "interior_pct": None,
        "equilibrium": sol.equilibrium().residual, "fit_rms": fit.rms,
    }
    pts_fit = fit_hertz(radial_coordinate(sol.points, center, 0 if prob.model.dim == 2 else None),
                        sol.pressure * sol.active, sol.weights)
    row["p0_pts_pct"], row["a_pts_pct"] = _pct(pts_fit.p0, p0_ex), _pct(pts_fit.a, a_ex)
    if prob.model.dim == 3:
        pts = sol.points
        r = radial_coordinate(pts, center)
        inside = r < 0.5 * a_ex
        sym = np.any(np.abs(pts[:, :2]) < 1e-9, axis=1)
        err = sol.pressure / np.maximum(ref.pressure(r, P), 1e-300) - 1.0
        row["sym_pct"] = 100.0 * float(np.mean(err[inside & sym]))
        row["interior_pct"] = 100.0 * float(np.mean(err[inside & ~sym]))
    return row


def _fmt(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.3g}" if abs(v) < 1e-3 and v != 0 else f"{v:+.2f}" if abs(v) < 1000 else f"{v:.0f}"
    return str(v)


def write_outputs(rows: list[dict], out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow(r)
    write_text_atomic(out / "estimators.csv", buf.getvalue())
    write_text_atomic(out / "estimators.json", json.dumps(rows, indent=1))
    head = ["case", "n/a", "R", "DOFs", "p0 fit %", "a fit %", "a free %", "p0 load %", "a mom %", "p0 pts %", "a pts %",
            "p0 max %", "a edge %", "sym. planes %",
            "interior %", "equilibrium", "wall s"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        vals = [r["case"], r["n_per_a"], r["radius"], r["dofs"], r["p0_fit_pct"], r["a_fit_pct"], r["a_free_pct"],
                r["p0_load_pct"], r["a_mom_pct"], r["p0_pts_pct"],
                r["a_pts_pct"], r["p0_max_pct"],
                r["a_edge_pct"], r["sym_pct"], r["interior_pct"], r["equilibrium"], r["wall_s"]]
        lines.append("| " + " | ".join(_fmt(v) for v in vals) + " |")
    write_text_atomic(out / "estimators.md", "\n".join(lines) + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="bench-estimators")
    ap.add_argument("--cases", nargs="*", default=DEFAULT_CASES, choices=list(CASES))
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    rows = []
    out = Path(args.out)
    for case in args.cases:
        for builder, kw in CASES[case]:
            row = run_one(case, builder, kw)
            rows.append(row)
            print(" ".join(f"{k}={_fmt(row[k])}" for k in FIELDS), flush=True)
            write_outputs(rows, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
