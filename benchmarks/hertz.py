"""Hertz contact benchmark: every frictionless algorithm and penalty, several mesh sizes.

For each case (:data:`CASES`: the 2D cylinder ladder of issue 11 from 10k to 984k DOFs,
:data:`LADDER_2D`; the 3D sphere on the direct path at 78k P2, 111k and 243k P1 DOFs; 3D
on the AMG path) and each algorithm/penalty the script records outer iterations, Newton
iterations, linear solves (triangular solve pairs with the one stiffness factor), CPU and
wall time, peak memory, and the ratio of the contact solve to one linear elastic solve of
the same mesh (a fresh factorization + one solve with the same solver,
:func:`plain_linear_solve`) measured in the same run, plus the accuracy against Hertz.
Writes ``<out>/hertz.csv``, ``<out>/hertz.md`` (the text above ``<!-- tables -->`` is kept) and
``<out>/hertz.png`` (log-log ratio, CPU time and peak memory against DOFs: the 2D ladder with
fitted exponents, the 3D direct-path cases as open markers).

Every case runs in its own process (``--in-process`` runs them in this one): the peak memory of
each linear and contact solve is the peak resident set size (``VmHWM``, reset through
``/proc/self/clear_refs`` before each measured solve) and one case's allocations do not carry
over into the next.

Loadings (issue 21): a case ``NAME:DRIVE`` runs the mesh of ``NAME`` with what moves the block into
contact chosen from :data:`alcontact.problems.hertz.DRIVES` (``obstacle``, the default; ``platen``: a
prescribed displacement of the bottom; ``force``: a body force; ``pressure``: a pressure on a body held
by the obstacle; ``mix``); ``--drives`` runs every chosen case with each of them. The contact solve
should cost the same whatever the drive.

Usage::

    python benchmarks/hertz.py [--out DIR] [--cases 2d-10k 2d-100k:platen ...] [--variants ssn simo-laursen ...]
        [--drives obstacle platen force pressure mix] [--issue-variants] [--merge] [--repeats N] [--in-process]
    python benchmarks/hertz.py --report --out DIR

Timings are ratios within one run; machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import io
import logging
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

from alcontact.contact import solve
from alcontact.io.results import write_text_atomic
from alcontact.problems import hertz

#: name -> (builder, keyword arguments)
CASES = {
    "2d-10k": (hertz.hertz_2d, dict(n_per_a=32, growth=1.15)),
    "2d-28k": (hertz.hertz_2d, dict(n_per_a=64, growth=1.15)),
    "2d-84k": (hertz.hertz_2d, dict(n_per_a=128, growth=1.15)),
    "2d-277k": (hertz.hertz_2d, dict(n_per_a=256, growth=1.15)),
    "2d-984k": (hertz.hertz_2d, dict(n_per_a=512, growth=1.15)),
    "2d-100k": (hertz.hertz_2d, dict(n_per_a=64, growth=1.02)),
    "2d-500k": (hertz.hertz_2d, dict(n_per_a=128, growth=1.01)),
    "3d-100k": (hertz.hertz_3d, dict(n_per_a=6, growth=1.07)),
    "3d-100k-direct": (hertz.hertz_3d, dict(n_per_a=6, growth=1.07)),  # condensed path, Schur build
    "3d-1M": (hertz.hertz_3d, dict(n_per_a=16, growth=1.04)),
    "3d-p2-78k-direct": (hertz.hertz_3d, dict(order=2, n_per_a=2.0, growth=1.3)),  # the peer's 3D P2 size
    "3d-243k-direct": (hertz.hertz_3d, dict(n_per_a=9, growth=1.07)),  # 243,000 DOFs, a factor of a few GB
    "3d-187k-direct": (hertz.hertz_3d, dict(n_per_a=8, growth=1.07)),  # 186,591 DOFs, a factor below 3 GB
    "3d-304k-direct": (hertz.hertz_3d, dict(n_per_a=10.5, growth=1.07)),  # 304,128 DOFs: issue 21's "to 300k in 3D"
    # issue 21: a P2 half disc on a plane (the peer's 2D benchmark geometry, our own mesh, 224,202 DOFs),
    # driven by a platen or by the plane (NAME:platen, NAME:obstacle)
    "2d-p2-disc-222k": (hertz.hertz_disc, dict(n=118)),
}
DEFAULT_CASES = ["2d-10k", "2d-100k", "2d-500k", "3d-100k"]
#: the 2D ladder of issue 11 (10k to 1M DOFs)
LADDER_2D = ["2d-10k", "2d-28k", "2d-84k", "2d-100k", "2d-277k", "2d-500k", "2d-984k"]
#: contact options per case: the 3D 1M-DOF factor (~30 GB) does not fit in memory, so that
#: case runs the factorization-free AMG path ("auto" would choose it too; stated explicitly)
CASE_OPTIONS = {"3d-1M": {"linear_solver": "amg"},
                "3d-100k-direct": {"linear_solver": "mkl-pardiso"},
                "3d-p2-78k-direct": {"linear_solver": "mkl-pardiso"},
                "3d-243k-direct": {"linear_solver": "mkl-pardiso"},
                "3d-187k-direct": {"linear_solver": "mkl-pardiso"},
                "3d-304k-direct": {"linear_solver": "mkl-pardiso"}}

#: (label, algorithm, penalty, extra options)
VARIANTS = [
    ("ssn", "ssn", None, {}),
    ("penalty", "penalty", None, {}),
    ("simo-laursen", "simo-laursen", None, {}),
    ("exp-met1", "family-p", "exp-met1", {}),
    ("exp-met2", "family-p", "exp-met2", {}),
    ("log-met1", "family-p", "log-met1", {}),
    ("log-met2", "family-p", "log-met2", {}),
    ("quad-met2", "family-p", "quad-met2", {}),
    ("rockafellar", "family-p", "rockafellar", {}),
    ("exp-met1/fixed-eta", "family-p", "exp-met1", {"eta_scaling": "fixed"}),
    ("log-met2/fixed-eta", "family-p", "log-met2", {"eta_scaling": "fixed"}),
]

#: the variants of issue 11 (every algorithm; family-p with the penalties of each kind)
ISSUE_VARIANTS = ["ssn", "penalty", "simo-laursen", "exp-met1", "log-met2", "quad-met2", "rockafellar"]
#: small models are timed several times and the fastest run kept (numerator and denominator alike):
#: repeats = min(MAX_REPEATS, REPEAT_BUDGET_S / one linear solve), at least 1; with repeats, every
#: variant's contact solves alternate with as many linear solves (both see the same machine load)
MAX_REPEATS = 10
REPEAT_BUDGET_S = 2.0

def case_spec(case: str):
    """Builder and keyword arguments of ``case`` (``NAME`` of :data:`CASES` or ``NAME:DRIVE``), and its options."""
    name, _, drive = case.partition(":")
    drives = hertz.DISC_DRIVES if CASES.get(name, (None,))[0] is hertz.hertz_disc else hertz.DRIVES
    if name not in CASES or (drive and drive not in drives):
        raise argparse.ArgumentTypeError(f"unknown case {case!r}: use NAME or NAME:DRIVE with NAME one of "
                                         f"{', '.join(CASES)} and DRIVE one of {', '.join(hertz.DRIVES)}")
    builder, kw = CASES[name]
    return builder, ({**kw, "drive": drive} if drive else kw), CASE_OPTIONS.get(name, {})


def _case_arg(case: str) -> str:
    case_spec(case)
    return case


FIELDS = ["case", "dofs", "candidates", "variant", "algorithm", "penalty", "status", "outer_iterations",
          "newton_iterations", "linear_solves", "factorizations", "cg_iterations", "wall_s", "linear_solve_s", "plain_linear_s",
          "ratio", "cpu_s", "plain_linear_cpu_s", "ratio_cpu", "repeats", "a_err_pct", "p0_err_pct",
          "penetration_over_h", "peak_rss_mb", "base_rss_mb", "plain_linear_peak_rss_mb",
          "plain_linear_base_rss_mb", "model_rss_mb", "ratio_rss", "schur_prediction", "prediction_cg_iterations",
          "prediction_s"]

_CLEAR_REFS = Path("/proc/self/clear_refs")


def _trim_heap() -> None:
    """Collect garbage and hand the C heap's free pages back to the system (glibc ``malloc_trim(0)``).

    Without it the memory a finished solve freed stays resident in the heap, and the next
    solve's "before" RSS counts it: the solve memory (peak - before) then reads low.
    """
    import ctypes
    import ctypes.util
    import gc

    gc.collect()
    try:
        ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):  # not glibc: nothing to trim
        pass


def reset_peak_rss() -> bool:
    """Reset the kernel's peak resident set size of this process (``VmHWM``) to the current one.

    The heap is trimmed first (:func:`_trim_heap`), so the current RSS is the live memory.
    Linux only (``echo 5 > /proc/self/clear_refs``); False where that is not possible, and then
    :func:`peak_rss_mb` is the peak since the process started.
    """
    _trim_heap()
    try:
        _CLEAR_REFS.write_text("5")
    except OSError:
        return False
    return True


def _status_mb(key: str) -> float:
    """``VmRSS`` / ``VmHWM`` of this process in MiB from ``/proc/self/status`` (NaN where it is missing)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return math.nan


def rss_mb() -> float:
    """Current resident set size of this process in MiB (NaN where ``/proc`` is missing)."""
    return _status_mb("VmRSS")


def peak_rss_mb() -> float:
    """Peak resident set size of this process in MiB since the last :func:`reset_peak_rss` (NaN if unknown)."""
    peak = _status_mb("VmHWM")
    if not math.isnan(peak):
        return peak
    try:
        import resource
    except ImportError:
        return math.nan
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


@dataclasses.dataclass(frozen=True, order=True)
class Timing:
    """Wall and CPU seconds (user + system of this process) and peak RSS (MiB) of one measurement; ordered by CPU."""

    cpu: float
    wall: float
    rss_mb: float = dataclasses.field(compare=False)
    base_rss_mb: float = dataclasses.field(compare=False)

    def __init__(self, wall: float, cpu: float, rss_mb: float = math.nan, base_rss_mb: float = math.nan):
        object.__setattr__(self, "cpu", cpu)
        object.__setattr__(self, "wall", wall)
        object.__setattr__(self, "rss_mb", rss_mb)
        object.__setattr__(self, "base_rss_mb", base_rss_mb)


def linear_reference(prob):
    """The problem whose linear solve is the denominator: ``prob``, except for a body held only by the
    obstacle (drive ``pressure``: its stiffness alone is singular), which gets the bottom of the
    obstacle drive (all components fixed): the same mesh, matrix size and solver."""
    if prob.meta.get("drive") != "pressure":
        return prob
    from alcontact.contact import Support

    return dataclasses.replace(prob, supports=(Support("bottom"),) + tuple(s for s in prob.supports
                                                                          if s.boundary != "bottom"), loads=())


def plain_linear_solve(prob, linear_solver="auto") -> Timing:
    """Wall and CPU seconds of one linear elastic solve of ``prob``'s mesh: a fresh factorization + one solve.

    The same solver as the contact solve (``"auto"`` resolved as the contact solve does: AMG
    for large 3D models, else the fast direct one), no Schur block, no reuse: this is the
    "one linear solve" the contact solve is compared with.
    """
    from alcontact.linalg import select_solver

    prob = linear_reference(prob)
    model = prob.model
    fixed, values = prob.dirichlet()
    backend = select_solver(linear_solver, dim=model.dim, ndofs=model.ndofs).name  # what the contact solve runs
    model.clear_factorization()
    reset_peak_rss()
    base = rss_mb()
    c0, t0 = time.process_time(), time.perf_counter()
    fac = model.factorize(fixed, backend=backend, reuse=False)
    fac.solve_full(prob.load_vector(), values)
    timing = Timing(time.perf_counter() - t0, time.process_time() - c0, peak_rss_mb(), base)
    del fac
    model.clear_factorization()
    return timing


def _row(case, label, prob, sol, plain: Timing, timing: Timing, repeats=1, model_rss=math.nan):
    ref = prob.reference
    P = ref.load(sol.normal_force)
    a = sol.contact_half_width(axis=0, center=prob.meta["center"])
    r = sol.result
    t = sol.timings
    return {
        "case": case, "dofs": prob.model.ndofs, "candidates": sol.extra["candidates"], "variant": label,
        "algorithm": r.algorithm, "penalty": r.penalty, "status": r.status.label,
        "outer_iterations": r.outer_iterations, "newton_iterations": r.newton_iterations,
        "linear_solves": r.linear_solves, "factorizations": r.factorizations,
        "cg_iterations": sol.extra.get("cg_iterations", ""),
        "wall_s": round(timing.wall, 4),
        "linear_solve_s": round(t["linear_solve_s"], 4), "plain_linear_s": round(plain.wall, 4),
        "ratio": round(timing.wall / plain.wall, 3), "cpu_s": round(timing.cpu, 4),
        "plain_linear_cpu_s": round(plain.cpu, 4), "ratio_cpu": round(timing.cpu / plain.cpu, 3), "repeats": repeats,
        "a_err_pct": round(100 * (a / ref.half_width(P) - 1), 3) if P > 0 else "",
        "p0_err_pct": round(100 * (sol.peak_pressure / ref.peak_pressure(P) - 1), 3) if P > 0 else "",
        "penetration_over_h": f"{r.penetration:.2e}",
        "peak_rss_mb": round(timing.rss_mb, 1), "base_rss_mb": round(timing.base_rss_mb, 1),
        "plain_linear_peak_rss_mb": round(plain.rss_mb, 1), "plain_linear_base_rss_mb": round(plain.base_rss_mb, 1),
        "model_rss_mb": round(model_rss, 1),
        "ratio_rss": round(timing.rss_mb / plain.rss_mb, 3),
        "schur_prediction": sol.extra.get("schur_prediction", ""),
        "prediction_cg_iterations": sol.extra.get("prediction_cg_iterations", ""),
        "prediction_s": round(t["prediction_s"], 4) if "prediction_s" in t else "",
    }


def _markdown(rows):
    out = ["## Runs", "",
           "Contact solve time over one linear elastic solve (a fresh factorization + one solve with the same "
           "solver, no Schur block) of the same mesh, measured in the same run, in CPU seconds of the process "
           "(user + system, one MKL thread: what a quiet machine takes) and in wall seconds (the smallest of the "
           "measurements before and after the variants; small models are timed `repeats` times in round robin "
           "(each round: every variant, then a linear solve), and the fastest run of each kept, numerator and "
           "denominator alike). "
           "Iterations: outer / Newton; solves: triangular solve pairs with the single stiffness factorization "
           "(the Delassus operator comes from the Schur complement with MKL PARDISO and costs none).", ""]
    for case in dict.fromkeys(r["case"] for r in rows):
        sub = [r for r in rows if r["case"] == case]
        out += [f"### {case} ({sub[0]['dofs']} DOFs, {sub[0]['candidates']} contact candidates)", "",
                f"one linear solve: {sub[0]['plain_linear_cpu_s']} s CPU, {sub[0]['plain_linear_s']} s wall "
                f"(fastest of {sub[0].get('repeats') or 1} before and {sub[0].get('repeats') or 1} after), "
                f"peak RSS {sub[0].get('plain_linear_peak_rss_mb') or '-'} MiB", "",
                "| variant | status | outer | Newton | solves | factorizations | Schur block from (CG its, wall s) | "
                "CPU s | contact/linear (CPU) | wall s | contact/linear (wall) | peak RSS MiB | a err % | p0 err % |",
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in sub:
            pred = r.get("schur_prediction") or "-"
            if pred == "rough solve":
                pred += f" ({r.get('prediction_cg_iterations')}, {r.get('prediction_s')})"
            out.append(f"| {r['variant']} | {r['status']} | {r['outer_iterations']} | {r['newton_iterations']} | "
                       f"{r['linear_solves']} | {r.get('factorizations') or '-'} | {pred} | {r['cpu_s']} | {r['ratio_cpu']} | "
                       f"{r['wall_s']} | {r['ratio']} | {r.get('peak_rss_mb') or '-'} | {r['a_err_pct']} | {r['p0_err_pct']} |")
        if any(r["cg_iterations"] not in ("", None) for r in sub):
            out += ["", "No factorization (linear_solver='amg'): solves are AMG-preconditioned CG solves, CG "
                    "iterations " + ", ".join(f"{r['variant']} {r['cg_iterations']}" for r in sub) + "; the "
                    "linear solve is the AMG setup plus one CG solve to 1e-10."]
        ratios = [float(r["ratio_cpu"]) for r in sub]
        out += ["", f"contact/linear (CPU): median {statistics.median(ratios):.2f}, max {max(ratios):.2f}", ""]
    return "\n".join(out) + "\n"


def _fit(xs, ys):
    """Least-squares exponent ``k`` of ``y ~ x^k`` over the points with positive finite ``y``
    (None with fewer than 3 such points)."""
    import numpy as np

    x, y = np.asarray(xs, float), np.asarray(ys, float)
    keep = np.isfinite(y) & (y > 0)
    if np.count_nonzero(keep) < 3:
        return None
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


#: the 3D cases of the direct path drawn next to the 2D ladder (P1 meshes; the P2 case is its own point)
LADDER_3D = ["3d-100k-direct", "3d-p2-78k-direct", "3d-187k-direct", "3d-243k-direct", "3d-304k-direct"]


def _num(row, key):
    """``row[key]`` as a float (NaN when missing: rows of older runs lack the memory columns)."""
    try:
        return float(row.get(key, "") or "nan")
    except ValueError:
        return math.nan


def _ratio_cell(row, key, status=True):
    v = _num(row, key)
    text = f"**{v:.2f}**" if v > 1.5 else f"{v:.2f}"
    return text + ("" if not status or row["status"] == "converged" else f" ({row['status']})")


def _ratio_table(rows, variants, cases, key, title_plain, plain_key):
    head = f"| case | DOFs | candidates | {title_plain} | " + " | ".join(variants) + " | median | max |"
    out = [head, "|---" * (6 + len(variants)) + "|"]
    for case in cases:
        sub = {r["variant"]: r for r in rows if r["case"] == case}
        r0 = next(iter(sub.values()))
        ratios = [_num(r, key) for r in sub.values()]
        cells = [_ratio_cell(sub[v], key) if v in sub else "-" for v in variants]
        out.append(f"| {case} | {r0['dofs']} | {r0['candidates']} | {r0[plain_key]} | " + " | ".join(cells)
                   + f" | {statistics.median(ratios):.2f} | {max(ratios):.2f} |")
    return out


def _solve_mb(row, linear=False):
    """Memory of one solve: its peak RSS above the RSS when it started (heap trimmed, :func:`reset_peak_rss`)."""
    if linear:
        return _num(row, "plain_linear_peak_rss_mb") - _num(row, "plain_linear_base_rss_mb")
    return _num(row, "peak_rss_mb") - _num(row, "base_rss_mb")


def _memory_table(rows, cases):
    """Per case: the model's resident size, the peak RSS and the solve memory of the linear and contact solves."""
    out = ["| case | DOFs | model MiB | one linear solve: peak RSS MiB (solve: +MiB) | contact solves: peak RSS MiB, "
           "min-max (solve: +MiB, min-max) | contact/linear solve memory, max |",
           "|---|---|---|---|---|---|"]
    for case in cases:
        sub = [r for r in rows if r["case"] == case]
        peaks = [_num(r, "peak_rss_mb") for r in sub]
        if all(math.isnan(x) for x in peaks):
            continue
        r0 = sub[0]
        lin, lin_solve = _num(r0, "plain_linear_peak_rss_mb"), _solve_mb(r0, linear=True)
        solves = [_solve_mb(r) for r in sub]
        ratio = f"{max(solves) / lin_solve:.2f}" if lin_solve > 0 else "-"
        out.append(f"| {case} | {r0['dofs']} | {_num(r0, 'model_rss_mb'):.0f} | {lin:.0f} (+{lin_solve:.0f}) | "
                   f"{min(peaks):.0f}-{max(peaks):.0f} (+{min(solves):.0f}-{max(solves):.0f}) | {ratio} |")
    return out


def summary(rows, ladder=LADDER_2D) -> str:
    """Markdown summary: contact/linear ratio (CPU and wall) and peak RSS per case and variant, and the
    fitted exponents of time, memory and ratio on the 2D ladder."""
    variants = [v for v in ISSUE_VARIANTS if any(r["variant"] == v for r in rows)]
    variants += [v for v in dict.fromkeys(r["variant"] for r in rows) if v not in variants]
    cases = list(dict.fromkeys(r["case"] for r in rows))
    cases = [c for c in ladder if c in cases] + [c for c in cases if c not in ladder]
    out = _ratio_table(rows, variants, cases, "ratio_cpu", "one linear solve CPU s", "plain_linear_cpu_s")
    out += ["", "Wall seconds (same runs; the machine's load, not the code, decides most of the spread):", ""]
    out += _ratio_table(rows, variants, cases, "ratio", "one linear solve wall s", "plain_linear_s")
    out += ["", "Peak memory (resident set size of the benchmark's process during the solve, `VmHWM` reset "
            "before each solve after trimming the C heap; \"model\": the resident size after the assembly, before any "
            "solve: interpreter, libraries, mesh, stiffness; \"solve\": the peak above the resident size when the "
            "solve started):", ""]
    out += _memory_table(rows, cases)
    lad = [c for c in ladder if c in cases]
    fits = ["", "Fitted exponents on the 2D ladder (" + ", ".join(lad) + "): quantity ~ DOFs^k", "",
            "| variant | k of CPU s | k of contact/linear (CPU) | k of wall s | k of peak RSS | k of solve memory "
            "(peak RSS above the start) |", "|---|---|---|---|---|---|"]
    dofs_of = {r["case"]: int(r["dofs"]) for r in rows}
    first = {}
    for r in rows:
        first.setdefault(r["case"], r)
    kp = _fit([dofs_of[c] for c in lad], [_num(first[c], "plain_linear_cpu_s") for c in lad])
    if kp is None:  # fewer than 3 ladder cases: no fit
        return "\n".join(out) + "\n"
    for v in variants:
        pts = [r for c in lad for r in rows if r["case"] == c and r["variant"] == v and r["status"] == "converged"]
        x = [dofs_of[r["case"]] for r in pts]
        ks = [_fit(x, [_num(r, key) for r in pts]) for key in ("cpu_s", "ratio_cpu", "wall_s", "peak_rss_mb")]
        ks.append(_fit(x, [_solve_mb(r) for r in pts]))
        if ks[0] is not None:
            fits.append(f"| {v} | {ks[0]:.2f} | {ks[1]:+.3f} | {ks[2]:.2f} | {_fmt_k(ks[3])} | {_fmt_k(ks[4])} |")
    kw = _fit([dofs_of[c] for c in lad], [_num(first[c], "plain_linear_s") for c in lad])
    km = _fit([dofs_of[c] for c in lad], [_num(first[c], "plain_linear_peak_rss_mb") for c in lad])
    ks = _fit([dofs_of[c] for c in lad], [_solve_mb(first[c], linear=True) for c in lad])
    fits.append(f"| (one linear solve) | {kp:.2f} | | {kw:.2f} | {_fmt_k(km)} | {_fmt_k(ks)} |")
    return "\n".join(out + fits) + "\n"


def _fmt_k(k):
    return "-" if k is None or math.isnan(k) else f"{k:.2f}"


def plot(rows, path: Path, ladder=LADDER_2D, ladder_3d=LADDER_3D) -> None:
    """Log-log plots against DOFs: contact/linear ratio (CPU), CPU time and solve memory, with fitted exponents.

    Lines: the 2D ladder (fits over it in the legend); open markers: the 3D direct-path cases.
    Memory: the peak RSS of each solve above the RSS when it started (:func:`_solve_mb`), and
    the model's resident size (interpreter, mesh, stiffness) for scale.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases = [c for c in ladder if any(r["case"] == c for r in rows)]
    cases3 = [c for c in ladder_3d if any(r["case"] == c for r in rows)]
    variants = [v for v in ISSUE_VARIANTS if any(r["variant"] == v for r in rows)]
    dofs_of = {r["case"]: int(r["dofs"]) for r in rows}
    first = {}
    for r in rows:
        first.setdefault(r["case"], r)
    getters = (lambda r: _num(r, "ratio_cpu"), lambda r: _num(r, "cpu_s"), _solve_mb)
    fmts = ("{:+.3f}", "{:.2f}", "{:.2f}")
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    for i, v in enumerate(variants):
        pts = sorted(((dofs_of[r["case"]], r) for r in rows
                      if r["variant"] == v and r["case"] in cases and r["status"] == "converged"),
                     key=lambda p: p[0])
        pts3 = [(dofs_of[r["case"]], r) for r in rows
                if r["variant"] == v and r["case"] in cases3 and r["status"] == "converged"]
        x = [p[0] for p in pts]
        for ax, get, fmt in zip(axes, getters, fmts):
            y = [get(p[1]) for p in pts]
            k = _fit(x, y) if pts else None
            if pts:
                ax.loglog(x, y, marker="o", color=f"C{i}",
                          label=f"{v} (k={fmt.format(k)})" if k is not None and not math.isnan(k) else v)
            if pts3:
                ax.loglog([p[0] for p in pts3], [get(p[1]) for p in pts3], ls="none", marker="^",
                          mfc="none", color=f"C{i}")
    x = [dofs_of[c] for c in cases]
    for ax, get, label, style in (
            (axes[1], lambda r: _num(r, "plain_linear_cpu_s"), "one linear solve", "k--"),
            (axes[2], lambda r: _solve_mb(r, linear=True), "one linear solve", "k--"),
            (axes[2], lambda r: _num(r, "model_rss_mb"), "model (before any solve)", "k:")):
        y = [get(first[c]) for c in cases]
        k = _fit(x, y) if cases else None
        ax.loglog(x, y, style, marker="s", label=f"{label} (k={k:.2f})" if k and not math.isnan(k) else label)
        if cases3:
            ax.loglog([dofs_of[c] for c in cases3], [get(first[c]) for c in cases3], "ks", mfc="none")
    axes[0].axhline(1.5, color="k", ls=":", lw=1, label="1.5 (issue 11)")
    axes[0].set(xlabel="DOFs", ylabel="contact solve / one linear solve (CPU s)", title="Hertz: ratio")
    axes[1].set(xlabel="DOFs", ylabel="CPU s (1 MKL thread)", title="Hertz: time")
    axes[2].set(xlabel="DOFs", ylabel="MiB", title="Hertz: memory (peak RSS above the start of the solve)")
    fig.suptitle("2D ladder: lines, fitted exponents k in the legends; 3D direct path (" + ", ".join(cases3)
                 + "): open markers", fontsize=9)
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_drives(rows, path: Path) -> None:
    """Contact solve / one linear solve (CPU) against DOFs for the cases ``NAME:DRIVE``: one marker per
    drive, one colour per variant (2D filled, 3D open)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    drives = list(dict.fromkeys(r["case"].partition(":")[2] or "obstacle" for r in rows))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    markers = dict(zip(drives, "osD^vP*X"))
    fig, ax = plt.subplots(figsize=(8, 5))
    for r in rows:
        if r["status"] != "converged":
            continue
        drive = r["case"].partition(":")[2] or "obstacle"
        three = r["case"].startswith("3d")
        ax.semilogx(int(r["dofs"]), _num(r, "ratio_cpu"), ls="none", marker=markers[drive],
                    color=f"C{variants.index(r['variant'])}", mfc="none" if three else None)
    for d in drives:
        ax.plot([], [], "k" + markers[d], ls="none", label=d)
    for i, v in enumerate(variants):
        ax.plot([], [], color=f"C{i}", label=v)
    ax.axhline(1.5, color="k", ls=":", lw=1)
    ax.set(xlabel="DOFs", ylabel="contact solve / one linear solve (CPU s)",
           title="Hertz: ratio by drive (2D filled, 3D open markers)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _timed_solves(prob, chosen, case_opts, repeats, backend, done=None):
    """Per variant of ``chosen``: the solution and the fastest (CPU) timing of ``repeats`` contact solves
    (each with its own factorization); and the fastest of the linear solves between them (none for one repeat).

    Round robin: every repeat runs each variant once, then one linear solve, so that every variant and
    the denominator sample the same stretches of machine load (a shared machine's load changes over
    seconds; timing one variant's repeats in a row let a busy stretch inflate that variant alone).
    ``done(label, solution, timing)``, if given, is called after each variant of a single repeat
    (big cases: provisional rows survive an interrupted run).
    """
    best = {label: Timing(math.inf, math.inf) for label, *_ in chosen}
    sols = {}
    plain = Timing(math.inf, math.inf)
    for _ in range(repeats):
        for label, alg, pen, opts in chosen:
            prob.model.clear_factorization()  # every variant pays its factorization (no reuse across variants)
            sols.pop(label, None)
            reset_peak_rss()
            base = rss_mb()
            c0, t0 = time.process_time(), time.perf_counter()
            sols[label] = solve(prob, alg, pen, **{**case_opts, **opts})
            best[label] = min(best[label], Timing(time.perf_counter() - t0, time.process_time() - c0, peak_rss_mb(),
                                                  base))
            if done is not None and repeats == 1:
                done(label, sols[label], best[label])
        if repeats > 1:
            plain = min(plain, plain_linear_solve(prob, backend))
    return [(label, sols[label], best[label]) for label, *_ in chosen], plain


def _read_csv(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def write_report(out: Path, rows) -> None:
    """``hertz.csv``, ``hertz.png`` and ``hertz.md`` (text above ``<!-- tables -->`` kept) from ``rows``."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS, extrasaction="ignore")
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(out / "hertz.csv", buf.getvalue())
    (plot_drives if any(":" in r["case"] for r in rows) else plot)(rows, out / "hertz.png")
    md = out / "hertz.md"
    text = md.read_text() if md.exists() else ""
    head = text.split("<!-- tables -->")[0] if "<!-- tables -->" in text else "# Hertz benchmark\n\n"
    body = ["<!-- tables -->", "", "## Summary (generated): contact solve / one linear solve, CPU seconds", "",
            "Bold: above 1.5. A status in parentheses: the run failed (its time up to the failure). Fits and "
            "plot: converged runs only; the fits run over the 2D ladder, the 3D direct-path cases are the open "
            "markers of the plot.", "", summary(rows), "![ratio, time and memory against DOFs](hertz.png)", "",
            _markdown(rows)]
    write_text_atomic(md, head + "\n".join(body))


def run(out_dir=None, cases=None, variants=None, log=print, merge=False, repeats=None) -> Path:
    """Run the benchmark in this process; return the folder with ``hertz.csv``, ``hertz.md`` and ``hertz.png``.

    ``merge``: keep the rows of other cases already in ``hertz.csv`` (big cases run one at a
    time). ``repeats``: timings per variant (default from :data:`REPEAT_BUDGET_S`).
    :func:`run_isolated` runs every case in a process of its own.
    """
    out = Path(out_dir or Path(__file__).parent / "out")
    out.mkdir(parents=True, exist_ok=True)
    cases = cases or DEFAULT_CASES
    chosen = [v for v in VARIANTS if variants is None or v[0] in variants]
    rows = []
    for case in cases:
        builder, kw, case_opts = case_spec(case)
        t0 = time.perf_counter()
        prob = builder(**kw)
        log(f"{case}: {prob.model.ndofs} DOFs (mesh {time.perf_counter() - t0:.1f} s)")
        backend = case_opts.get("linear_solver", "auto")
        prob.model.stiffness()  # assembled once, outside both timings
        model_rss = rss_mb()  # interpreter, libraries, mesh, stiffness: what every solve starts from
        # the first call also loads the solver library: kept only if no later linear solve is faster
        # (a big case is timed once before and once after the variants; a separate warm-up would cost
        # a whole linear solve there)
        plain = plain_linear_solve(prob, backend)
        reps = repeats or max(1, min(MAX_REPEATS, int(REPEAT_BUDGET_S / plain.cpu)))
        plain = min([plain] + [plain_linear_solve(prob, backend) for _ in range(reps - 1)])
        log(f"  one linear solve {plain.wall:.3f} s wall, {plain.cpu:.3f} s CPU, peak RSS {plain.rss_mb:.0f} MiB, "
            f"repeats {reps}")
        provisional = []

        def done(label, sol, timing, case=case, prob=prob, plain=plain, model_rss=model_rss, provisional=provisional):
            """A provisional row (linear solve measured before the variants only), written at once with ``merge``."""
            provisional.append(_row(case, label, prob, sol, plain, timing, 1, model_rss))
            if merge:
                old = [r for r in _read_csv(out / "hertz.csv") if r["case"] != case]
                write_report(out, old + rows + provisional)

        sols, between = _timed_solves(prob, chosen, case_opts, reps, backend, done)
        plain = min(plain, between)
        # shared machines: the smallest of the measurements before, between and after the variants
        plain = min([plain] + [plain_linear_solve(prob, backend) for _ in range(reps)])
        log(f"  one linear solve (min of before/after) {plain.wall:.3f} s wall, {plain.cpu:.3f} s CPU")
        for label, sol, timing in sols:
            row = _row(case, label, prob, sol, plain, timing, reps, model_rss)
            rows.append(row)
            log(f"  {label:20s} {row['status']:14s} outer={row['outer_iterations']:3d} "
                f"newton={row['newton_iterations']:4d} solves={row['linear_solves']:5d} "
                f"factorizations={row['factorizations']} cg_its={row['cg_iterations']} "
                f"wall={row['wall_s']:.3f}s ratio={row['ratio']:.3f} cpu={row['cpu_s']:.3f}s "
                f"ratio_cpu={row['ratio_cpu']:.3f} rss={row['peak_rss_mb']:.0f}MiB ratio_rss={row['ratio_rss']:.3f}")
        if merge:  # written after every case: an interrupted run keeps what it measured
            old = [r for r in _read_csv(out / "hertz.csv") if r["case"] not in {r["case"] for r in rows}]
            write_report(out, old + rows)
    if not merge:
        write_report(out, rows)
    return out


def run_isolated(out_dir=None, cases=None, variants=None, log=print, merge=False, repeats=None,
                 timeout=None) -> tuple[Path, list[str]]:
    """Run every case in a process of its own (:func:`run` with ``merge``); return the folder and the failed cases.

    A fresh process per case: the peak RSS of a case does not include the previous case's heap,
    and a case that runs out of memory or past ``timeout`` seconds loses only its own rows.
    Without ``merge`` the rows of cases not run are dropped from ``hertz.csv`` first.
    """
    out = Path(out_dir or Path(__file__).parent / "out")
    out.mkdir(parents=True, exist_ok=True)
    cases = cases or DEFAULT_CASES
    if not merge:
        write_report(out, [])
    failed = []
    for case in cases:
        cmd = [sys.executable, str(Path(__file__).resolve()), "--in-process", "--merge", "--out", str(out),
               "--cases", case]
        if variants is not None:
            cmd += ["--variants", *variants]
        if repeats:
            cmd += ["--repeats", str(repeats)]
        try:
            rc = subprocess.run(cmd, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            rc = "timeout"
        if rc != 0:
            log(f"{case}: its process ended with {rc}; its rows are missing")
            failed.append(case)
    return out, failed


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--cases", nargs="*", type=_case_arg, default=None,
                    help=f"NAME or NAME:DRIVE; NAME one of {', '.join(CASES)}")
    ap.add_argument("--drives", nargs="*", choices=list(hertz.DRIVES), default=None,
                    help="run every case with each of these drives (NAME:DRIVE)")
    ap.add_argument("--variants", nargs="*", choices=[v[0] for v in VARIANTS], default=None)
    ap.add_argument("--issue-variants", action="store_true", help="the variants of issue 11 (ISSUE_VARIANTS)")
    ap.add_argument("--merge", action="store_true", help="keep the other cases already in <out>/hertz.csv")
    ap.add_argument("--repeats", type=int, default=None, help="timings per variant (default: by model size)")
    ap.add_argument("--report", action="store_true", help="only rewrite hertz.md / hertz.png from hertz.csv")
    ap.add_argument("--in-process", action="store_true", help="run the cases in this process (default: one each)")
    ap.add_argument("--case-timeout", type=float, default=None, help="seconds per case process")
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    out = Path(args.out or Path(__file__).parent / "out")
    if args.report:
        write_report(out, _read_csv(out / "hertz.csv"))
        print(f"wrote {out / 'hertz.md'}")
        return 0
    variants = ISSUE_VARIANTS if args.issue_variants else args.variants
    cases = args.cases
    if args.drives:
        cases = [f"{c.partition(':')[0]}:{d}" for c in (cases or DEFAULT_CASES) for d in args.drives]
    if args.in_process:
        path = run(args.out, cases, variants, merge=args.merge, repeats=args.repeats)
        failed = []
    else:
        path, failed = run_isolated(args.out, cases, variants, merge=args.merge, repeats=args.repeats,
                                    timeout=args.case_timeout)
    print(f"wrote {path / 'hertz.csv'}, {path / 'hertz.md'} and {path / 'hertz.png'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
