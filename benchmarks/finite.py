"""Finite-deformation contact benchmark: neo-Hookean half-cylinder (2D) or hemisphere (3D) on a rigid plane.

Cases: :func:`alcontact.problems.half_cylinder.half_cylinder` (plane strain, P2 by
default), pressed to ``delta/R = 0.4``, and :func:`alcontact.problems.hemisphere.hemisphere`
(``--problem hemisphere``: a quarter hemisphere, P1 or P2, ``delta/R = 0.2``), in uniform
load steps. For every algorithm and contact penalty the script records per load step the
Newton iterations (all Newton systems of the step: subproblems, active-set steps,
predictor excluded), the assembly + linear solves of the step (a tangent predictor
included; the secant predictor costs none) and the CPU time of the step (one thread;
wall time drifts with the load of a shared machine), and divides the CPU time per step by
the CPU cost of one tangent assembly plus one sparse direct solve of the same mesh
(measured in the same run, at the final state), once with a fresh solver (ordering and
analysis included) and once reusing the analysis as the Newton iterations do (the
``ratio`` column of the CSV). Writes ``<out>/<name>.csv`` (one row per step) and
``<out>/<name>.md`` (``--name``, default ``finite``). With ``--profile`` every variant runs
under :mod:`cProfile` with a CPU-time clock and the report adds where a load step's CPU time
goes (:data:`BREAKDOWN`: factorization, solve phase, back-substitutions, solver overhead,
tangent assembly, Newton matrix, residual evaluations, multiplier step, predictor, rest) with
the counts of residual evaluations and back-substitutions. The solver registry's one-time
library lookup runs before the timed variants.

Usage::

    python benchmarks/finite.py [--out DIR] [--case 2d-100k] [--problem half-cylinder] [--n 24] [--order 2]
                                [--steps 20] [--delta 0.4] [--variants ssn ...] [--name finite] [--profile]
    alcontact bench --suite finite [--case 2d-100k --case 3d-100k] [--variant ssn ...] [--quick]

``--case`` picks a preset mesh of :data:`CASES` (``2d-100k``: ``--n 112 --order 2``, 101 250
DOFs; ``3d-100k``: ``--problem hemisphere --n 31 --order 1 --steps 10``, 98 304 DOFs);
``alcontact bench`` runs :func:`run` (default: both 100k-DOF cases, every variant, hours
of CPU time; ``--quick``: ``2d-5k``, three variants). The default ``--n 24`` (4.8k DOFs)
runs in a minute on a laptop.
"""

from __future__ import annotations

import argparse
import cProfile
import csv
import io
import logging
import pstats
import sys
import time
from pathlib import Path

import numpy as np

from alcontact.contact import solve
from alcontact.contact.systems import FiniteContact, NewtonSolver
from alcontact.contact.systems._full_space import linear_solve
from alcontact.errors import UnknownNameError
from alcontact.io.results import write_text_atomic
from alcontact.problems.half_cylinder import half_cylinder
from alcontact.problems.hemisphere import hemisphere

PROBLEMS = {"half-cylinder": half_cylinder, "hemisphere": hemisphere}

VARIANTS = {
    "ssn": ("ssn", None),
    "simo-laursen": ("simo-laursen", None),
    "penalty": ("penalty", None),
    "exp-met1": ("family-p", "exp-met1"),
    "exp-met2": ("family-p", "exp-met2"),
    "log-met1": ("family-p", "log-met1"),
    "log-met2": ("family-p", "log-met2"),
    "quad-met1": ("family-p", "quad-met1"),
    "quad-met2": ("family-p", "quad-met2"),
}

#: Preset meshes of ``--case`` and ``alcontact bench --suite finite --case ...``:
#: name -> (problem, n, element order, load steps); the name gives the DOFs.
CASES = {
    "2d-5k": ("half-cylinder", 24, 2, 20),  # 4 802 DOFs
    "2d-63k": ("half-cylinder", 88, 2, 20),  # 62 658 DOFs (the peer's size)
    "2d-100k": ("half-cylinder", 112, 2, 20),  # 101 250 DOFs
    "3d-7k": ("hemisphere", 12, 1, 10),  # 6 591 DOFs
    "3d-47k": ("hemisphere", 24, 1, 10),  # 46 875 DOFs
    "3d-100k": ("hemisphere", 31, 1, 10),  # 98 304 DOFs
}
#: the cases of issue 10 (about 100k DOFs in 2D and in 3D)
DEFAULT_CASES = ["2d-100k", "3d-100k"]

FIELDS = ["variant", "step", "t", "newton_iterations", "assembly_solves", "outer_iterations", "cutbacks", "force",
          "cpu_seconds", "ratio"]


def assembly_and_solve_seconds(problem, u: np.ndarray, repeat: int = 3) -> tuple[float, float, float]:
    """Best of ``repeat`` CPU timings at ``u``: ``(assembly, first solve, repeated solve)``.

    The first solve is a fresh :class:`NewtonSolver` (ordering, symbolic analysis,
    numerical factorization, solve); the repeated one reuses the analysis (numerical
    factorization + solve), as the Newton iterations of a load step do.
    """
    dc = FiniteContact(problem)
    ta = tf = tr = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        K = dc._tangent_free(u)
        t1 = time.process_time()
        solver = NewtonSolver()
        linear_solve(K, np.ones(K.shape[0]), solver)
        t2 = time.process_time()
        linear_solve(K, np.ones(K.shape[0]), solver)
        t3 = time.process_time()
        ta, tf, tr = min(ta, t1 - t0), min(tf, t2 - t1), min(tr, t3 - t2)
    return ta, tf, tr


#: rows of the ``--profile`` breakdown: (label, what it measures)
BREAKDOWN = [
    ("factorization", "PARDISO analysis + numerical factorization (all Newton systems and predictors)"),
    ("solve", "PARDISO solve phase of the Newton systems"),
    ("back-substitutions", "PARDISO solves with the factor at hand (multiplier step of Algorithm 6.1)"),
    ("solver overhead", "the solver's pattern lookup, conversion to PARDISO's input and residual check"),
    ("tangent assembly", "K_T(u): element tangents and their CSR assembly"),
    ("Newton matrix", "free block, contact blocks, saddle-point matrix (besides the tangent)"),
    ("residual evaluations", "f_int, energy, gaps and contact forces of the start and of every trial step"),
    ("multiplier step", "Algorithm 6.1's dual step besides its back-substitutions"),
    ("predictor", "configure: secant / tangent predictor, candidates (besides its assembly and solve)"),
    ("rest", "outer loops, stopping tests, step records"),
]


def _cum(stats: dict, name: str, file: str = "", caller: str | None = None) -> tuple[float, int]:
    """Cumulative CPU seconds and calls of the functions ``name`` (defined in a file containing ``file``),
    all callers or only those named ``caller``."""
    total, calls = 0.0, 0
    for (f, _, fn), (_, nc, _, ct, callers) in stats.items():
        if fn != name or file not in f:
            continue
        if caller is None:
            total, calls = total + ct, calls + nc
            continue
        for (_, _, cfn), cstat in callers.items():
            if cfn == caller:
                total, calls = total + cstat[3], calls + cstat[1]
    return total, calls


def breakdown(prof: cProfile.Profile, total: float) -> tuple[dict, dict]:
    """CPU seconds of a profiled run by :data:`BREAKDOWN` row (non-overlapping) and call counts."""
    st = pstats.Stats(prof).stats
    # PARDISO's input (upper triangle) from the matrix: a conversion, not the factorization
    convert = _cum(st, "_upper_with_diagonal", "_sequence")[0] + _cum(st, "_gathered", "_sequence")[0]
    fact = (_cum(st, "refactorize", "_sequence")[0] + _cum(st, "__init__", "_sequence.py")[0]
            - _cum(st, "__init__", "_sequence.py", "__init__")[0] - convert)  # SequenceSolver.__init__ is no factor
    solve = _cum(st, "solve", "_solvers", "solve")[0]
    back, nback = _cum(st, "solve", "_solvers", "resolve")
    seq = _cum(st, "solve", "_sequence")[0]
    tan = _cum(st, "tangent_data", "hyperelastic")[0] or _cum(st, "tangent", "hyperelastic")[0]
    tan_pred = _cum(st, "tangent", "hyperelastic", "_predict")[0]
    steps = _cum(st, "step", "_full_space.py")[0]
    solve_steps = _cum(st, "linear_solve", "_full_space.py", "step")[0]
    ev, nev = _cum(st, "evaluate", "_full_space.py")
    mult = _cum(st, "multiplier_step", "_full_space.py")[0]
    conf = _cum(st, "configure", "_full_space.py")[0]
    solve_pred = _cum(st, "linear_solve", "_full_space.py", "_predict")[0]
    out = {
        "factorization": fact, "solve": solve, "back-substitutions": back, "solver overhead": seq - fact - solve,
        "tangent assembly": tan, "Newton matrix": steps - solve_steps - (tan - tan_pred),
        "residual evaluations": ev, "multiplier step": mult - back,
        "predictor": conf - solve_pred - tan_pred,
    }
    out["rest"] = total - sum(out.values())
    counts = {"evaluations": nev, "back-substitutions": nback,
              "factorizations": _cum(st, "refactorize", "_sequence")[1]}
    return out, counts


def run_case(args, log=logging.info, command: str | None = None) -> str:
    """Run the variants ``args.variants`` on one mesh; write ``<args.out>/<args.name>.csv`` and ``.md``.

    ``args`` carries ``problem``, ``n``, ``order``, ``steps``, ``delta`` (``None``: the
    problem's), ``repeat`` (unit-cost timings, best of), ``out`` and ``name``; ``command``
    is the command line quoted in the markdown (default: this script's arguments).
    Returns the markdown.
    """
    kwargs = {} if args.delta is None else {"delta": args.delta}
    problem = PROBLEMS[args.problem](args.n, order=args.order, **kwargs)
    rows, summary, profiles = [], [], []
    t_ref = None
    NewtonSolver()  # the solver registry's one-time library lookup (imports, pypardiso's search) is no step cost
    for name in args.variants:
        algorithm, penalty = VARIANTS[name]
        prof = cProfile.Profile(time.process_time) if args.profile else None
        marks = []  # CPU time at the start (done = 0) and after every accepted step (solve's progress callback)
        t0 = time.perf_counter()
        if prof is not None:
            prof.enable()
        sol = solve(problem, algorithm, penalty, steps=args.steps,
                    on_step=lambda done, total, t: marks.append(time.process_time()))
        if prof is not None:
            prof.disable()
        frames = [f for f in sol.frames if f.t > 0]  # the accepted load steps (a run that reached none: the start)
        if prof is not None:
            profiles.append((name, len(frames), int(sum(f.newton_iterations for f in frames)),
                             *breakdown(prof, marks[-1] - marks[0])))
        wall = time.perf_counter() - t0
        if t_ref is None:
            t_asm, t_first, t_again = assembly_and_solve_seconds(problem, sol.u, repeat=args.repeat)
            t_ref = t_asm + t_first
            t_ref2 = t_asm + t_again
        newton = [f.newton_iterations for f in frames]
        secs = list(np.diff(marks))
        solves = [f.linear_solves for f in frames]
        for k, f in enumerate(frames, 1):
            rows.append({"variant": name, "step": k, "t": f"{f.t:.4f}", "newton_iterations": f.newton_iterations,
                         "assembly_solves": f.linear_solves, "outer_iterations": f.outer_iterations,
                         "cutbacks": f.cutbacks, "force": f"{f.contact_force[1]:.10g}",
                         "cpu_seconds": f"{secs[k - 1]:.4f}", "ratio": f"{secs[k - 1] / t_ref2:.2f}"})
        summary.append((name, sol.status.label, len(frames), float(np.mean(newton)) if newton else np.nan,
                        max(newton, default=0), float(np.mean(solves)) if solves else np.nan,
                        float(np.mean(secs)) / t_ref if secs else np.nan,
                        float(np.mean(secs)) / t_ref2 if secs else np.nan, wall,
                        float(frames[-1].contact_force[1]) if frames else np.nan))
        log(f"{name}: {sol.status.label}, {summary[-1][3]:.2f} Newton per step, {summary[-1][5]:.2f} assembly+solves "
            f"per step, time ratios {summary[-1][6]:.2f} / {summary[-1][7]:.2f}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS)
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(out / f"{args.name}.csv", buf.getvalue())
    lines = [
        f"# Finite-deformation contact: {problem.name}",
        "",
        f"{problem.model.ndofs} DOFs; delta/R = {problem.meta['delta'] / problem.meta['radius']:g} in {args.steps} "
        f"uniform steps. One tangent assembly {t_asm:.4f} s; one direct solve (MKL PARDISO, symmetric "
        f"indefinite, 1 thread) {t_first:.4f} s with its analysis, {t_again:.4f} s reusing it (CPU seconds, same "
        "run; step times are CPU seconds too).",
        "Generated by `" + (command or "python benchmarks/finite.py " + " ".join(sys.argv[1:])) + "`.",
        "",
        "| variant | status | steps | Newton / step (mean) | Newton / step (max) | assembly + solves / step "
        "| step CPU / (assembly + first solve) | step CPU / (assembly + repeated solve) | wall s | final force |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, st, n, nm, nx, ns, ratio, ratio2, wall, f in summary:
        lines.append(f"| {name} | {st} | {n} | {nm:.2f} | {nx} | {ns:.2f} | {ratio:.2f} | {ratio2:.2f} | {wall:.1f} "
                     f"| {f:.10g} |")
    if profiles:
        lines += ["", "CPU seconds per load step by part (cProfile with a CPU-time clock; its overhead inflates "
                  "the Python-heavy rows a little), and per Newton system:", "",
                  "| part | " + " | ".join(f"{p[0]} / step | {p[0]} / Newton" for p in profiles) + " |",
                  "|---|" + "---|---|" * len(profiles)]
        for label, _ in BREAKDOWN:
            cells = [f"{p[3][label] / p[1]:.3f} | {p[3][label] / max(p[2], 1):.3f}" for p in profiles]
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
        cells = [f"{sum(p[3].values()) / p[1]:.3f} | {sum(p[3].values()) / max(p[2], 1):.3f}" for p in profiles]
        lines.append("| **total** | " + " | ".join(cells) + " |")
        for name, nsteps, newton, _, counts in profiles:
            lines.append(f"\n{name}: {newton} Newton systems in {nsteps} steps, {counts['factorizations']} "
                         f"refactorizations, {counts['evaluations']} residual evaluations "
                         f"({counts['evaluations'] / max(newton, 1):.2f} per Newton system), "
                         f"{counts['back-substitutions']} back-substitutions.")
        lines += [""] + [f"- {label}: {what}" for label, what in BREAKDOWN]
    text = "\n".join(lines) + "\n"
    write_text_atomic(out / f"{args.name}.md", text)
    return text


def run(out_dir=None, cases=None, variants=None, log=print, repeat: int = 3) -> Path:
    """``alcontact bench --suite finite``: run the preset meshes :data:`CASES`.

    Every case writes ``finite_<case>.csv`` and ``finite_<case>.md`` into ``out_dir``
    (:func:`run_case`); ``finite.md`` joins their markdown. ``cases`` default to
    :data:`DEFAULT_CASES` (the two 100k-DOF meshes of the issue: hours of CPU time),
    ``variants`` to all of :data:`VARIANTS`.

    Raises
    ------
    UnknownNameError
        A case or variant that is not a preset (the message lists the known ones).
    """
    out = Path(out_dir or Path(__file__).parent / "out")
    cases = list(cases or DEFAULT_CASES)
    variants = list(variants or VARIANTS)
    for case in cases:
        if case not in CASES:
            raise UnknownNameError("finite benchmark case", case, list(CASES))
    for v in variants:
        if v not in VARIANTS:
            raise UnknownNameError("finite benchmark variant", v, list(VARIANTS))
    parts = ["# Finite-deformation contact: Newton cost per load step", ""]
    for case in cases:
        problem, n, order, steps = CASES[case]
        args = argparse.Namespace(problem=problem, n=n, order=order, steps=steps, delta=None, repeat=repeat,
                                  out=out, name=f"finite_{case}", variants=variants,
                                  profile=False)
        log(f"finite {case}: {problem}, n = {n}, order {order}, {steps} load steps, variants {' '.join(variants)}")
        cmd = f"alcontact bench --suite finite --case {case}" + "".join(f" --variant {v}" for v in variants)
        text = run_case(args, log=log, command=cmd)
        parts += ["#" + text if text.startswith("# ") else text, ""]
    write_text_atomic(out / "finite.md", "\n".join(parts))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/benchmarks")
    ap.add_argument("--case", default=None, choices=list(CASES),
                    help="preset mesh (problem, n, order, steps); the options below override it")
    ap.add_argument("--problem", default=None, choices=list(PROBLEMS), help="default: half-cylinder")
    ap.add_argument("--n", type=int, default=None, help="default: 24")
    ap.add_argument("--delta", type=float, default=None, help="final approach (default: the problem's)")
    ap.add_argument("--repeat", type=int, default=3, help="timings of the unit cost (best of)")
    ap.add_argument("--name", default="finite", help="base name of the output files")
    ap.add_argument("--order", type=int, default=None, help="default: 2")
    ap.add_argument("--steps", type=int, default=None, help="default: 20")
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    ap.add_argument("--profile", action="store_true",
                    help="profile every variant (CPU clock) and add the breakdown of a step's CPU time by part")
    args = ap.parse_args(argv)
    preset = dict(zip(("problem", "n", "order", "steps"), CASES[args.case] if args.case else
                      ("half-cylinder", 24, 2, 20)))
    for key, value in preset.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    print(run_case(args))
    return 0


if __name__ == "__main__":
    sys.exit(main())
