"""Ironing benchmark (issue 18): Newton iterations per sliding step at finite deformation.

A rigid cylinder (2D, plane strain) or sphere (3D, half model) of radius R = 1 is pressed
0.2 R into a neo-Hookean block (E = 1000, nu = 0.3, P1) in 4 load steps, then slid along it
in steps of 0.05 R (:func:`alcontact.problems.ironing.ironing`). For every algorithm the
script records per sliding step the Newton iterations (every Newton system of the step,
cut-back attempts included), the cut-backs, the CPU time (one thread) and the ratio of that
time to the CPU cost of one tangent assembly plus one sparse direct solve reusing its analysis
(measured in the same run, at the final state), and checks each accepted step independently
of the solver: the equilibrium residual :math:`\\max|f_{int} - f_{ext} + B^T(w\\,t_N)|` on
the free DOFs relative to the largest nodal contact force, recomputed from the returned
displacement and pressures. The frictionless horizontal force of steady sliding (the sliding
steps after the first radius of travel) is reported relative to the vertical one, with its
largest jump between consecutive steps.

Coulomb friction (mu = 0.3, :func:`alcontact.contact.solve` with ``friction=0.3``): the variants
:data:`FRICTION_VARIANTS` (not run by default) record the same counts and, per run, the
largest relative error of the slip law :math:`|t_T| = \\mu t_N` at the slipping points, the
largest :math:`|t_T| / (\\mu t_N)` at the sticking points, the stick/slip reversals between
Newton iterates (``FiniteFrictionStep.state_reversals``) and the equilibrium residual with the
tangential tractions included.

Writes ``<out>/<name>.csv`` (one row per sliding step), ``<out>/<name>.json`` (the summary) and
``<out>/<name>.md``.

Usage::

    python benchmarks/ironing.py [--out DIR] [--case 2d-s ...] [--variants ssn ...] [--slide 2.0]
    alcontact bench --suite ironing [--case 2d-s] [--variant ssn ...] [--quick]
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import logging
import re
import sys
import time
from pathlib import Path

import numpy as np

from alcontact.contact import solve
from alcontact.contact.systems import FiniteContact, NewtonSolver
from alcontact.contact.systems._full_space import linear_solve
from alcontact.contact.obstacles import translate
from alcontact.errors import UnknownNameError
from alcontact.io.results import write_text_atomic
from alcontact.problems.ironing import ironing, ironing_schedule

VARIANTS = {
    "ssn": ("ssn", None),
    "simo-laursen": ("simo-laursen", None),
    "exp-met1": ("family-p", "exp-met1"),
    "log-met1": ("family-p", "log-met1"),
    "quad-met1": ("family-p", "quad-met1"),
}

#: Coulomb friction, mu = MU: name -> (algorithm, penalty, options) of contact.solve(..., friction=MU)
FRICTION_VARIANTS = {
    "ssn-coulomb": ("ssn", None, {}),
    # Algorithm 6.2 with its defaults (second-order multiplier update, penalty_scale 10 at finite deformation)
    "simo-laursen-coulomb": ("simo-laursen", None, {}),
    # the same with the stiff penalty every other algorithm defaults to (Algorithm 6.2's default before issue 18)
    "simo-laursen-coulomb-p100": ("simo-laursen", None, {"penalty_scale": 100.0}),
    # the same with the first-order updates (6.2b)/(6.2c): the finite-deformation path before issue 18's fix
    "simo-laursen-coulomb-first-order": ("simo-laursen", None, {"multiplier_update": "first-order"}),
    # the same with a ten times softer penalty (the fixed point does not depend on it)
    "simo-laursen-coulomb-p10": ("simo-laursen", None, {"penalty_scale": 10.0}),
    # the same with the coupled Coulomb radius mu t_N in every subproblem (slip law exact in each)
    "simo-laursen-coulomb-traction": ("simo-laursen", None, {"radius": "traction"}),
    # Algorithm 6.4 with exp-met1 and its defaults (second-order update, penalty_scale 10 at finite deformation)
    "exp-met1-coulomb": ("family-p", "exp-met1", {}),
    # the same with the stiff penalty (Algorithm 6.4's default before issue 18's second wave)
    "exp-met1-coulomb-p100": ("family-p", "exp-met1", {"penalty_scale": 100.0}),
    # Algorithm 6.4 with the other MET 1 generators, defaults (log-met1, a barrier: second-order since issue 18)
    "log-met1-coulomb": ("family-p", "log-met1", {}),
    "quad-met1-coulomb": ("family-p", "quad-met1", {}),
}
MU = 0.3

#: preset meshes: name -> (dim, elements per unit length); the block is 5 x 2 (2D) or 5 x 1.5 x 2 (3D)
CASES = {
    "2d-s": (2, 10),  # 2 142 DOFs
    "2d-m": (2, 20),  # 8 282 DOFs
    "2d-l": (2, 40),  # 32 562 DOFs
    "2d-100k": (2, 70),  # 98 982 DOFs
    "3d-s": (3, 4),  # 3 969 DOFs
    "3d-m": (3, 6),  # 12 090 DOFs
    "3d-l": (3, 8),  # 27 183 DOFs
    "3d-100k": (3, 12),  # 69 825 DOFs
}
DEFAULT_CASES = ["2d-s", "2d-m", "2d-l", "3d-s", "3d-m", "3d-l"]

FIELDS = ["case", "variant", "step", "t", "newton_iterations", "linear_solves", "cutbacks", "outer_iterations", "fx",
          "fy", "fz",
          "equilibrium", "cpu_seconds", "ratio", "slip_law_error", "stick_ratio_max", "state_reversals",
          "stick_slip_reversals"]


def unit_cost(problem, u: np.ndarray, repeat: int = 3) -> float:
    """Best of ``repeat`` CPU timings at ``u`` of one tangent assembly plus one direct solve reusing its analysis."""
    dc = FiniteContact(problem)
    solver = NewtonSolver()
    K = dc._tangent_free(u)
    linear_solve(K, np.ones(K.shape[0]), solver)  # the analysis, as the first Newton system of a run
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        K = dc._tangent_free(u)
        linear_solve(K, np.ones(K.shape[0]), solver)
        best = min(best, time.process_time() - t0)
    return best


class EquilibriumCheck:
    """Relative equilibrium residual of an accepted step, recomputed from its displacement and pressures."""

    def __init__(self, problem, path):
        model = problem.model
        self.problem, self.path, self.model = problem, path, model
        self.points, self.dofs = model.node_dofs(problem.contact_boundary)
        self.weights = np.asarray(model.boundary_weights(problem.contact_boundary), dtype=float)
        fixed, _ = problem.dirichlet()
        free = np.ones(model.ndofs, dtype=bool)
        free[np.asarray(fixed, dtype=np.int64)] = False
        self.free = free
        self.load = np.asarray(problem.load_vector(), dtype=float)

    def __call__(self, t: float, u: np.ndarray, pressure: np.ndarray, traction_t: np.ndarray | None = None) -> float:
        """``traction_t``: the tangential traction on the body, global ``(m, d)`` (``ContactFrame.traction_t``)."""
        ob = translate(self.problem.obstacle, self.path(t))
        _, nu = ob.evaluate(self.points + u[self.dofs])
        f = np.asarray(self.model.internal_force(u), dtype=float) - self.load
        nodal = self.weights * pressure
        # the contact force on the body is w (t_N nu + t_T) at each point (frictionless: B = -nu^T)
        contact = nodal[:, None] * nu
        if traction_t is not None:
            contact = contact + self.weights[:, None] * traction_t
        np.add.at(f, self.dofs.ravel(), (-contact).ravel())
        scale = max(float(np.max(np.abs(nodal), initial=0.0)), 1e-300)
        return float(np.max(np.abs(f[self.free]), initial=0.0)) / scale


def run_case(case: str, variants, *, slide: float = 2.0, repeat: int = 3, log=logging.info):
    """Run ``variants`` on the preset mesh ``case``: ``(rows, summaries, problem)``."""
    dim, n = CASES[case]
    problem = ironing(dim, n, slide=slide)
    times, path = ironing_schedule(problem)
    npress = problem.meta["press_steps"]
    check = EquilibriumCheck(problem, path)
    rows, summaries = [], []
    t_unit = None
    NewtonSolver()  # the solver registry's one-time library lookup is no step cost
    for name in variants:
        friction = name in FRICTION_VARIANTS
        marks = []  # CPU time of solve's progress callback (done, total, t)

        def on_step(done, total, t, marks=marks):
            marks.append(time.process_time())

        t0 = time.perf_counter()
        if friction:
            algorithm, penalty, options = FRICTION_VARIANTS[name]
            sol = solve(problem, algorithm, penalty, friction=MU, steps=times, obstacle_path=path, on_step=on_step,
                        **options)
        else:
            algorithm, penalty = VARIANTS[name]
            sol = solve(problem, algorithm, penalty, steps=times, obstacle_path=path, on_step=on_step)
        wall = time.perf_counter() - t0
        frames = [f for f in sol.frames if f.t > 0]  # the accepted load steps (a run that reached none: the start)
        if t_unit is None:
            t_unit = unit_cost(problem, sol.u, repeat=repeat)
        secs = _step_cpu(marks, frames, friction)
        # the solver-independent check of every accepted step, from its returned state
        eq = [check(f.t, f.u, f.pressure, f.traction_t if friction else None) for f in frames]
        slide_rows, slide_ks = [], []
        for k, s in enumerate(frames):
            if s.t <= npress:
                continue
            f = np.asarray(s.contact_force, dtype=float)
            row = {"case": case, "variant": name, "step": k + 1, "t": f"{s.t:.6g}",
                   "newton_iterations": s.newton_iterations, "linear_solves": s.linear_solves, "cutbacks": s.cutbacks,
                   "outer_iterations": s.outer_iterations, "fx": f"{f[0]:.10g}", "fy": f"{f[1]:.10g}",
                   "fz": f"{f[2]:.10g}" if dim == 3 else "", "equilibrium": f"{eq[k]:.3e}",
                   "cpu_seconds": f"{secs[k]:.4f}", "ratio": f"{secs[k] / t_unit:.2f}"}
            if friction:
                slip_err, stick_max = coulomb_check(s)
                rev, ss_rev = _state_reversals(sol, k)
                row.update(slip_law_error=f"{slip_err:.2e}", stick_ratio_max=f"{stick_max:.6f}",
                           state_reversals="" if rev is None else rev,
                           stick_slip_reversals="" if ss_rev is None else ss_rev)
            rows.append(row)
            slide_rows.append((s, f, eq[k], secs[k]))
            slide_ks.append(k)
        newton = np.array([s.newton_iterations for s, *_ in slide_rows])
        # steady sliding: after one radius of travel
        steady = [(s, f) for s, f, *_ in slide_rows if (s.t - npress) * problem.meta["slide_step"] >= 1.0]
        fx = np.array([f[0] for _, f in steady])
        fv = np.array([abs(f[-1]) for _, f in steady])
        summary = {
            "case": case, "variant": name, "dofs": int(problem.model.ndofs), "status": sol.status.label,
            "sliding_steps": len(slide_rows), "newton_mean": float(newton.mean()) if newton.size else None,
            "newton_max": int(newton.max()) if newton.size else None,
            "linear_solves_mean": float(np.mean([s.linear_solves for s, *_ in slide_rows])) if slide_rows else None,
            "outer_mean": float(np.mean([s.outer_iterations for s, *_ in slide_rows])) if slide_rows else None,
            "cutbacks": int(sum(s.cutbacks for s, *_ in slide_rows)),
            "equilibrium_max": float(max((e for *_, e, _ in slide_rows), default=np.nan)),
            "step_cpu_over_unit": float(np.mean([c for *_, c in slide_rows]) / t_unit) if slide_rows else None,
            "unit_cpu_seconds": t_unit, "wall_seconds": wall,
            "horizontal_over_vertical_max": float(np.max(np.abs(fx) / fv)) if fx.size else None,
            "horizontal_jump_over_vertical_max": float(np.max(np.abs(np.diff(fx)) / fv[1:])) if fx.size > 1 else None,
        }
        if friction:
            law = [coulomb_check(s) for s, *_ in slide_rows]
            both = [_state_reversals(sol, k) for k in slide_ks]
            rev, ss_rev = [b[0] for b in both], [b[1] for b in both]
            steady_ks = [k for k, (s, *_) in zip(slide_ks, slide_rows)
                         if (s.t - npress) * problem.meta["slide_step"] > 0.25]
            ss_steady = [_state_reversals(sol, k)[1] for k in steady_ks]
            summary.update(
                mu=MU, slip_law_error_max=float(max((a for a, _ in law), default=np.nan)),
                stick_ratio_max=float(max((b for _, b in law), default=np.nan)),
                state_reversals=None if any(r is None for r in rev) else int(sum(rev)),
                steps_with_reversals=None if any(r is None for r in rev) else int(sum(r > 0 for r in rev)),
                stick_slip_reversals=None if any(r is None for r in ss_rev) else int(sum(ss_rev)),
                stick_slip_reversals_after_transition=(None if any(r is None for r in ss_steady)
                                                       else int(sum(ss_steady))))
        summaries.append(summary)
        mean, ratio = summary["newton_mean"], summary["step_cpu_over_unit"]
        log(f"ironing {case} {name}: {summary['status']}, Newton per sliding step "
            f"{'-' if mean is None else f'{mean:.2f}'} (max {summary['newton_max']}), {summary['cutbacks']} "
            f"cut-backs, equilibrium <= {summary['equilibrium_max']:.1e}, step / unit "
            f"{'-' if ratio is None else f'{ratio:.2f}'}")
    return rows, summaries, problem


def _step_cpu(marks, frames, friction: bool) -> list[float]:
    """CPU seconds of every accepted step from the progress marks.

    Frictionless: a mark at the start and after every accepted step. Coulomb: a mark before every
    requested step and one at the end, so a requested step's time (its cut-back sub-steps and failed
    tries included) is given to the frame that reaches it, and 0 to the sub-steps before it.
    """
    secs = list(np.diff(marks))
    if not friction or len(secs) == len(frames):
        return secs
    out, k = [], 0
    for f in frames:
        out.append(secs[k] if f.requested and k < len(secs) else 0.0)
        k += int(f.requested)
    return out


def _state_reversals(sol, k: int):
    """``(state reversals, stick/slip reversals)`` between the Newton iterates of accepted step ``k`` (counts the
    Coulomb engine's record keeps per step, ``FiniteFrictionStep.state_reversals`` / ``stick_slip_reversals``;
    ``None`` when not counted)."""
    st = sol.record.steps[k]
    return st.state_reversals, st.stick_slip_reversals


#: slipping / sticking points whose pressure is at most this fraction of the largest are compared on the scale of
#: mu times the largest pressure: a family-P law keeps a positive pressure at every candidate (exp-met1: down to
#: 1e-280 of the largest at open points), where a relative error of the slip law is round-off over round-off
PRESSURE_FLOOR = 1e-14


def coulomb_check(step) -> tuple[float, float]:
    """``(largest | |t_T| - mu t_N | / (mu t_N) at slipping points, largest |t_T| / (mu t_N) at sticking points)``
    of a :class:`~alcontact.contact.ContactFrame` (at points pressed by at most :data:`PRESSURE_FLOOR` of the largest
    pressure, over mu times the largest pressure instead)."""
    tt = np.linalg.norm(step.traction_t, axis=1)
    bound = MU * step.pressure
    scale = np.maximum(bound, PRESSURE_FLOOR * MU * float(np.max(step.pressure, initial=0.0)))
    slip, stick = step.state == 2, step.state == 1  # SLIP, STICK (ContactFrame.state)
    err = float(np.max(np.abs(tt[slip] - bound[slip]) / scale[slip], initial=0.0))
    ratio = float(np.max(tt[stick] / scale[stick], initial=0.0))
    return err, ratio


def _fmt(v, spec):
    return "-" if v is None else format(v, spec)


#: the explanation of the frictional table's columns
FRICTION_COLUMNS = (
    f"Coulomb friction, mu = {MU}: *slip law*: the largest | abs(t_T) - mu t_N | / (mu t_N) at a slipping point "
    f"(at points pressed by at most {PRESSURE_FLOOR:g} of the largest pressure, over mu times the largest pressure: "
    "a family-P law keeps a round-off pressure at open points); *stick*: the largest abs(t_T) / (mu t_N) at a "
    "sticking point; *reversals*: points whose stick/slip/open state went back to one it had left between the "
    "Newton iterates of an accepted step (sum over the sliding steps, and the steps with any); *stick/slip rev.*: "
    "the same between stick and slip only (a point's open iterates skipped), all sliding steps / after the first "
    "0.25 R of travel (the stick-to-slip transition); *equilibrium* with the tangential tractions; *solves*: linear "
    "solves per sliding step (Newton systems, predictors and the sensitivity of the second-order multiplier "
    "update); *outer*: AL outer iterations per step.")


def frictionless_table(summaries) -> list[str]:
    """Markdown rows of the frictionless summaries."""
    lines = ["| case | DOFs | variant | status | sliding steps | Newton / step (mean) | max | cut-backs | equilibrium "
             "| step / unit | max abs(Fx)/Fy | max jump/Fy |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in (s for s in summaries if "mu" not in s):
        lines.append(f"| {s['case']} | {s['dofs']} | {s['variant']} | {s['status']} | {s['sliding_steps']} "
                     f"| {_fmt(s['newton_mean'], '.2f')} | {s['newton_max']} | {s['cutbacks']} "
                     f"| {_fmt(s['equilibrium_max'], '.1e')} | {_fmt(s['step_cpu_over_unit'], '.2f')} "
                     f"| {_fmt(s['horizontal_over_vertical_max'], '.2e')} "
                     f"| {_fmt(s['horizontal_jump_over_vertical_max'], '.2e')} |")
    return lines


def friction_table(summaries) -> list[str]:
    """Markdown rows of the frictional summaries (columns: :data:`FRICTION_COLUMNS`)."""
    lines = ["| case | DOFs | variant | status | sliding steps | Newton / step (mean) | max | solves / step "
             "| outer / step | cut-backs | equilibrium | step / unit | max Fx/Fy | slip law | stick "
             "| reversals (steps) | stick/slip rev. |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in (s for s in summaries if "mu" in s):
        rev = "-" if s["state_reversals"] is None else f"{s['state_reversals']} ({s['steps_with_reversals']})"
        ss = ("-" if s.get("stick_slip_reversals") is None
              else f"{s['stick_slip_reversals']} / {s['stick_slip_reversals_after_transition']}")
        lines.append(f"| {s['case']} | {s['dofs']} | {s['variant']} | {s['status']} | {s['sliding_steps']} "
                     f"| {_fmt(s['newton_mean'], '.2f')} | {s['newton_max']} | {_fmt(s['linear_solves_mean'], '.2f')} "
                     f"| {_fmt(s['outer_mean'], '.2f')} | {s['cutbacks']} "
                     f"| {_fmt(s['equilibrium_max'], '.1e')} | {_fmt(s['step_cpu_over_unit'], '.2f')} "
                     f"| {_fmt(s['horizontal_over_vertical_max'], '.3f')} | {_fmt(s['slip_law_error_max'], '.1e')} "
                     f"| {_fmt(s['stick_ratio_max'], '.4f')} | {rev} | {ss} |")
    return lines


def report(summaries, cases, command: str) -> str:
    lines = ["# Ironing at finite deformation: Newton iterations per sliding step", "",
             "A rigid cylinder (2D, plane strain) or sphere (3D, half model) of radius R = 1 pressed 0.2 R into a "
             "neo-Hookean block (E = 1000, nu = 0.3, P1) in 4 steps, then slid in steps of 0.05 R (frictionless). "
             "Counts over the sliding steps; *equilibrium*: the largest relative equilibrium residual of an accepted "
             "step, recomputed by the script from the returned state; *step / unit*: CPU time of a sliding step "
             "over one tangent assembly + one direct solve reusing its analysis (same run, 1 thread); *|Fx|/Fy* "
             "and *jump*: steady sliding (after 1 R of travel), the horizontal force and its largest change "
             "between steps relative to the vertical force.",
             "", f"Generated by `{command}`.", ""]
    if any("mu" not in s for s in summaries):
        lines += frictionless_table(summaries)
    if any("mu" in s for s in summaries):
        lines += ["", FRICTION_COLUMNS, ""] + friction_table(summaries)
    return "\n".join(lines) + "\n"


#: the ``--out DIR`` of a recorded command
_OUT_ARG = re.compile(r" --out \S+")
#: a generated block of a report: ``<!-- table FILE.json -->`` ... ``<!-- /table -->``
_TABLE_BLOCK = re.compile(r"(<!-- table ([\w.-]+\.json) -->\n)(.*?)(<!-- /table -->)", re.S)


def tables_into(doc: Path, bench_dir: Path) -> str:
    """``doc`` with every generated block replaced by the table of its summary file in ``bench_dir``
    (frictionless or frictional rows, with the command that wrote the file where it recorded one)."""
    def block(m):
        path = bench_dir / m.group(2)
        if not path.is_file():
            return m.group(1) + f"`{m.group(2)}`: not run.\n" + m.group(4)
        summaries = json.loads(path.read_text())
        cmds = list(dict.fromkeys(s["command"] for s in summaries if s.get("command")))
        lines = [f"From `{m.group(2)}`" + (" (" + "; ".join(f"`{c}`" for c in cmds) + ")" if cmds else "") + ":", ""]
        lines += frictionless_table(summaries) if all("mu" not in s for s in summaries) else friction_table(summaries)
        return m.group(1) + "\n".join(lines) + "\n" + m.group(4)

    return _TABLE_BLOCK.sub(block, doc.read_text())


def run(out_dir=None, cases=None, variants=None, log=print, repeat: int = 3, slide: float = 2.0,
        name: str = "ironing", command: str | None = None) -> Path:
    """``alcontact bench --suite ironing``: run the preset meshes :data:`CASES` (default: all of them).

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
            raise UnknownNameError("ironing benchmark case", case, list(CASES))
    for v in variants:
        if v not in VARIANTS and v not in FRICTION_VARIANTS:
            raise UnknownNameError("ironing benchmark variant", v, list(VARIANTS) + list(FRICTION_VARIANTS))
    all_rows, all_summaries = [], []
    for case in cases:
        rows, summaries, _ = run_case(case, variants, slide=slide, repeat=repeat, log=log)
        all_rows += rows
        all_summaries += summaries
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS)
    w.writeheader()
    w.writerows(all_rows)
    write_text_atomic(out / f"{name}.csv", buf.getvalue())
    cmd = command or ("alcontact bench --suite ironing" + "".join(f" --case {c}" for c in cases)
                      + "".join(f" --variant {v}" for v in variants))
    for s in all_summaries:
        s["command"] = cmd
    write_text_atomic(out / f"{name}.json", json.dumps(all_summaries, indent=1) + "\n")
    write_text_atomic(out / f"{name}.md", report(all_summaries, cases, cmd))
    return out


def merge(out: Path, name: str, parts) -> None:
    """``out/name.json`` and ``out/name.csv``: the summaries and per-step rows of the runs ``parts``, in order."""
    summaries, rows = [], []
    for part in parts:
        for summary in json.loads((out / f"{part}.json").read_text()):
            if summary.get("command"):  # where the part was written is no part of how to run it
                summary["command"] = _OUT_ARG.sub("", summary["command"])
            summaries.append(summary)
        with open(out / f"{part}.csv", newline="") as fh:
            rows += list(csv.DictReader(fh))
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS)
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(out / f"{name}.csv", buf.getvalue())
    write_text_atomic(out / f"{name}.json", json.dumps(summaries, indent=1) + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/benchmarks")
    ap.add_argument("--case", nargs="+", default=DEFAULT_CASES, choices=list(CASES))
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS) + list(FRICTION_VARIANTS))
    ap.add_argument("--slide", type=float, default=2.0, help="sliding distance in radii (default 2)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--name", default="ironing", help="base name of the output files")
    ap.add_argument("--tables", type=Path, default=None,
                    help="regenerate the tables of this report (docs/benchmarks/ironing.md) from the summaries in "
                         "--out, and run nothing")
    ap.add_argument("--merge", nargs="+", default=None, metavar=("NAME", "PART"),
                    help="write NAME.json / NAME.csv in --out from the summaries and rows of the runs PART ... there "
                         "(one run per case or variant, e.g. on a shared machine), and run nothing")
    args = ap.parse_args(argv)
    if args.merge is not None:
        merge(Path(args.out), args.merge[0], args.merge[1:])
        return 0
    if args.tables is not None:
        write_text_atomic(args.tables, tables_into(args.tables, Path(args.out)))
        return 0
    logging.basicConfig(level=logging.WARNING, format="%(message)s")
    run(args.out, args.case, args.variants, repeat=args.repeat, slide=args.slide, name=args.name,
        command="python benchmarks/ironing.py " + " ".join(argv if argv is not None else sys.argv[1:]))
    print((Path(args.out) / f"{args.name}.md").read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
