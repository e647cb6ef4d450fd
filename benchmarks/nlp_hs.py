"""Nonlinear-programming benchmark on the Hock-Schittkowski selection.

Runs every augmented Lagrangian penalty of :mod:`alcontact.optim` (and the classical
exterior penalty method), plus SciPy's SLSQP and trust-constr, in the same process on
every problem of :mod:`alcontact.problems.hock_schittkowski`, from the collection's
starting points. Writes

- ``<out>/nlp_hs.csv``: one row per problem x solver (solved, f, |f - f*|, feasibility,
  outer/inner iterations, evaluations, wall time, status, message);
- ``<out>/nlp_hs.md``: one summary row per solver (solved count, median iterations and
  evaluations, total/median wall time) and the list of failures.

"Solved" means ``|f - f*| <= 1e-6 max(1, |f*|)`` and maximal violation ``<= 1e-6``.
Wall times are only comparable within one run (shared, noisy machines).

Usage::

    python benchmarks/nlp_hs.py [--out DIR] [--variants NAME ...]

Variant names: an AL penalty (``exp-met1``, ``rockafellar``, ...), a classical method
(``exterior-penalty``, ``barrier``) or ``SLSQP`` / ``trust-constr`` (SciPy).
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import os
import statistics
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import minimize as scipy_minimize

from alcontact.problems import hock_schittkowski as hs

AL_PENALTIES = ["rockafellar", "exp-met1", "exp-met2", "log-met1", "log-met2", "quad-met1", "quad-met2"]
CLASSICAL = ["exterior-penalty", "barrier"]
SCIPY = ["SLSQP", "trust-constr"]
DEFAULT_VARIANTS = AL_PENALTIES + ["exterior-penalty"] + SCIPY

_SCIPY_OPTIONS = {
    "SLSQP": dict(maxiter=1000, ftol=1e-12),
    # tight tolerances: with the defaults trust-constr stops at ~1e-5 relative accuracy
    "trust-constr": dict(maxiter=3000, gtol=1e-12, xtol=1e-14, barrier_tol=1e-12),
}

FIELDS = [
    "problem", "n", "solver", "solved", "f", "f_star", "abs_err", "feasibility",
    "outer_iterations", "inner_iterations", "nfev", "njev", "nhev", "wall_s", "status", "message",
]  # fmt: skip


def _count(res, name):
    value = getattr(res, name, None)
    if value is None and hasattr(res, "get"):
        value = res.get(name)
    return "" if value is None else int(value)


def _run_one(p: hs.HSProblem, variant: str) -> dict:
    row = {"problem": p.name, "n": p.n, "solver": variant, "f_star": p.f_star}
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if variant in SCIPY:
                kw = p.minimize_kwargs(with_hess=variant != "SLSQP")
                res = scipy_minimize(**kw, method=variant, options=_SCIPY_OPTIONS[variant])
                inner = ""
            else:
                from alcontact.optim import minimize

                if variant in CLASSICAL:
                    res = minimize(**p.minimize_kwargs(), method=variant)
                else:
                    res = minimize(**p.minimize_kwargs(), method="al", penalty=variant)
                inner = _count(res, "nit_inner")
    except Exception as exc:  # one crashing problem must not abort the benchmark
        row.update(
            solved=False, f=math.nan, abs_err=math.nan, feasibility=math.nan,
            outer_iterations="", inner_iterations="", nfev="", njev="", nhev="",
            wall_s=time.perf_counter() - start, status="exception",
            message=f"{type(exc).__name__}: {exc}"[:200],
        )  # fmt: skip
        return row
    wall = time.perf_counter() - start
    x, f = np.asarray(res.x, float), float(res.fun)
    row.update(
        solved=p.is_solved(f, x),
        f=f,
        abs_err=abs(f - p.f_star),
        feasibility=p.max_violation(x),
        outer_iterations=_count(res, "nit"),
        inner_iterations=inner,
        nfev=_count(res, "nfev"),
        njev=_count(res, "njev"),
        nhev=_count(res, "nhev"),
        wall_s=wall,
        status=str(getattr(res, "status", "")),
        message=" ".join(str(getattr(res, "message", "")).split())[:200],
    )
    return row


def _median(rows, key):
    vals = [r[key] for r in rows if r[key] != "" and not (isinstance(r[key], float) and math.isnan(r[key]))]
    return statistics.median(vals) if vals else math.nan


def _fmt(v, digits=1):
    if isinstance(v, float) and math.isnan(v):
        return "-"
    return f"{v:.{digits}f}" if isinstance(v, float) else str(v)


def _markdown(rows, variants, n_problems) -> str:
    out = io.StringIO()
    out.write("# Hock-Schittkowski benchmark\n\n")
    out.write(
        f"{n_problems} problems with inequality constraints, collection starting points. "
        "Solved: |f - f*| <= 1e-6 max(1, |f*|) and max violation <= 1e-6. Medians over all "
        "problems; wall times comparable within this run only.\n\n"
    )
    out.write(
        "| solver | solved | median outer it. | median inner it. | median nfev | median njev "
        "| median nhev | total wall [s] | median wall [ms] |\n"
    )
    out.write("|---|---|---|---|---|---|---|---|---|\n")
    for v in variants:
        rs = [r for r in rows if r["solver"] == v]
        solved = sum(bool(r["solved"]) for r in rs)
        total_wall = sum(r["wall_s"] for r in rs)
        out.write(
            f"| {v} | {solved}/{len(rs)} | {_fmt(_median(rs, 'outer_iterations'))} "
            f"| {_fmt(_median(rs, 'inner_iterations'))} | {_fmt(_median(rs, 'nfev'))} "
            f"| {_fmt(_median(rs, 'njev'))} | {_fmt(_median(rs, 'nhev'))} | {total_wall:.2f} "
            f"| {1e3 * _median(rs, 'wall_s'):.1f} |\n"
        )
    out.write("\n## Failures\n\n")
    for v in variants:
        bad = [r for r in rows if r["solver"] == v and not r["solved"]]
        out.write(f"- **{v}** ({len(bad)}): ")
        out.write(", ".join(f"{r['problem']} ({_describe_failure(r)})" for r in bad) or "none")
        out.write("\n")
    return out.getvalue()


def _describe_failure(r) -> str:
    if r["status"] == "exception":
        return r["message"][:60]
    return f"f={r['f']:.6g}, viol={r['feasibility']:.1e}"


def _write_atomic(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", newline="") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def run(out_dir=None, variants=None) -> Path:
    """Run the benchmark; return the path of the CSV file (the markdown lies beside it)."""
    out = Path(out_dir) if out_dir is not None else Path(__file__).resolve().parent / "out"
    out.mkdir(parents=True, exist_ok=True)
    variants = list(variants) if variants else list(DEFAULT_VARIANTS)
    problems = hs.problems()
    rows = [_run_one(p, v) for v in variants for p in problems]

    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=FIELDS)
    writer.writeheader()
    for r in rows:
        writer.writerow({k: (f"{r[k]:.12g}" if isinstance(r[k], float) else r[k]) for k in FIELDS})
    csv_path = out / "nlp_hs.csv"
    _write_atomic(csv_path, buf.getvalue())
    _write_atomic(out / "nlp_hs.md", _markdown(rows, variants, len(problems)))
    return csv_path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=None, help="output folder (default: benchmarks/out)")
    parser.add_argument(
        "--variants", nargs="+", default=None, help=f"solvers to run (default: {' '.join(DEFAULT_VARIANTS)})"
    )
    args = parser.parse_args(argv)
    path = run(args.out, args.variants)
    print(path.with_suffix(".md").read_text())
    print(f"wrote {path} and {path.with_suffix('.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
