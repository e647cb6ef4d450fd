"""Hyperelastic assembly benchmark: tangent and internal force against the linear elastic assembly.

For each case (2D plane strain P2 at about 64k DOFs, 3D P1 at about 100k DOFs) and each
built-in law the script times, on a moderately deformed state u (10 % stretch plus shear):

* ``pattern``: the one-time CSR pattern and entry map (first tangent minus a later one),
* ``tangent``: one ``Hyperelastic.tangent(u)`` (median of ``--repeat``),
* ``force``: one ``internal_force(u)``, ``energy``: one ``energy(u)``,
* with ``--symbolic`` also the neo-Hookean law derived by :class:`SymbolicMaterial`,
* ``le_stiffness``: ``LinearElasticity.stiffness()`` (scikit-fem's generic ``asm`` of the
  bilinear form, same mesh and quadrature),
* ``solve``: one factorization of the tangent on the free DOFs plus one solve
  (``LinearElasticity.factorize`` defaults: CHOLMOD in 2D, SuperLU + nested dissection in 3D),
  and ``le_solve`` the same for the linear elastic stiffness (3D only with ``--solve-3d``:
  SuperLU takes minutes at 100k DOFs).

Writes ``<out>/hyperelastic.csv`` and ``<out>/hyperelastic.md``.

Usage::

    python benchmarks/hyperelastic.py [--out DIR] [--cases 2d-p2-64k 3d-p1-100k] [--repeat 3]

Timings are ratios within one run; machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import csv
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from alcontact.fem import Hyperelastic, LinearElasticity, Material, SymbolicMaterial, available_materials, meshes


def _neo_hookean_energy(F, lam, mu):
    import sympy

    J = F.det()
    return mu / 2 * ((F.T * F).trace() - 3) - mu * sympy.log(J) + lam / 2 * sympy.log(J) ** 2

CASES = {
    "2d-p2-64k": (lambda: meshes.rectangle(0.0, 1.0, 0.0, 1.0, 89, 89), 2),
    "3d-p1-100k": (lambda: meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 31, 31, 31), 1),
    "2d-p2-8k": (lambda: meshes.rectangle(0.0, 1.0, 0.0, 1.0, 31, 31), 2),
    "3d-p1-10k": (lambda: meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 14, 14, 14), 1),
}


def _timed(fun, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fun()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def _solve(model, K, f):
    fixed = model.dirichlet("left")[0]
    free = np.setdiff1d(np.arange(model.ndofs), fixed)
    t0 = time.perf_counter()
    fac = model.factorize(fixed, matrix=K, check=False)
    fac.solve(f[free])
    return time.perf_counter() - t0


def run_case(name: str, repeat: int, solve_3d: bool, symbolic: bool) -> list[dict]:
    build, order = CASES[name]
    mesh = build()
    mat = Material(E=100.0, nu=0.3)
    le = LinearElasticity(mesh, mat, order=order)
    t_le, _ = _timed(lambda: (setattr(le, "_stiffness", None), le.stiffness()), repeat)
    solve = le.dim == 2 or solve_3d
    t_le_solve = _solve(le, le.stiffness(), np.ones(le.ndofs)) if solve else float("nan")
    rows = []
    laws = list(available_materials())
    if symbolic:  # the same neo-Hookean law derived by SymPy (generic tangent contraction)
        laws.append(SymbolicMaterial(_neo_hookean_energy, name="sympy-neo-hookean"))
    for law in laws:
        t0 = time.perf_counter()
        body = Hyperelastic(mesh, mat, order=order, model=law)
        t_init = time.perf_counter() - t0
        body.law.energy(np.eye(body.dim)[None], 1.0, 1.0)  # compile a symbolic law outside the timings
        dim = body.dim
        u = body.interpolate(lambda x: np.vstack([0.1 * x[0] + 0.05 * x[1], -0.03 * x[1:]]))
        t0 = time.perf_counter()
        body.tangent(u)
        t_first = time.perf_counter() - t0
        t_tan, K = _timed(lambda: body.tangent(u), repeat)
        t_f, f = _timed(lambda: body.internal_force(u), repeat)
        t_e, _ = _timed(lambda: body.energy(u), repeat)
        t_solve = _solve(body, K, f) if solve else float("nan")
        rows.append(dict(case=name, law=body.law.name, dim=dim, order=order, ndofs=body.ndofs, nel=mesh.t.shape[1],
                         nnz=K.nnz, init=t_init, pattern=t_first - t_tan, tangent=t_tan, force=t_f,
                         energy=t_e, le_stiffness=t_le, solve=t_solve, le_solve=t_le_solve))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="bench-out")
    ap.add_argument("--cases", nargs="+", default=["2d-p2-64k", "3d-p1-100k"], choices=sorted(CASES))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--solve-3d", action="store_true", help="also time the 3D factorizations (minutes)")
    ap.add_argument("--symbolic", action="store_true", help="also time the SymPy-derived neo-Hookean law")
    args = ap.parse_args()
    rows = [r for c in args.cases for r in run_case(c, args.repeat, args.solve_3d, args.symbolic)]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    keys = list(rows[0])
    with open(out / "hyperelastic.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for r in rows:
        lines.append("| " + " | ".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in r.values()) + " |")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    head = [
        "# Hyperelastic assembly benchmark",
        "",
        f"`python benchmarks/hyperelastic.py {' '.join(sys.argv[1:])}` on {platform.node() or 'this machine'}, "
        f"{os.cpu_count()} cores, load average {load:.1f} at the end (times in seconds, medians of "
        f"{args.repeat}; compare ratios within one run).",
        "",
        "Columns: `tangent`, `force`, `energy` one call on a deformed state; `pattern` the one-time "
        "sparsity pattern and entry map; `le_stiffness` scikit-fem `asm` of the linear elastic stiffness; "
        "`solve`/`le_solve` one factorization plus solve of the tangent / of the linear stiffness.",
        "",
    ]
    (out / "hyperelastic.md").write_text("\n".join(head + lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
