"""The meshed rigid surface master (obstacle ``"surface"``): accuracy against the facet count, search cost.

Two tables:

1. **Accuracy**: the 2D Hertz problem (``hertz_2d(level=1)``) against the analytic circle and
   against its lower arc meshed with N facets (vertices on the circle, N = 32 ... 2048). The
   relative max-norm difference of the displacement, of the total contact force and of the
   contact half-width, with the observed rate between successive N (the displacement's is
   about 1: the facet normals are piecewise constant, their angle error is O(1/N)).
2. **Search cost**: a triangulated unit sphere with N faces (subdivided icosahedron), the
   time of one ``evaluate`` (gap and normal) of 20,000 points within a band of the surface
   (|distance| <= 0.1, and <= 0.005 as contact points are), per point, as a ratio to the
   smallest N (cKDTree on face centroids plus the exact point-triangle distance to every
   face that may be closer).

Writes ``<out>/meshed_surface.csv``, ``<out>/meshed_surface.json`` and
``<out>/meshed_surface.md``. Timings are ratios within one run; machines are shared and noisy.

Usage::

    python benchmarks/meshed_surface.py [--out docs/benchmarks]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import io
import json
import time
from pathlib import Path

import numpy as np

from alcontact.contact import obstacles, solve
from alcontact.io.results import write_text_atomic
from alcontact.problems import hertz


def _arc(center, radius, n):
    th = np.linspace(-np.pi / 2 - 0.5, -np.pi / 2 + 0.5, n + 1)
    V = np.asarray(center) + radius * np.column_stack([np.cos(th), np.sin(th)])
    return obstacles.make("surface", vertices=V, facets=np.column_stack([np.arange(n), np.arange(1, n + 1)]))


def accuracy(ns) -> list[dict]:
    base = hertz.hertz_2d(level=1)
    ref = solve(base, "simo-laursen")
    c, R = base.obstacle.center, base.obstacle.radius
    rows = []
    for n in ns:
        sol = solve(dataclasses.replace(base, obstacle=_arc(c, R, n)), "simo-laursen")
        rows.append({"facets": n, "status": sol.result.status.label, "dofs": base.model.ndofs,
                     "newton_iterations": sol.result.newton_iterations, "linear_solves": sol.result.linear_solves,
                     "u_rel_diff": float(np.abs(sol.u - ref.u).max() / np.abs(ref.u).max()),
                     "force_rel_diff": abs(sol.normal_force / ref.normal_force - 1),
                     "half_width_rel_diff": abs(sol.contact_half_width() / ref.contact_half_width() - 1)})
    for a, b in zip(rows, rows[1:]):
        b["u_rate"] = float(np.log(a["u_rel_diff"] / b["u_rel_diff"]) / np.log(b["facets"] / a["facets"]))
    return rows, {"newton_iterations": ref.result.newton_iterations, "linear_solves": ref.result.linear_solves}


def _icosphere(level: int):
    t = (1 + 5 ** 0.5) / 2
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
         [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
         [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
         [8, 6, 7], [9, 8, 1]]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(level):
        mid: dict = {}

        def m(i, j):
            key = (min(i, j), max(i, j))
            if key not in mid:
                p = V[i] + V[j]
                V.append(p / np.linalg.norm(p))
                mid[key] = len(V) - 1
            return mid[key]

        F = [f for a, b, c in F for f in ([a, m(a, b), m(c, a)], [b, m(b, c), m(a, b)], [c, m(c, a), m(b, c)],
                                          [m(a, b), m(b, c), m(c, a)])]
    return np.array(V), np.array(F)


def search_cost(levels, m: int = 20000, band: float = 0.1) -> list[dict]:
    rng = np.random.default_rng(0)
    d = rng.normal(size=(m, 3))
    x = d / np.linalg.norm(d, axis=1, keepdims=True) * rng.uniform(1 - band, 1 + band, size=(m, 1))
    rows = []
    for lv in levels:
        V, F = _icosphere(lv)
        t0 = time.perf_counter()
        ob = obstacles.make("surface", vertices=V, facets=F)
        build = time.perf_counter() - t0
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            g, _ = ob.evaluate(x)
            best = min(best, time.perf_counter() - t0)
        err = float(np.abs(g - (1 - np.linalg.norm(x, axis=1))).max())  # distance to the faces vs to the sphere
        rows.append({"band": band, "faces": int(F.shape[0]), "build_s": build, "evaluate_s": best,
                     "us_per_point": 1e6 * best / m, "gap_vs_sphere_max_abs": err})
    for r in rows:
        r["ratio_to_smallest"] = r["evaluate_s"] / rows[0]["evaluate_s"]
    return rows


def render(acc, ref_counts, cost) -> str:
    out = ["# Meshed rigid surface: accuracy against the facet count, search cost", "",
           "`python benchmarks/meshed_surface.py` (timings: ratios within one run on a shared machine).", "",
           "## Accuracy: 2D Hertz, meshed arc of N facets against the analytic circle", "",
           f"`hertz_2d(level=1)`, {acc[0]['dofs']} DOFs, Algorithm 6.1 (`simo-laursen`); the analytic circle took "
           f"{ref_counts['newton_iterations']} Newton iterations and {ref_counts['linear_solves']} linear solves.", "",
           "| facets N | u rel. diff | rate | force rel. diff | half-width rel. diff | Newton | linear solves |",
           "|---|---|---|---|---|---|---|"]
    for r in acc:
        rate = f"{r['u_rate']:.2f}" if "u_rate" in r else ""
        out.append(f"| {r['facets']} | {r['u_rel_diff']:.2e} | {rate} | {r['force_rel_diff']:.2e} | "
                   f"{r['half_width_rel_diff']:.2e} | {r['newton_iterations']} | {r['linear_solves']} |")
    out += ["", "The displacement converges at first order in 1/N: the facet normals are piecewise constant "
            "(angle error O(1/N)); the contact force converges faster. Gap: the exact signed distance to the "
            "facets (no smoothing), so a meshed plane is the analytic plane exactly.", "",
            "## Search cost: triangulated unit sphere, 20,000 points within a band of the surface", "",
            "| band | faces | build (s) | evaluate (s) | per point (us) | ratio to the smallest "
            "| max abs gap - sphere gap |",
            "|---|---|---|---|---|---|---|"]
    for r in cost:
        out.append(f"| {r['band']:g} | {r['faces']} | {r['build_s']:.3f} | {r['evaluate_s']:.3f} | "
                   f"{r['us_per_point']:.1f} | "
                   f"{r['ratio_to_smallest']:.2f} | {r['gap_vs_sphere_max_abs']:.2e} |")
    out += ["", "Candidate faces come from a cKDTree on face centroids (the 4 nearest, then every face whose "
            "centroid lies within the best distance d plus the largest face radius r): exact, and the candidates "
            "of a point are the faces of a cap of radius about sqrt(2 d r) around its closest point. A point near "
            "the surface (contact points: d of the order of the element size) sees a few faces and its cost grows "
            "with log N; a point far from a finely meshed surface (d >> r) sees more.", ""]
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/benchmarks")
    args = ap.parse_args(argv)
    out = Path(args.out)
    acc, ref_counts = accuracy([32, 64, 128, 256, 512, 1024, 2048])
    cost = search_cost([2, 3, 4, 5, 6]) + search_cost([2, 3, 4, 5, 6], band=0.005)
    buf = io.StringIO()
    keys = sorted({k for r in acc for k in r})
    w = csv.DictWriter(buf, fieldnames=["table"] + keys + sorted({k for r in cost for k in r}))
    w.writeheader()
    for r in acc:
        w.writerow({"table": "accuracy", **r})
    for r in cost:
        w.writerow({"table": "search", **r})
    write_text_atomic(out / "meshed_surface.csv", buf.getvalue())
    write_text_atomic(out / "meshed_surface.json", json.dumps({"accuracy": acc, "reference": ref_counts,
                                                               "search": cost}, indent=2))
    write_text_atomic(out / "meshed_surface.md", render(acc, ref_counts, cost))
    print(render(acc, ref_counts, cost))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
