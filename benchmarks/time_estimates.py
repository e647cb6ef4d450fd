"""Calibrate the run-time estimates of ``alcontact check`` and ``alcontact bench --quick``.

``alcontact check FILE`` prints how long ``alcontact run FILE`` will take. Its model
(:func:`alcontact.io.preflight.run_seconds`) is the solver's cost model of
:mod:`alcontact.io.preflight` (factorizations, AMG, finite-deformation Newton iterations,
which dominates large meshes) plus terms for what a small run spends outside the linear
algebra, fitted here on the problem files of ``examples/`` (and the mesh of
``examples/gmsh_punch.py``):

.. math::

    t = a + S\\,(b + b_f\\,[\\text{friction}] + b_F\\,[\\text{finite}]) + c\\,n\\,S + t_{solver}

with :math:`S` load steps and :math:`n` DOFs: :math:`a` interpreter start, imports, mesh,
plots and pictures; :math:`b` per step (solve set-up, the step's VTU); :math:`b_f`, :math:`b_F`
the extra per frictional / finite-deformation step; :math:`c` per DOF and step. The fit
minimizes the relative error (least squares on :math:`t_{model}/t - 1`, non-negative
coefficients). Each example is timed as a user runs it: ``alcontact run FILE --out DIR -q``
in a fresh process, the best of ``--repeats`` runs (the machines are shared).

``--bench`` also times ``alcontact bench --quick`` per suite (read from ``bench.md``).

``--add FILE`` times one more problem file and adds (or replaces) its row with the committed
coefficients (no refit); its time is normalized to the calibration's conditions by
``hertz_2d.toml`` timed in the same run (raw time x committed / same-run time of hertz_2d); the
report lists it apart with the raw times.

Writes ``src/alcontact/io/time_calibration.json`` (the coefficients and the machine they were
measured on, read by :mod:`alcontact.io.preflight` and :func:`alcontact.runner.quick_bench_seconds`),
``docs/benchmarks/time_estimates.csv`` and ``docs/benchmarks/time_estimates.md`` (estimate
against measured per example, the ratio, and the machine).

Usage::

    python benchmarks/time_estimates.py [--repeats 2] [--bench] [--out docs/benchmarks]
    python benchmarks/time_estimates.py --add examples/two_cylinders.toml
"""

from __future__ import annotations

import argparse
import csv
import datetime as _dt
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from alcontact.io.preflight import this_machine

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
CALIBRATION = ROOT / "src" / "alcontact" / "io" / "time_calibration.json"
ENV = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def machine() -> dict:
    """This machine's kind (:func:`alcontact.io.preflight.this_machine`) and the Python version."""
    return {**this_machine(), "python": platform.python_version()}


def problem_files(tmp: Path) -> list[Path]:
    """The example problem files, plus the Gmsh punch written by examples/gmsh_punch.py."""
    files = sorted(EXAMPLES.glob("*.toml"))
    subprocess.run([sys.executable, str(EXAMPLES / "gmsh_punch.py"), "--out", str(tmp / "punch")], check=True,
                   env=ENV, capture_output=True)
    return files + [tmp / "punch" / "punch.toml"]


def features(path: Path) -> dict:
    from alcontact.io.preflight import check_problem, run_features

    pre = check_problem(path)
    return {"file": path.name, **run_features(pre.setup, pre.size)}


def time_run(path: Path, tmp: Path, repeats: int) -> float:
    best = np.inf
    exe = Path(sys.executable).with_name("alcontact")
    for k in range(repeats):
        out = tmp / f"run-{path.stem}-{k}"
        t0 = time.perf_counter()
        subprocess.run([str(exe), "run", str(path), "--out", str(out), "--force", "-q"], env=ENV, check=False,
                       capture_output=True)
        best = min(best, time.perf_counter() - t0)
    return float(best)


def add_file(path: Path, repeats: int, out: Path) -> int:
    """``--add``: time ``path`` and add its row to the committed calibration with the committed coefficients.

    The wall time of ``alcontact run FILE`` as for the other rows (best of ``repeats``), normalized to the
    calibration's conditions by ``hertz_2d.toml`` timed in the same run: ``measured_s = raw * committed /
    now`` of hertz_2d (the machine's load changes both alike); the row keeps ``measured_raw_s``."""
    from alcontact.io.preflight import check_problem

    cal = json.loads(CALIBRATION.read_text())
    ref = EXAMPLES / "hertz_2d.toml"
    with tempfile.TemporaryDirectory() as td:
        row = features(path)
        times = [(time_run(path, Path(td), 1), time_run(ref, Path(td), 1)) for _ in range(repeats)]  # interleaved
        row["measured_s"] = min(t for t, _ in times)
        ref_s = min(t for _, t in times)
    row["estimate_s"] = float(check_problem(path).run_seconds)  # the committed coefficients
    ref_old = next(r["measured_s"] for r in cal["examples"] if r["file"] == ref.name)
    row["measured_raw_s"] = row["measured_s"]
    row["measured_s"] = row["measured_raw_s"] * ref_old / ref_s
    cal["examples"] = [r for r in cal["examples"] if r["file"] != row["file"]] + [row]
    CALIBRATION.write_text(json.dumps(cal, indent=1) + "\n")
    ratio = row["estimate_s"] / row["measured_s"]
    line = (f"| {row['file']} | {row['ndofs']} | {row['steps']} | {'yes' if row['friction'] else ''} | "
            f"{'yes' if row['finite'] else ''} | {row['estimate_s']:.2f} | {row['measured_s']:.2f} | {ratio:.2f} | "
            f"{row['measured_raw_s']:.2f} | {ref_s:.2f} (committed {ref_old:.2f}) |")
    md = out / "time_estimates.md"
    text = md.read_text() if md.is_file() else ""
    head = "## Added with `--add` (committed coefficients, not refitted)"
    lines = [x for x in text.splitlines() if not x.startswith(f"| {row['file']} |")]
    if head not in lines:
        lines += ["", head, "", "measured = raw x (committed / same-run time of hertz_2d.toml, runs interleaved, "
                  "best of each): the run in the calibration's conditions.", "",
                  "| problem file | DOFs | steps | friction | finite | estimate (s) | measured (s) | "
                  "estimate / measured | measured, raw (s) | hertz_2d.toml in the same run (s) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
    lines.append(line)
    md.write_text("\n".join(lines) + "\n")
    print(line)
    return 0


def design(rows: list[dict]) -> np.ndarray:
    """Columns of the fitted terms: 1, S, S [friction], S [finite], n S."""
    return np.array([[1.0, r["steps"], r["steps"] * r["friction"], r["steps"] * r["finite"],
                      r["ndofs"] * r["steps"]] for r in rows])


def fit(rows: list[dict]) -> dict:
    from scipy.optimize import nnls

    A = design(rows)
    t = np.array([r["measured_s"] for r in rows])
    solver = np.array([r["solver_s"] for r in rows])
    # relative least squares: (A x + solver) / t - 1 -> rows scaled by 1/t
    x, _ = nnls(A / t[:, None], 1.0 - solver / t)
    names = ("fixed_s", "per_step_s", "per_friction_step_s", "per_finite_step_s", "per_dof_step_s")
    return dict(zip(names, map(float, x)))


def time_bench(tmp: Path) -> dict:
    exe = Path(sys.executable).with_name("alcontact")
    out = tmp / "bench"
    t0 = time.perf_counter()
    subprocess.run([str(exe), "bench", "--quick", "--out", str(out)], env=ENV, check=True, capture_output=True)
    total = time.perf_counter() - t0
    text = (out / "bench.md").read_text()
    suites = {m.group(1): float(m.group(2)) for m in re.finditer(r"<!-- (\w+): ([0-9.]+) s -->", text)}
    return {"total_s": total, "suites_s": suites}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--bench", action="store_true", help="also time `alcontact bench --quick`")
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks")
    ap.add_argument("--add", type=Path, default=None, help="time one more problem file and add its row (committed "
                                                           "coefficients)")
    args = ap.parse_args(argv)
    if args.add is not None:
        return add_file(args.add, args.repeats, args.out)

    old = json.loads(CALIBRATION.read_text()) if CALIBRATION.is_file() else {}
    with tempfile.TemporaryDirectory() as td:
        tmp = Path(td)
        rows = []
        for path in problem_files(tmp):
            row = features(path)
            row["measured_s"] = time_run(path, tmp, args.repeats)
            rows.append(row)
            print(f"{row['file']:32s} {row['ndofs']:7d} DOFs {row['steps']:3d} steps  {row['measured_s']:6.2f} s",
                  flush=True)
        bench = time_bench(tmp) if args.bench else old.get("bench_quick")
    coef = fit(rows)
    A = design(rows)
    for r, a in zip(rows, A):
        r["estimate_s"] = float(a @ np.array(list(coef.values())) + r["solver_s"])
        r["ratio"] = r["estimate_s"] / r["measured_s"]
    cal = {
        "about": "written by benchmarks/time_estimates.py; read by alcontact.io.preflight.run_seconds",
        "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "machine": machine(),
        "run": coef,
        "bench_quick": bench,
        "examples": [{k: r[k] for k in ("file", "ndofs", "steps", "friction", "finite", "solver_s", "measured_s",
                                        "estimate_s")} for r in rows],
    }
    CALIBRATION.write_text(json.dumps(cal, indent=1) + "\n")
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "time_estimates.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(cal["examples"][0]) + ["ratio"])
        w.writeheader()
        for r in rows:
            w.writerow({k: r[k] for k in w.fieldnames})
    m = cal["machine"]
    lines = ["# Run-time estimates of `alcontact check` and `alcontact bench --quick`", "",
             f"Measured {cal['date']} on {m['cpu']}, {m['cores']} cores, Python {m['python']} "
             "(`python benchmarks/time_estimates.py`; each file run as `alcontact run FILE -q` in a fresh "
             f"process, best of {args.repeats}; other jobs shared the machine).", "",
             "Model: t = a + S (b + b_f [friction] + b_F [finite]) + c n S + t_solver "
             "(t_solver: the solver cost model of `alcontact.io.preflight`). Fitted: "
             + ", ".join(f"{k} = {v:.3g}" for k, v in coef.items()) + ".", "",
             "| problem file | DOFs | steps | friction | finite | estimate (s) | measured (s) | estimate / measured |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['file']} | {r['ndofs']} | {r['steps']} | {'yes' if r['friction'] else ''} | "
                     f"{'yes' if r['finite'] else ''} | {r['estimate_s']:.2f} | {r['measured_s']:.2f} | "
                     f"{r['ratio']:.2f} |")
    ratios = np.array([r["ratio"] for r in rows])
    lines += ["", f"Estimate / measured: {ratios.min():.2f} to {ratios.max():.2f} (target: within 0.5 to 2).", ""]
    if bench:
        lines += ["## `alcontact bench --quick`", "",
                  f"Total {bench['total_s']:.1f} s; per suite: "
                  + ", ".join(f"{k} {v:.1f} s" for k, v in bench["suites_s"].items()) + ".", ""]
    (args.out / "time_estimates.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
