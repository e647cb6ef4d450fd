"""``report.md``: a one-page markdown summary of a results folder.

It states the problem and the solver, the outcome (status, iterations, time),
the key numbers against the analytical reference where there is one, embeds
the PNG plots and lists the other files with what they hold.
"""

from __future__ import annotations

import os
from pathlib import Path

from .results import write_text_atomic

__all__ = ["render_report", "write_report"]

_FILE_DOCS = {
    "summary.json": "every number of this page (stable keys, see `alcontact.io.SUMMARY_KEYS`)",
    "solution.vtu": "final state: displacement, stress, von Mises, contact pressure, gap, contact state "
                    "(+ slip for friction); ParaView: File > Open, Apply, colour by a field, Filters > Warp By Vector",
    "solution.pvd": "all load steps as a ParaView time series (open this file, then use the time controls)",
    "history.csv": "outer iterations of the (last) solve: penetration, complementarity, multiplier change",
    "steps.csv": "one row per load step: forces, contact zone, iterations, control displacements",
    "pressure.png": "contact pressure along the contact boundary (and tangential traction for friction)",
    "convergence.png": "convergence history",
    "load_displacement.png": "contact force against the prescribed displacement or obstacle travel, one panel per "
                             "phase of the path (press, then slide); load-driven runs: against the mean "
                             "displacement of the loaded boundary",
    "steps/": "one VTU per load step (referenced by solution.pvd)",
    "reaction_force.csv": "finite deformation: per step the prescribed quantities (support displacements "
                          "prescribed_u_*, obstacle position obstacle_* and its travel along the path, load "
                          "factors), the support reaction and the contact force; a rigid body: its pose "
                          "(rigid_<body>_u_*, _rot_*), the reaction of its prescribed components and the contact "
                          "force and moment on it, per step",
    "interface_pressure.png": "a pair between two bodies: the contact pressure along the interface on both sides "
                              "(slave: solved; master: the slave nodal forces carried by the mortar weights)",
    "reaction_force.png": "reaction and contact force against what was prescribed, one panel per phase of the "
                          "path (press, then slide)",
    "body_pressure.png": "picture of the deformed body coloured by contact pressure",
    "body_von_mises.png": "picture of the deformed body coloured by von Mises stress",
}


#: finite deformation: the VTU points are the deformed positions already
_FINITE_FILE_DOCS = {
    "solution.vtu": "final state in the deformed configuration (the points are already moved: do not warp "
                    "it again): displacement, stress, von Mises, contact pressure, gap, contact state (+ slip "
                    "for friction); ParaView: File > Open, Apply, colour by a field",
    "solution.pvd": "all load steps as a ParaView time series, each in its deformed configuration (open this "
                    "file, then use the time controls; no Warp By Vector needed)",
}

#: Pictures of the body (alcontact.viz.pictures) shown in their own section.
_PICTURES = (("body_pressure.png", "Deformed body coloured by contact pressure"),
             ("body_von_mises.png", "Deformed body coloured by von Mises stress"))


def _f(x, spec=".5g") -> str:
    if x is None:
        return "-"
    if isinstance(x, float):
        return format(x, spec)
    return str(x)


def _half_width_label(s: dict) -> str:
    if s.get("contact_half_width_measure") == "half the extent of the loaded zone":
        return "contact half-width a: half the extent of the loaded zone"
    return "contact half-width a" + (" (contact radius)" if s.get("dim") == 3 else "")


def _linear_solve_rows(s: dict) -> list[str]:
    """What one linear solve took: a factorization + solve of the stiffness, or the mean Newton solve."""
    if s.get("linear_solve_time_kind") == "mean Newton linear solve":
        return [
            f"| one Newton linear solve, mean of {s.get('linear_solve_count')} (s) | "
            f"{_f(s.get('linear_solve_time_s'), '.3g')} | | |",
            f"| all linear solves together (s) | {_f(s.get('linear_solve_time_total_s'), '.3f')} | | |",
            f"| wall time / one Newton linear solve | {_f(s.get('time_ratio_contact_to_linear'), '.2f')} | | |",
        ]
    if s.get("kinematics") == "finite":  # the solver did not time its linear solves
        return []
    return [
        f"| one linear elastic solve: factorization + solve (s) | {_f(s.get('linear_solve_time_s'), '.3f')} | | |",
        f"| wall time / linear solve | {_f(s.get('time_ratio_contact_to_linear'), '.2f')} | | |",
    ]


def _header_lines(s: dict, description: str, source: str | None) -> list[str]:
    """Title, description, problem file, status and the one-line description of the run."""
    ok = s.get("status") == "converged"
    lines = [f"# {s.get('problem_label') or s.get('problem')}", ""]
    if description:
        lines += [description, ""]
    if source:
        lines += [f"Problem file: `{source}`", ""]
    return lines + [
        f"**Status: {s.get('status')}**" + ("" if ok else f" -- {s.get('message')}"),
        "",
        f"{s.get('dim')}D, P{s.get('order')}, {s.get('dofs')} DOFs; algorithm `{s.get('algorithm')}`, "
        f"penalty `{s.get('penalty')}`"
        + (f"; Coulomb friction mu = {s['friction']:g}" if s.get("friction") else "; frictionless")
        + (f"; {s['load_steps']} load steps" if s.get("load_steps", 1) > 1 else "") + ".",
        "",
    ]


def _reference_rows(s: dict, L: str, S: str, F: str) -> list[str]:
    """The table head and the rows compared with the analytical reference (Hertz width and peak pressure)."""
    return [
        "| quantity | computed | reference | error % |",
        "|---|---|---|---|",
        f"| {_half_width_label(s)} ({L}) | {_f(s.get('contact_half_width'))} | "
        f"{_f(s.get('contact_half_width_exact'))} | {_f(s.get('contact_half_width_error_pct'), '+.2f')} |",
        f"| peak pressure p0 ({S}) | {_f(s.get('peak_pressure'))} | {_f(s.get('peak_pressure_exact'))} | "
        f"{_f(s.get('peak_pressure_error_pct'), '+.2f')} |",
        f"| total contact force P ({F}) | {_f(s.get('total_contact_force'))} | | |",
    ]


def _finite_rows(s: dict, notes: list[str]) -> list[str]:
    """Finite deformation: Newton iterations per accepted step (sub-steps marked *), cut-backs, residual."""
    if s.get("kinematics") != "finite":
        return []
    newton = s.get("step_newton_iterations", [])
    asked = s.get("step_requested") or [True] * len(newton)
    marked = " ".join(f"{n}" if r else f"{n}*" for n, r in zip(newton, asked))
    lines = [f"| finite deformation ({s.get('material_model')}): Newton iterations per accepted step | "
             f"{marked} | | |",
             f"| cut-backs / equilibrium residual | {s.get('cutbacks')} / "
             f"{_f(s.get('equilibrium_residual'), '.2e')} | | |"]
    if not all(asked):
        notes.append(f"Load steps: {sum(1 for r in asked if not r)} of the {len(asked)} accepted steps "
                     "(marked *) are sub-steps that cut-backs inserted (a failed step's increment halved); "
                     "`summary.json` lists every accepted step in `step_times`, and `step_requested` says "
                     "which were requested.")
    return lines


def _friction_rows(s: dict, L: str, F: str, notes: list[str]) -> list[str]:
    """Coulomb friction: tangential force against mu N, stick/slip/open counts, stick half-width."""
    if not s.get("friction"):
        return []
    lines = [f"| tangential force of the model, resultant \\|Q\\| = \\|sum q_i\\| ({F}) | "
             f"{_f(s.get('tangential_force'))} | <= mu N = {_f(s.get('coulomb_limit'))} | |"]
    if s.get("tangential_force_magnitude_sum") is not None:
        lines.append(f"| sum of the nodal tangential force magnitudes, sum \\|q_i\\| ({F}) | "
                     f"{_f(s.get('tangential_force_magnitude_sum'))} | <= mu N = {_f(s.get('coulomb_limit'))} | |")
        notes.append("Friction: every contact point obeys Coulomb's law |q_i| <= mu p_i (= where it "
                     "slips), so sum |q_i| <= mu N, with equality when every loaded point slips. The "
                     "resultant |Q| is smaller than sum |q_i| where the tangent directions turn over "
                     "the contact zone (a curved or deformed surface) or the points slip in different "
                     "directions; |Q| < mu N is then no sign of sticking.")
    lines.append(f"| stick / slip / open points | {s.get('stick_points')} / {s.get('slip_points')} / "
                 f"{s.get('open_points')} | | |")
    if s.get("stick_half_width_exact") is not None:
        lines.append(f"| stick half-width c ({L}) | {_f(s.get('stick_half_width'))} | "
                     f"{_f(s.get('stick_half_width_exact'))} | {_f(s.get('stick_half_width_error_pct'), '+.2f')} |")
    return lines


def _cost_rows(s: dict) -> list[str]:
    """Iterations, linear solves, penetration and times."""
    stepped = s.get("load_steps", 1) > 1
    return [
        f"| outer / Newton iterations{' (all steps)' if stepped else ''} | {s.get('outer_iterations')} / "
        f"{s.get('newton_iterations')} | | |",
        f"| linear solves | {s.get('linear_solves')} | | |",
        f"| max penetration / h | {_f(s.get('penetration'), '.2e')} | | |",
        f"| wall time{' of all steps' if stepped else ''} (s) | {_f(s.get('wall_time_s'), '.3f')} | | |",
    ] + _linear_solve_rows(s)


def _vec(v) -> str:
    return "(" + ", ".join(format(float(x), ".5g") for x in v) + ")"


def _pair_lines(s: dict, F: str) -> list[str]:
    """Pairs between bodies (the contact force on each side, action = reaction) and rigid bodies (pose, forces)."""
    lines = []
    pairs = s.get("contact_pairs") or []
    if pairs:
        lines += ["## Contact pairs", "",
                  f"| slave | master | force on the slave ({F}) | force on the master ({F}) | "
                  "abs(F_s + F_m) / abs(F_s) |", "|---|---|---|---|---|"]
        lines += [f"| `{p['slave']}` | `{p['master']}` | {_vec(p['slave_force'])} | {_vec(p['master_force'])} | "
                  f"{_f(p['contact_force_balance'], '.2e')} |" for p in pairs]
        forces = s.get("body_contact_forces") or {}
        if forces:
            lines += ["", "Contact force on each body: " + ", ".join(f"`{k}` {_vec(v)}" for k, v in forces.items())
                      + f" ({F}).", ""]
    rigid = s.get("rigid_bodies") or {}
    if rigid:
        lines += ["## Rigid bodies", "",
                  "The pose of the reference point (translation, rotation in radians), the contact force and moment "
                  "on the body (about its reference point), and the reaction of its prescribed components (what "
                  "the drive applies; zero on the force-driven ones, which are in equilibrium).", "",
                  "| body | prescribed | translation | rotation | contact force | contact moment | applied force "
                  "| applied moment | reaction force | reaction moment |", "|---|---|---|---|---|---|---|---|---|---|"]
        for name, st in rigid.items():
            lines.append(f"| `{name}` | {', '.join(st['prescribed']) or 'none'} | {_vec(st['displacement'])} | "
                         f"{_vec(st['rotation'])} | {_vec(st['contact_force'])} | {_vec(st['contact_moment'])} | "
                         f"{_vec(st['applied_force'])} | {_vec(st['applied_moment'])} | "
                         f"{_vec(st['reaction_force'])} | {_vec(st['reaction_moment'])} |")
        lines.append("")
    return lines


def _figure_lines(files: list[str]) -> list[str]:
    """The plots present in the folder, then the pictures of the body in their own section."""
    lines = []
    for png, caption in (("pressure.png", "Contact pressure"), ("interface_pressure.png", "Pressure on both sides"),
                         ("convergence.png", "Convergence"),
                         ("load_displacement.png", "Load-displacement curve"),
                         ("reaction_force.png", "Reaction-force curve")):
        if png in files:
            lines += [f"![{caption}]({png})", ""]
    pictures = [(png, caption) for png, caption in _PICTURES if png in files]
    if pictures:
        lines += ["## Pictures of the body", "",
                  "The deformed body (small-deformation runs: displacement magnified, the factor is in the title); "
                  "2D: the whole body and the mesh near the contact zone; 3D: the boundary surface.", ""]
        for png, caption in pictures:
            lines += [f"![{caption}]({png})", ""]
    return lines


def _file_lines(files: list[str], deformed: bool) -> list[str]:
    """The files of the folder with what each holds (``report.md`` itself left out)."""
    lines = ["## Files", ""]
    for name in files:
        if name == "report.md":
            continue
        doc = _FINITE_FILE_DOCS.get(name) if deformed else None
        lines.append(f"- `{name}`: {doc or _FILE_DOCS.get(name, '')}".rstrip(": "))
    return lines + [""]


def render_report(summary: dict, files: list[str], *, description: str = "", source: str | None = None,
                  units=None) -> str:
    """The markdown text of ``report.md``.

    Parameters
    ----------
    summary : dict
        The ``summary.json`` dictionary.
    files : list of str
        Names of the files in the results folder (listed with what they hold).
    description, source : str
        Free text and the problem file, shown under the title.
    units : alcontact.viz.Units, optional
        Units of the quantities (default: those of the problem, unnamed).
    """
    from ..viz.plots import Units

    u = units if units is not None else Units()
    s = summary
    L, S, F = u.length, u.pressure, u.force(int(s.get("dim") or 2))
    notes: list[str] = []
    lines = (_header_lines(s, description, source) + _reference_rows(s, L, S, F) + _finite_rows(s, notes)
             + _friction_rows(s, L, F, notes) + _cost_rows(s))
    lines += [""] + [line for note in notes for line in (note, "")]
    lines += _pair_lines(s, F)
    lines += _figure_lines(files) + _file_lines(files, s.get("kinematics") == "finite")
    return "\n".join(lines)


def write_report(path: str | os.PathLike, summary: dict, files: list[str], **kwargs) -> Path:
    """Write :func:`render_report` to ``path`` atomically."""
    return write_text_atomic(path, render_report(summary, files, **kwargs))
