"""Linear-solver benchmark: factorization + solve time and peak memory of every registered solver.

Matrices: the stiffness of the Hertz problems (:mod:`alcontact.problems.hertz`) condensed on
the free DOFs, 2D P2 (cylinder), 3D P1 and 3D P2 (sphere), at a ladder of sizes set by the
number of elements per contact half-width, plus the three sizes of the peer code's figures
(2D P2 221,946 DOFs; 3D P2 37,620 and 77,583 DOFs).

Each (matrix, solver) pair runs in its own subprocess with a wall-clock limit; the child
reports the factorization time, the time of one solve, the time of a 32-column solve (what
the contact condensation does), the relative residual, the factor size the library reports
and ``ru_maxrss`` after assembling the matrix and at the end (C allocations included).

Usage::

    python benchmarks/linear_solvers.py run [--cases 2d-p2 3d-p1 3d-p2 peer] [--solvers ...]
        [--max-dofs N] [--limit SECONDS] [--out docs/benchmarks]
    python benchmarks/linear_solvers.py report [--out docs/benchmarks]

``run`` appends to ``<out>/linear_solvers.jsonl`` (one JSON object per run; a rerun of a
pair replaces the old record in the report); ``report`` writes ``linear_solvers.csv``,
``linear_solvers.md`` and ``linear_solvers.png``. Set ``OMP_NUM_THREADS=1
MKL_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1`` for one-thread figures.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

#: case -> (builder name, order, ladder of n_per_a, growth)
CASES = {
    "2d-p2": ("hertz_2d", 2, (16, 32, 49.5, 100, 110, 120), 1.15),
    "3d-p1": ("hertz_3d", 1, (8, 12, 16, 20, 24), 1.3),
    "3d-p2": ("hertz_3d", 2, (1.25, 2.0, 3.0, 4.0), 1.3),
}
#: peer figures (one linear solve, seconds, as quoted by the tester): case, n_per_a and growth giving
#: the DOF count closest to the peer's (the 3D meshes come in steps), peer DOFs, peer time, alcontact before
PEER = [
    ("2d-p2", 49.5, 1.15, 221_946, "2.7-3.3 (MUMPS)", "6.8-7.6 (CHOLMOD)"),
    ("3d-p2", 1.25, 1.35, 37_620, "2.6 (MUMPS)", "35.5 (SuperLU + ND)"),
    ("3d-p2", 2.0, 1.3, 77_583, "8-11 (MUMPS)", "271 (SuperLU + ND)"),
]
NRHS = 32


def _maxrss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _cpu_s() -> float:
    """User + system CPU seconds of this process (all threads): robust on a loaded machine."""
    ru = resource.getrusage(resource.RUSAGE_SELF)
    return ru.ru_utime + ru.ru_stime


def _status_mb(key: str) -> float | None:
    """``VmRSS`` / ``VmHWM`` of this process in MB (Linux), None elsewhere."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def _reset_peak() -> bool:
    """Reset the peak RSS (``VmHWM``) so that it measures what follows (Linux >= 4.0)."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


def build(case: str, n_per_a: float, growth: float | None = None):
    """Condensed stiffness ``K_ff``, a right-hand side and the hints of the Hertz problem ``case``."""
    import numpy as np

    from alcontact.fem.elasticity import rigid_body_modes
    from alcontact.linalg import MatrixHints
    from alcontact.problems import hertz

    builder, order, _, default_growth = CASES[case]
    prob = getattr(hertz, builder)(order=order, n_per_a=n_per_a, growth=growth or default_growth)
    model = prob.model
    fixed, _ = prob.dirichlet()
    mask = np.ones(model.ndofs, dtype=bool)
    mask[fixed] = False
    free = np.flatnonzero(mask)
    K = model.stiffness()[free][:, free].tocsr()
    rng = np.random.default_rng(0)
    b = rng.standard_normal(free.size)

    def near_null():
        pts, dofs = model.all_node_dofs()
        modes, _ = rigid_body_modes(pts)
        R = np.zeros((model.ndofs, modes.shape[-1]))
        R[dofs.ravel()] = modes.reshape(-1, modes.shape[-1])
        return np.ascontiguousarray(R[free])

    hints = MatrixHints(dim=model.dim, ordering=lambda: model.ordering(free) if model.dim == 3 else None,
                        near_null=near_null)
    return model, K, b, hints


def one(case: str, n_per_a: float, solver: str, growth: float | None = None) -> dict:
    """Run one (matrix, solver) pair in this process; returns the record."""
    import numpy as np

    from alcontact.linalg import make_solver

    t0 = time.perf_counter()
    model, K, b, hints = build(case, n_per_a, growth)
    t_build = time.perf_counter() - t0
    import gc

    gc.collect()
    rss0 = _maxrss_mb()
    reset = _reset_peak()  # peak RSS from here on = matrix + factor + solve temporaries
    rss_before = _status_mb("VmRSS")
    s = make_solver(solver)
    c0 = _cpu_s()
    t0 = time.perf_counter()
    fac = s.factorize(K, hints)
    t_fac = time.perf_counter() - t0  # includes the ordering (nested dissection for SuperLU in 3D)
    c1 = _cpu_s()
    t0 = time.perf_counter()
    x = fac.solve(b)
    t_solve = time.perf_counter() - t0
    c2 = _cpu_s()
    res = float(np.linalg.norm(K @ x - b) / np.linalg.norm(b))
    rec = dict(case=case, n_per_a=n_per_a, growth=growth or CASES[case][3], solver=solver, dim=model.dim, order=model.order,
               ndofs=int(model.ndofs), nfree=int(K.shape[0]), nnz_K=int(K.nnz), build_s=t_build,
               factor_s=t_fac, solve_s=t_solve, linear_s=t_fac + t_solve, residual=res,
               nnz_factor=int(fac.nnz), factor_mb=(fac.memory_bytes or 0) / 2**20 or None,
               rss_matrix_mb=rss0, threads=os.environ.get("OMP_NUM_THREADS", "?"),
               factor_cpu_s=c1 - c0, solve_cpu_s=c2 - c1, linear_cpu_s=c2 - c0)
    if solver != "amg":  # 32 columns at once (the contact condensation)
        B = np.random.default_rng(1).standard_normal((K.shape[0], NRHS))
        t0 = time.perf_counter()
        fac.solve(B)
        rec["solve32_s"] = time.perf_counter() - t0
    rec["rss_peak_mb"] = _maxrss_mb()
    if reset and rss_before is not None:
        rec["rss_before_mb"] = rss_before
        rec["factor_peak_mb"] = _status_mb("VmHWM") - rss_before  # C allocations included
    return rec


def _sizes(cases):
    """(case, n_per_a) pairs, smallest first (so that an interrupted run keeps the small sizes)."""
    peer = sorted({(c, float(n), g) for c, n, g, *_ in PEER}, key=lambda p: _estimate_dofs(p[0], p[1]))
    pairs = set()
    for case in cases:
        if case != "peer":
            pairs.update((case, float(n), CASES[case][3]) for n in CASES[case][2])
    rest = sorted(pairs - set(peer), key=lambda p: _estimate_dofs(p[0], p[1]))
    return (peer if "peer" in cases else []) + rest  # the peer sizes first


#: rough DOFs per case and n_per_a (measured), to skip sizes above --max-dofs without building them
def _estimate_dofs(case: str, n: float) -> float:
    if case == "2d-p2":
        return 224_238 * (n / 50) ** 2 * 0.95
    if case == "3d-p1":
        return 141_453 * (n / 16) ** 3 * 0.9
    return 77_841 * (n / 2.0) ** 3 * 0.9


def run(args) -> None:
    from alcontact.linalg import available_solvers

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    log = out / "linear_solvers.jsonl"
    solvers = args.solvers or available_solvers()
    failed: dict[tuple[str, str], float] = {}  # (case, solver) -> smallest size that failed: skip larger ones
    for case, n, growth in _sizes(args.cases):
        if _estimate_dofs(case, n) > args.max_dofs or (args.sizes and n not in args.sizes):
            continue
        for solver in solvers:
            if _estimate_dofs(case, n) >= failed.get((case, solver), math.inf):
                continue
            if (solver in ("superlu", "cholmod") and case.startswith("3d")
                    and _estimate_dofs(case, n) > args.slow_3d_max):  # minutes from 60k DOFs on
                continue
            cmd = [sys.executable, __file__, "one", case, str(n), solver, "--growth", str(growth)]
            t0 = time.perf_counter()
            try:
                p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.limit)
                lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
                if p.returncode != 0 or not lines:
                    rec = dict(case=case, n_per_a=n, growth=growth, solver=solver, error=(p.stderr or "")[-400:],
                               returncode=p.returncode)
                    failed[(case, solver)] = min(failed.get((case, solver), math.inf), _estimate_dofs(case, n))
                else:
                    rec = json.loads(lines[-1])
            except subprocess.TimeoutExpired:
                rec = dict(case=case, n_per_a=n, growth=growth, solver=solver, error=f"timeout after {args.limit} s")
                failed[(case, solver)] = min(failed.get((case, solver), math.inf), _estimate_dofs(case, n))
            rec["wall_s"] = time.perf_counter() - t0
            with open(log, "a") as fh:
                fh.write(json.dumps(rec) + "\n")
            print(json.dumps({k: rec.get(k) for k in ("case", "n_per_a", "solver", "ndofs", "factor_s",
                                                     "solve_s", "rss_peak_mb", "error")}), flush=True)


# ---------------------------------------------------------------------- report
def _records(out: Path) -> list[dict]:
    recs: dict[tuple, dict] = {}
    for line in (out / "linear_solvers.jsonl").read_text().splitlines():
        if line.strip():
            r = json.loads(line)
            recs[(r["case"], float(r["n_per_a"]), float(r.get("growth") or CASES[r["case"]][3]), r["solver"])] = r
    return list(recs.values())


def _fit(xs, ys):
    """Least-squares slope of log y against log x (None with fewer than 3 points)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x and y and y > 0]
    if len(pts) < 3:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def _lin(r) -> float:
    """CPU seconds of factorization + one solve (wall seconds for records without CPU times)."""
    return r.get("linear_cpu_s") or r["linear_s"]


def _s(x) -> str:
    return "-" if x is None else f"{x:.2f}"


def _mb(x) -> str:
    return "-" if x is None else f"{x:.0f}"


def report(args) -> None:
    out = Path(args.out)
    recs = [r for r in _records(out) if "error" not in r]
    errs = [r for r in _records(out) if "error" in r]
    recs.sort(key=lambda r: (r["case"], r["ndofs"], r["solver"]))
    keys = ["case", "solver", "n_per_a", "growth", "ndofs", "nfree", "nnz_K", "factor_s", "solve_s", "solve32_s",
            "linear_s", "residual", "nnz_factor", "factor_mb", "factor_peak_mb", "rss_before_mb", "rss_peak_mb",
            "threads"]
    with open(out / "linear_solvers.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in recs:
            w.writerow(r)
    _plot(recs, out / "linear_solvers.png")
    lines = []
    fits = {}
    for case in CASES:
        for solver in sorted({r["solver"] for r in recs}):
            rs = [r for r in recs if r["case"] == case and r["solver"] == solver]
            ft = _fit([r["nfree"] for r in rs], [_lin(r) for r in rs])
            rm = [r for r in rs if r.get("factor_peak_mb")]
            fm = _fit([r["nfree"] for r in rm], [r["factor_peak_mb"] for r in rm])
            if ft is not None:
                fits[(case, solver)] = (ft, fm, len(rs))
    lines.append("| case | solver | DOFs (free) | factor CPU s | 1 solve CPU s | factor wall s | 1 solve wall s | "
                 "32 solves wall s | factor nnz | factor MB (library) | peak RSS of factor + solves MB | residual |")
    lines.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in recs:
        lines.append(
            f"| {r['case']} | {r['solver']} | {r['nfree']:,} | {_s(r.get('factor_cpu_s'))} | "
            f"{_s(r.get('solve_cpu_s'))} | {r['factor_s']:.2f} | {r['solve_s']:.3f} | "
            f"{_s(r.get('solve32_s'))} | {r['nnz_factor']:,} | {_mb(r.get('factor_mb'))} | "
            f"{_mb(r.get('factor_peak_mb'))} | {r['residual']:.1e} |")
    fit_lines = ["| case | solver | runs | time exponent | memory exponent |", "|---|---|---:|---:|---:|"]
    for (case, solver), (ft, fm, k) in sorted(fits.items()):
        fit_lines.append(f"| {case} | {solver} | {k} | {ft:.2f} | {fm:.2f} |" if fm is not None
                         else f"| {case} | {solver} | {k} | {ft:.2f} | - |")
    peer_lines = ["| case | DOFs (ours) | peer DOFs | peer one solve s | alcontact before s | "
                  + " | ".join(f"{s} s" for s in sorted({r['solver'] for r in recs})) + " |"]
    peer_lines.append("|---" * (5 + len({r['solver'] for r in recs})) + "|")
    def same(r, case, n, g):
        return (r["case"] == case and abs(float(r["n_per_a"]) - n) < 1e-9
                and abs(float(r.get("growth") or CASES[case][3]) - g) < 1e-9)

    for case, n, g, dofs, peer_t, before in PEER:
        rs = {r["solver"]: r for r in recs if same(r, case, n, g)}
        if not rs:
            continue
        nd = next(iter(rs.values()))["ndofs"]
        cells = []
        for s in sorted({r["solver"] for r in recs}):
            cells.append(f"{_lin(rs[s]):.2f}" if s in rs else
                         ("timeout" if any(e["solver"] == s and same(e, case, n, g) for e in errs) else "-"))
        peer_lines.append(f"| {case} | {nd:,} | {dofs:,} | {peer_t} | {before} | " + " | ".join(cells) + " |")
    err_lines = [f"- {e['case']} n_per_a={e['n_per_a']} {e['solver']}: {e['error'].strip().splitlines()[-1]}"
                 for e in errs if e.get("error")]
    text = (out / "linear_solvers.md").read_text() if (out / "linear_solvers.md").exists() else ""
    head = text.split("<!-- tables -->")[0] if "<!-- tables -->" in text else (text or "# Linear solvers\n\n")
    body = ["<!-- tables -->", "", "## Peer comparison (one linear solve = factorization + one solve, CPU s)", "",
            *peer_lines, "", "## All runs", "", *lines, "", "## Fitted exponents (time and memory ~ DOFs^k)", "",
            *fit_lines, "", "![time and memory against DOFs](linear_solvers.png)", ""]
    if err_lines:
        body += ["## Runs that did not finish", "", *err_lines, ""]
    (out / "linear_solvers.md").write_text(head + "\n".join(body))


def _plot(recs, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    markers = {"2d-p2": "o", "3d-p1": "s", "3d-p2": "^"}
    colors = {}
    for r in recs:
        colors.setdefault(r["solver"], f"C{len(colors)}")
    for case in CASES:
        for solver, c in colors.items():
            rs = sorted((r for r in recs if r["case"] == case and r["solver"] == solver), key=lambda r: r["nfree"])
            if not rs:
                continue
            x = [r["nfree"] for r in rs]
            axes[0].loglog(x, [_lin(r) for r in rs], marker=markers[case], color=c, label=f"{case} {solver}")
            rm = [r for r in rs if r.get("factor_peak_mb")]
            if rm:
                axes[1].loglog([r["nfree"] for r in rm], [max(r["factor_peak_mb"], 1.0) for r in rm],
                               marker=markers[case], color=c, label=f"{case} {solver}")
    axes[0].set(xlabel="free DOFs", ylabel="factorization + one solve [CPU s]", title="time (1 thread)")
    axes[1].set(xlabel="free DOFs", ylabel="peak RSS of factorization + solves [MB]", title="memory")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--cases", nargs="+", default=["peer", "2d-p2", "3d-p1", "3d-p2"])
    r.add_argument("--solvers", nargs="+")
    r.add_argument("--max-dofs", type=float, default=1.2e6)
    r.add_argument("--sizes", nargs="+", type=float, help="only these n_per_a values")
    r.add_argument("--slow-3d-max", type=float, default=6e4)
    r.add_argument("--limit", type=float, default=300.0)
    r.add_argument("--out", default="docs/benchmarks")
    o = sub.add_parser("one")
    o.add_argument("case")
    o.add_argument("n_per_a", type=float)
    o.add_argument("solver")
    o.add_argument("--growth", type=float)
    p = sub.add_parser("report")
    p.add_argument("--out", default="docs/benchmarks")
    args = ap.parse_args(argv)
    if args.cmd == "one":
        print(json.dumps(one(args.case, args.n_per_a, args.solver, args.growth)), flush=True)
    elif args.cmd == "run":
        run(args)
    else:
        report(args)


if __name__ == "__main__":
    main()
