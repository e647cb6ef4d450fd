"""The mixed u-p body on the approximate linear-solver path: MINRES + block preconditioner against the factorization.

Cases (finite deformation, ``simo-laursen``, neo-Hookean isochoric law, E = 1000):

* ``half-cylinder``: :func:`alcontact.problems.half_cylinder.half_cylinder` (plane strain, curved P2,
  ``delta/R = 0.4`` in 8 load steps) as a :class:`~alcontact.fem.MixedHyperelastic` body;
* ``half-cylinder-fan``: the same problem on the shape-regular nested mesh of ``benchmarks/curved_p2.py``
  (``fan_mesh(level)``; the elliptical-grid mesh of ``half_cylinder`` flattens its elements near the arc at
  45 degrees under refinement, smallest angle 13.4 / 6.9 / 3.5 / 1.8 deg at n = 8 ... 64, and algebraic
  multigrid feels that: CG with one V-cycle on the displacement block at F = I takes 30 / 42 / 55 / 96
  iterations there against 28 / 31 / 33 / 50 on the fan mesh at comparable sizes);
* ``hemisphere``: the 3D quarter :func:`alcontact.problems.hemisphere.hemisphere` (curved P2 tetrahedra,
  ``delta/R = 0.2`` in 5 load steps) as a mixed body.

Per size and path (``linear_solver = "direct"``: MKL PARDISO's symmetric-indefinite factorization of every
Newton matrix; ``"amg"``: MINRES with the block-diagonal preconditioner of ``alcontact.linalg._saddle``,
one PyAMG V-cycle on the displacement block and the lumped pressure mass x (1/mu + 1/kappa) on the
pressure rows): DOFs, status, cut-backs, Newton iterations, MINRES iterations per Newton step (inexact
Newton: the forcing terms of :class:`alcontact.linalg.NewtonKrylovSolver`), AMG setups, direct fallbacks,
CPU seconds per Newton step (the whole solve's process CPU time over its Newton steps: assembly
included), the wall fraction spent in linear solves, and the force and displacement against the direct
run. On a loaded shared machine the ratios of CPU times in one run are what to compare. NumPy's random state
is seeded before each solve (:data:`SEED`: PyAMG's hierarchies start from a random vector).

Diagnostics on the Newton matrices of a direct run (half-cylinder, nu = 0.4999, every 6th matrix),
MINRES to 1e-8 relative in the preconditioner's norm from the Newton right-hand sides:

* the Schur scale: the lumped pressure mass times ``c/mu + 1/kappa`` for c = 0.5, 1, 2;
* the displacement block preconditioned exactly (a sparse LU of it) instead of by one V-cycle: what the
  Schur approximation alone costs, and how much of the growth under refinement is AMG's;
* the aggregation strength threshold theta of the displacement block's hierarchy (PyAMG's
  ``smoothed_aggregation_solver``, ``'symmetric'`` strength; the solver uses theta = 0): CG iterations with
  one V-cycle on the displacement block alone to 1e-10 from a random right-hand side, operator complexity.

Writes ``<out>/mixed_amg.csv``, ``.json`` and ``mixed_amg.md``.

Usage::

    python benchmarks/mixed_amg.py [--out docs/benchmarks] [--n2d 16 32 64 110] [--fan 3 4 5 6] [--n3d 4 6 8 10]
    python benchmarks/mixed_amg.py --out docs/benchmarks --merge run1/mixed_amg.json run2/mixed_amg.json
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
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, splu

from alcontact import contact, linalg
from alcontact.contact.systems import _full_space
from alcontact.fem import MixedHyperelastic
from alcontact.linalg import krylov
from alcontact.linalg._amg import SMOOTHER, smoothed_aggregation
from alcontact.problems.half_cylinder import half_cylinder
from alcontact.problems.hemisphere import hemisphere

E = 1000.0
#: NumPy's global seed before each solve: PyAMG estimates the spectral radius of its prolongator smoother from a
#: random start vector, so the hierarchies, the MINRES counts and the inexact Newton path vary with the random
#: state (half-cylinder n = 16, seeds 0 / 1 / 2: 44 Newton each, 87.9 / 83.8 / 82.4 MINRES per Newton; the
#: forces agree to 4e-13). Seeded, a run repeats to the last digit.
SEED = 0


def _fan_half_cylinder(level: int):
    """The half-cylinder problem on the shape-regular nested mesh ``fan_mesh(level)`` of ``benchmarks/curved_p2.py``."""
    from curved_p2 import fan_mesh  # this folder is on the path when the script runs

    from alcontact.contact import ContactProblem, Support
    from alcontact.contact.obstacles import HalfSpace
    from alcontact.fem import Hyperelastic, Material

    body = Hyperelastic(fan_mesh(level), Material(E=E, nu=0.3, plane="strain"), order=2)
    return ContactProblem(model=body, obstacle=HalfSpace([0.0, 0.0], [0.0, 1.0]), contact_boundary="curved",
                          supports=(Support("symmetry", components=(0,)), Support("top", components=(1,), value=-0.4)),
                          kinematics="finite")


CASES = {"half-cylinder": (lambda n: half_cylinder(n, order=2, curved=True, nu=0.3, delta=0.4), 8),
         "half-cylinder-fan": (_fan_half_cylinder, 8),
         "hemisphere": (lambda n: hemisphere(n, order=2, curved=True, nu=0.3, delta=0.2), 5)}


def _problem(case: str, n: int, nu: float):
    make, steps = CASES[case]
    base = make(n)
    return dataclasses.replace(base, model=MixedHyperelastic(base.model.mesh, E=E, nu=nu)), steps


def _count_factorizations():
    """Wrap the registry direct solvers' ``factorize`` to count its calls (a hidden factorization shows)."""
    calls = []
    for cls in (linalg.SuperLUSolver, linalg.PardisoSolver, linalg.CholmodSolver):
        orig = cls.factorize

        def counted(self, *args, _orig=orig, **kw):
            calls.append(self.name)
            return _orig(self, *args, **kw)

        cls.factorize = counted
    return calls


CALLS = _count_factorizations()


def _row(case: str, n: int, nu: float, path: str, ref: dict | None) -> dict:
    problem, steps = _problem(case, n, nu)
    del CALLS[:]
    np.random.seed(SEED)  # PyAMG's spectral-radius estimate starts from a random vector (module doc)
    t0, c0 = time.perf_counter(), time.process_time()
    sol = contact.solve(problem, "simo-laursen", steps=steps, options={"linear_solver": path})
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    ex, tm = sol.extra, sol.timings
    newton = int(sum(f.newton_iterations for f in sol.frames))
    row = {"case": case, "n": n, "nu": nu, "path": path, "ndofs": int(problem.model.ndofs),
           "status": sol.result.status.label, "steps": len(sol.frames),
           "cutbacks": int(sum(f.cutbacks for f in sol.frames)), "newton": newton,
           "solver": ex.get("linear_solver"), "krylov": ex.get("krylov", "-"),
           "minres_per_newton": float(ex.get("cg_per_newton", 0.0)), "krylov_iterations": int(ex.get("cg_iterations", 0)),
           "amg_setups": int(ex.get("amg_setups", 0)), "direct_fallbacks": int(ex.get("direct_fallbacks", 0)),
           "factorize_calls": len(CALLS),
           "cpu_s": cpu, "wall_s": wall, "cpu_per_newton_s": cpu / max(newton, 1),
           "linear_fraction": float(tm.get("linear_solve_s", 0.0)) / max(float(tm.get("total_s", wall)), 1e-12),
           "force": float(sol.total_contact_force[1]), "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}
    if ref is not None:
        row["force_rel_diff"] = abs(row["force"] - ref["force"]) / abs(ref["force"])
        row["u_rel_diff"] = float(np.max(np.abs(sol.u - ref["u"])) / np.max(np.abs(ref["u"])))
    else:
        row["force_rel_diff"] = row["u_rel_diff"] = 0.0
    row["_u"] = sol.u
    return row


def run(case: str, ns, nu: float = 0.4999) -> list[dict]:
    rows = []
    for n in ns:
        ref = _row(case, n, nu, "direct", None)
        amg = _row(case, n, nu, "amg", {"force": ref["force"], "u": ref["_u"]})
        for r in (ref, amg):
            r.pop("_u")
            rows.append(r)
            print(json.dumps(r), flush=True)
    return rows


# ---------------------------------------------------------------------- diagnostics
def _newton_matrices(n: int, nu: float = 0.4999, every: int = 6):
    """Newton matrices and right-hand sides of a direct run of the half-cylinder (every ``every``-th)."""
    problem, steps = _problem("half-cylinder", n, nu)
    store = []
    orig = _full_space.NewtonSolver.newton_step

    def keep(self, A, rhs, history):
        store.append((sp.csr_matrix(A).copy(), np.array(rhs)))
        return orig(self, A, rhs, history)

    _full_space.NewtonSolver.newton_step = keep
    try:
        contact.solve(problem, "simo-laursen", steps=steps, options={"linear_solver": "direct"})
    finally:
        _full_space.NewtonSolver.newton_step = orig
    return problem.model, store[::every]


def diagnostics(ns, nu: float = 0.4999, rtol: float = 1e-8) -> list[dict]:
    rows = []
    for n in ns:
        model, mats = _newton_matrices(n, nu)
        lumped = model.lumped_pressure_mass
        fixed = np.concatenate([model.dirichlet("symmetry", [0])[0], model.dirichlet("top", [1])[0]])
        free = np.zeros(model.ndofs, dtype=bool)
        free[: model.ndofs_u] = True
        free[fixed] = False
        B = model.near_null()[free]  # the rigid-body modes on the free displacement rows
        for A, rhs in mats:
            m = A.shape[0] - model.npressure
            Auu = A[:m, :m].tocsr()
            ml = smoothed_aggregation(Auu, B)
            V = ml.aspreconditioner(cycle="V")
            lu = splu(Auu.tocsc())
            for label, inner in (("amg", V), ("exact", None)):
                for c in ((0.5, 1.0, 2.0) if label == "amg" else (1.0,)):
                    sinv = 1.0 / (lumped * (c / model.mu + (0.0 if np.isinf(model.kappa) else 1.0 / model.kappa)))

                    def apply(r, inner=inner, sinv=sinv):
                        z = np.empty_like(r)
                        z[:m] = inner @ r[:m] if inner is not None else lu.solve(r[:m])
                        z[m:] = sinv * r[m:]
                        return z

                    M = LinearOperator(A.shape, matvec=apply, dtype=float)
                    x, it, why = krylov.minres(A, rhs, M, rtol, 5000)
                    res = float(np.linalg.norm(A @ x - rhs) / np.linalg.norm(rhs))
                    rows.append({"n": n, "ndofs": A.shape[0], "primal": label, "c": c, "method": "minres",
                                 "minres": it, "why": why, "true_res": res})
                    if label == "amg" and c == 1.0:  # the block-triangular preconditioner with GMRES, same matrix
                        A12 = A[:m, m:].tocsr()

                        def tri(r, inner=inner, sinv=sinv, A12=A12):
                            z = np.empty_like(r)
                            z[m:] = -sinv * r[m:]
                            z[:m] = inner @ (r[:m] - A12 @ z[m:])
                            return z

                        T = LinearOperator(A.shape, matvec=tri, dtype=float)
                        x, it, info = krylov.gmres(A, rhs, T, rtol=rtol, restart=300, maxiter=20)
                        res = float(np.linalg.norm(A @ x - rhs) / np.linalg.norm(rhs))
                        rows.append({"n": n, "ndofs": A.shape[0], "primal": label, "c": c, "method": "gmres-triangular",
                                     "minres": it, "why": "" if info == 0 else "maxiter", "true_res": res})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def theta_sweep(ns, thetas=(0.0, 0.02, 0.05, 0.1)) -> list[dict]:
    import pyamg

    rows = []
    for n in ns:
        problem, _ = _problem("half-cylinder", n, 0.4999)
        model = problem.model
        K = model.tangent(np.zeros(model.ndofs))
        fixed = np.concatenate([model.dirichlet("symmetry", [0])[0], model.dirichlet("top", [1])[0]])
        free = np.zeros(model.ndofs, dtype=bool)
        free[: model.ndofs_u] = True
        free[fixed] = False
        Kf = K[free][:, free].tocsr()
        B = model.near_null()[free]
        rhs = np.random.default_rng(0).standard_normal(Kf.shape[0])
        for th in thetas:
            c0 = time.process_time()
            ml = (smoothed_aggregation(Kf, B) if th == 0.0 else pyamg.smoothed_aggregation_solver(
                Kf, B=B, strength=("symmetric", {"theta": th}), max_coarse=500, coarse_solver="splu",
                presmoother=SMOOTHER, postsmoother=SMOOTHER))
            c1 = time.process_time()
            _, it, why = krylov.pcg(Kf, rhs, ml.aspreconditioner(cycle="V"), 1e-10, 5000)
            c2 = time.process_time()
            rows.append({"n": n, "ndofs_u": int(Kf.shape[0]), "theta": th, "levels": len(ml.levels),
                         "operator_complexity": float(ml.operator_complexity()), "cg": it,
                         "setup_cpu_s": c1 - c0, "cg_cpu_s": c2 - c1})
            print(json.dumps(rows[-1]), flush=True)
    return rows


# ---------------------------------------------------------------------- report
def _fmt(x, spec):
    return format(x, spec) if isinstance(x, (int, float)) else str(x)


def report(rows, diag, theta, load: str) -> str:
    lines = ["# The mixed u-p body on the AMG path: MINRES + block preconditioner against the factorization", "",
             f"`python benchmarks/mixed_amg.py` on {platform.processor() or platform.machine()}, {os.cpu_count()} "
             f"cores shared with other jobs ({load}: wall times are noisy, the CPU times of one run and the counts "
             "are what to compare), one thread. Finite deformation, `simo-laursen`, mixed Taylor-Hood body "
             "(curved P2 / P1), isochoric neo-Hookean, E = 1000, nu = 0.4999. `direct`: MKL PARDISO "
             "(symmetric indefinite) on every Newton matrix; `amg`: MINRES with the block-diagonal preconditioner "
             "(one V-cycle of PyAMG smoothed aggregation with the rigid-body modes on the displacement block, the "
             "lumped pressure mass x (1/mu + 1/kappa) on the pressure rows), inexact Newton. "
             "`factorize` counts the calls of every registry direct solver's `factorize` during the run (0: no "
             "hidden factorization; on the direct path PARDISO's numerical refactorizations of a kept analysis "
             "are not calls). `CPU s / Newton`: the whole solve's CPU time over its Newton steps.", "",
             "| case | n | DOFs | path | status | cut-backs | Newton | MINRES / Newton | AMG setups | fallbacks | "
             "factorize | CPU s / Newton | linear share | force | force vs direct | u vs direct |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['n']} | {r['ndofs']:,} | {r['path']} ({r['solver']}) | {r['status']} | "
                     f"{r['cutbacks']} | {r['newton']} | {_fmt(r['minres_per_newton'], '.1f') if r['path'] == 'amg' else '-'} | "
                     f"{r['amg_setups'] or '-'} | {r['direct_fallbacks']} | {r['factorize_calls']} | "
                     f"{r['cpu_per_newton_s']:.3f} | {r['linear_fraction']:.2f} | {r['force']:.9g} | "
                     f"{r['force_rel_diff']:.1e} | {r['u_rel_diff']:.1e} |")
    lines += ["", "CPU time ratio amg / direct per Newton step (same run):", ""]
    by = {(r["case"], r["n"], r["path"]): r for r in rows}
    for (case, n, path), r in by.items():
        if path == "amg" and (case, n, "direct") in by:
            d = by[(case, n, "direct")]
            lines.append(f"- {case} n = {n} ({r['ndofs']:,} DOFs): {r['cpu_per_newton_s'] / d['cpu_per_newton_s']:.2f}"
                         f" (whole solve {r['cpu_s'] / d['cpu_s']:.2f})")
    lines += ["", "MINRES iterations per Newton step under refinement (DOFs in parentheses):", ""]
    for case in CASES:
        amg = sorted((r for r in rows if r["case"] == case and r["path"] == "amg"), key=lambda r: r["ndofs"])
        if amg:
            lines.append(f"- {case}: " + ", ".join(f"{r['minres_per_newton']:.0f} ({r['ndofs']:,})" for r in amg)
                         + "; Newton steps amg / direct: " + ", ".join(
                             f"{r['newton']} / {by[(case, r['n'], 'direct')]['newton']}" for r in amg
                             if (case, r["n"], "direct") in by))
    amg_rows = [r for r in rows if r["path"] == "amg"]
    if amg_rows:
        ratios = [r["cpu_s"] / by[(r["case"], r["n"], "direct")]["cpu_s"] for r in amg_rows
                  if (r["case"], r["n"], "direct") in by]
        ok = sum(r["status"] == "converged" for r in amg_rows)
        lines += ["", f"Reading: the AMG path converged on {ok} of {len(amg_rows)} rows with no direct factorization "
                  f"(factorize calls {sum(r['factorize_calls'] for r in amg_rows)}, direct fallbacks "
                  f"{sum(r['direct_fallbacks'] for r in amg_rows)}) and the direct path's force to "
                  f"{max(r['force_rel_diff'] for r in amg_rows):.1e} (displacement "
                  f"{max(r['u_rel_diff'] for r in amg_rows):.1e}). It costs {min(ratios):.1f} to {max(ratios):.1f} "
                  "times the factorization's CPU time for the whole solve at these sizes (more Newton steps: the "
                  "inexact Newton and the loose dual-step solves of `NewtonKrylovSolver`; MINRES iterations on the "
                  "saddle point, several times CG's on the displacement block alone), so `auto` keeps the "
                  "factorization for mixed bodies; the AMG path is the one whose memory stays linear in the size. "
                  "MINRES iterations per Newton step grow slowly on the shape-regular fan mesh and faster on the "
                  "elliptical-grid mesh, whose flattening elements degrade the AMG hierarchy of the displacement "
                  "block (theta table below)."]
    if diag:
        lines += ["", "## MINRES on the Newton matrices of a direct run (half-cylinder, every 6th matrix)", "",
                  "MINRES iterations to 1e-8 (preconditioner norm) from the Newton right-hand sides, mean (max) over the "
                  "matrices; `amg`: one V-cycle on the displacement block (rigid-body modes of the reference configuration), "
                  "`exact`: a sparse LU of it; Schur diagonal = lumped pressure mass x (c/mu + 1/kappa).", "",
                  "`gmres-triangular`: GMRES(300) with the block upper-triangular preconditioner (the one of the "
                  "frictional path) to the same rtol of its own (Euclidean) residual; `true residual`: the largest "
                  "|A x - b| / |b| reached.", "",
                  "| n | DOFs | displacement block | c | method | iterations mean | max | true residual |",
                  "|---|---|---|---|---|---|---|---|"]
        keys = sorted({(d["n"], d["ndofs"], d["primal"], d["c"], d.get("method", "minres")) for d in diag})
        seen = set()
        for n, nd, primal, c, method in keys:
            if (n, primal, c, method) in seen:
                continue
            seen.add((n, primal, c, method))
            sel = [d for d in diag if d["n"] == n and d["primal"] == primal and d["c"] == c
                   and d.get("method", "minres") == method]
            its = [d["minres"] for d in sel]
            res = max(d.get("true_res", float("nan")) for d in sel)
            lines.append(f"| {n} | {nd:,} | {primal} | {c:g} | {method} | {np.mean(its):.1f} | {max(its)} | {res:.1e} |")
    if theta:
        lines += ["", "## Aggregation strength threshold on the displacement block", "",
                  "CG with one V-cycle on the mixed body's displacement block at F = I (random right-hand side, "
                  "1e-10), PyAMG `symmetric` strength with threshold theta (theta = 0: the solver's lean first "
                  "level, PyAMG's default).", "",
                  "| n | displacement DOFs | theta | levels | operator complexity | CG | setup CPU s | CG CPU s |",
                  "|---|---|---|---|---|---|---|---|"]
        for t in theta:
            lines.append(f"| {t['n']} | {t['ndofs_u']:,} | {t['theta']:g} | {t['levels']} | "
                         f"{t['operator_complexity']:.2f} | {t['cg']} | {t['setup_cpu_s']:.3f} | {t['cg_cpu_s']:.3f} |")
    return "\n".join(lines) + "\n"


def _write(out: Path, rows, diag, theta, load: str) -> None:
    out.mkdir(parents=True, exist_ok=True)
    if rows:
        with open(out / "mixed_amg.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    (out / "mixed_amg.json").write_text(json.dumps({"rows": rows, "diagnostics": diag, "theta": theta, "load": load},
                                                   indent=1))
    (out / "mixed_amg.md").write_text(report(rows, diag, theta, load))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks"))
    ap.add_argument("--n2d", type=int, nargs="*", default=[16, 32, 64, 110])
    ap.add_argument("--n3d", type=int, nargs="*", default=[4, 6, 8, 10])
    ap.add_argument("--fan", type=int, nargs="*", default=[3, 4, 5, 6], help="levels of the fan mesh")
    ap.add_argument("--diag", type=int, nargs="*", default=[8, 16, 32])
    ap.add_argument("--theta", type=int, nargs="*", default=[16, 32, 64])
    ap.add_argument("--merge", type=Path, nargs="*", default=None,
                    help="write the report of these earlier runs' mixed_amg.json files together (no solves), in order")
    args = ap.parse_args()
    if args.merge:
        parts = [json.loads(Path(f).read_text()) for f in args.merge]
        rows = sorted((r for p in parts for r in p["rows"]),
                      key=lambda r: (list(CASES).index(r["case"]), r["n"], r["path"] != "direct"))
        _write(args.out, rows, [d for p in parts for d in p["diagnostics"]], [t for p in parts for t in p["theta"]],
               "; ".join(p.get("load", "load not recorded") for p in parts))
        return
    rows = run("half-cylinder", args.n2d) + run("half-cylinder-fan", args.fan) + run("hemisphere", args.n3d)
    diag = diagnostics(args.diag)
    theta = theta_sweep(args.theta)
    _write(args.out, rows, diag, theta, "load average %.1f %.1f %.1f at the end" % os.getloadavg())


if __name__ == "__main__":
    main()
