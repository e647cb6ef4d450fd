"""The results folder: one writer for a built-in run (:func:`write_results`) and a problem-file run
(:func:`write_setup_results`), and the per-step rows of ``steps.csv`` and ``reaction_force.csv``."""

from __future__ import annotations

import logging
import math
import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from .summary import _tolerances

__all__ = ["RESULT_FILES", "write_results", "write_setup_results"]

logger = logging.getLogger(__name__)


#: Files :func:`write_results` writes (``summary.json`` last).
RESULT_FILES: tuple[str, ...] = ("solution.vtu", "history.csv", "pressure.png", "convergence.png",
                                 "body_pressure.png", "body_von_mises.png", "report.md", "summary.json")



def _per_radian(model, summary: dict) -> dict[str, Any]:
    """A body of revolution (``geometry = "axisymmetric"``): its forces are totals over the revolution
    (2 pi integrated); the summary adds ``geometry`` and every force key again per radian (``<key>_per_radian``)."""
    if not model.axisymmetric:
        return {}
    out: dict[str, Any] = {"geometry": "axisymmetric",
                           "forces": "totals over the revolution (2 pi integrated); *_per_radian: divided by 2 pi"}

    def numbers(v):  # a number or a (nested) list of numbers
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return True
        return isinstance(v, list) and bool(v) and all(numbers(x) for x in v)

    def per_radian(v):
        return [per_radian(x) for x in v] if isinstance(v, list) else float(v) / (2.0 * math.pi)

    for key, v in summary.items():
        if "force" in key and numbers(v):
            out[f"{key}_per_radian"] = per_radian(v)
    return out


def write_results(out: str | os.PathLike, problem, solution, summary: dict, *,
                  tolerances: dict | None = None, units=None, description: str = "") -> dict[str, Path]:
    """Write the result files of :data:`RESULT_FILES` into the existing folder ``out``.

    Each file is written atomically; ``summary.json`` is written last. To get
    the whole set or nothing, write into :class:`alcontact.io.ResultsFolder`
    (as :func:`run_problem` does). ``units`` (:class:`alcontact.viz.Units`)
    label the plots. Returns ``{file name: path}``.
    """
    from ..io import write_history_csv, write_json, write_solution_vtu
    from ..io.report import write_report
    from ..viz import save_convergence_plot, save_pressure_plot
    from ..viz.pictures import save_body_pictures

    out = Path(out)
    paths = {name: out / name for name in RESULT_FILES}
    write_solution_vtu(paths["solution.vtu"], solution)
    write_history_csv(paths["history.csv"], solution.result.history)
    save_pressure_plot(solution, paths["pressure.png"], units=units)
    save_convergence_plot(solution.result, paths["convergence.png"], tolerances=tolerances)
    save_body_pictures(solution, out, units=units, title=summary.get("problem_label") or summary.get("problem"))
    write_report(paths["report.md"], summary, list(RESULT_FILES), description=description, units=units)
    write_json(paths["summary.json"], {**summary, **_per_radian(problem.model, summary), "files": list(RESULT_FILES)})
    logger.info("results written to %s", out)
    return paths


def _controls(setup) -> list[tuple[str, str, str, int]]:
    """Boundaries whose mean displacement is the abscissa of the load-displacement curve.

    The first ramped normal action and the first ramped tangential one:
    ``(label, kind, boundary, component)``.
    """
    from ..contact import Support

    out = []
    hist = setup.history
    if hist is None:
        return out
    for want in ("normal", "tangential"):
        for case in hist.cases:
            if case.tangential != (want == "tangential") or not hasattr(case.item, "boundary"):
                continue
            item = case.item
            dim = setup.problem.model.dim
            if isinstance(item, Support) and item.components is not None:
                comp = int(item.components[0])
            elif isinstance(item, Support):
                comp = int(np.argmax(np.abs(np.broadcast_to(np.asarray(item.value, float), (dim,)))))
            else:
                comp = dim - 1 if want == "normal" else 0
            out.append((f"{item.boundary}_{'xyz'[comp]}", want, item.boundary, comp))
            break
    return out


def _prescribed(setup, t: float) -> dict[str, float]:
    """What the problem file prescribes at pseudo-time ``t``: ``reaction_force.csv``'s leading columns.

    ``prescribed_u_<boundary>_<x|y|z>``: the value of each ramped support component (value x
    amplitude; zero throughout: left out by :func:`_prescribed_quantities`),
    ``load_factor_<load>``: the amplitude of each ramped load, ``obstacle_<x|y|z>`` and
    ``obstacle_travel``: the obstacle's translation ``t * path`` and the distance it has
    travelled along its (straight) path.
    """
    from ..contact import Support

    out: dict[str, float] = {}
    dim = int(setup.problem.model.dim)
    for case in (setup.history.cases if setup.history is not None else ()):
        a = float(case.value(t))
        item = case.item
        if isinstance(item, Support):
            if callable(item.value):  # a field of values (Python API): no single prescribed number
                continue
            comps = range(dim) if item.components is None else item.components
            for c in comps:
                v = item.value if np.ndim(item.value) == 0 else item.value[c]
                # components past the dimension are a rigid body's rotations (contact.RigidBody)
                axis = "xyz"[c] if c < dim else ("rot_z" if dim == 2 else f"rot_{'xyz'[c - dim]}")
                key = f"prescribed_u_{item.boundary}_{axis}"
                out[key] = out.get(key, 0.0) + float(v) * a
        else:
            out["load_factor_" + re.sub(r"\W+", "_", str(case.name or case.label)).strip("_")] = a
    if setup.obstacle_path is not None:
        off = setup.obstacle_offset(t)
        for c, v in zip("xyz", off):
            out[f"obstacle_{c}"] = float(v)
        out["obstacle_travel"] = float(np.linalg.norm(off))
    return out


def _prescribed_quantities(setup, rows, final) -> list[tuple[str, str, bool]]:
    """The prescribed quantities that change over the steps: ``(column, label, normal)``.

    ``normal``: a pressing action (a support not marked ``tangential``, an obstacle moving
    along the contact normal), preferred as the abscissa of a phase that has one.
    """
    from ..contact import Support

    if not rows:
        return []
    start = _prescribed(setup, 0.0)
    moving = [k for k in rows[0] if k.startswith(("prescribed_u_", "load_factor_", "obstacle_travel"))
              and any(abs(float(r[k]) - start.get(k, 0.0)) > 0 for r in rows)]
    tangential = set()
    for case in (setup.history.cases if setup.history is not None else ()):
        if case.tangential and isinstance(case.item, Support):
            tangential |= {k for k in moving if k.startswith(f"prescribed_u_{case.item.boundary}_")}
    out = []
    for k in moving:
        if k == "obstacle_travel":
            path = np.asarray(setup.obstacle_path, dtype=float)
            w = np.asarray(final.pressure, dtype=float)
            n = np.asarray(final.normals, dtype=float).T @ (w if w.sum() > 0 else np.ones_like(w))
            along = abs(float(path @ n)) / max(float(np.linalg.norm(path) * np.linalg.norm(n)), 1e-300)
            out.append((k, "obstacle travel along its path", along > 0.5))
        elif k.startswith("prescribed_u_"):
            boundary, comp = k[len("prescribed_u_"):].rsplit("_", 1)
            out.append((k, f"prescribed u_{comp} of {boundary}", k not in tangential))
        else:
            out.append((k, f"load factor of {k[len('load_factor_'):]}", True))
    return out


def _rigid_columns(states: dict) -> dict[str, float]:
    """Columns of the rigid bodies' states of one frame (``extra["rigid_bodies"]``): ``rigid_<body>_u_x``,
    ``rigid_<body>_rot_z``, ``rigid_<body>_reaction_F_y``, ``rigid_<body>_reaction_M_z``, ``rigid_<body>_contact_F_y``,
    ... (the reaction: what the prescribed components' drive applies; the contact force and moment on the body)."""
    row: dict[str, float] = {}
    for name, st in states.items():
        rot = ["z"] if len(st["displacement"]) == 2 else ["x", "y", "z"]
        head = f"rigid_{name}_"
        row.update({f"{head}u_{c}": float(v) for c, v in zip("xyz", st["displacement"])})
        row.update({f"{head}rot_{c}": float(v) for c, v in zip(rot, st["rotation"])})
        for key in ("reaction", "contact"):
            row.update({f"{head}{key}_F_{c}": float(v) for c, v in zip("xyz", st[f"{key}_force"])})
            row.update({f"{head}{key}_M_{c}": float(v) for c, v in zip(rot, st[f"{key}_moment"])})
    return row


def _step_rows(setup, frames, controls) -> list[dict[str, Any]]:
    from ..viz.plots import contact_half_width

    model = setup.problem.model
    meta = setup.problem.meta
    axis = int(meta.get("symmetry_axis", 0))
    rows = []
    for k, fr in enumerate(frames):
        ex = fr.extra
        tf = np.asarray(ex.get("tangential_force", np.zeros(model.dim)), dtype=float)
        row: dict[str, Any] = {
            "step": k + 1, "t": float(ex.get("t", setup.times[min(k, len(setup.times) - 1)])),
            "requested": int(bool(ex.get("requested", True))),  # 0: a sub-step inserted by a cut-back
            "status": fr.result.status.label,
            "outer_iterations": ex.get("step_outer_iterations", fr.result.outer_iterations),
            "newton_iterations": ex.get("step_newton_iterations", fr.result.newton_iterations),
            "normal_force": fr.normal_force,
            "tangential_force": float(np.linalg.norm(tf)),
            "peak_pressure": fr.peak_pressure,
            "contact_half_width": contact_half_width(fr, axis=axis, center=meta.get("center"),
                                                     declared=bool(meta.get("center_declared", True))),
            "active_points": int(np.count_nonzero(fr.active)),
            "penetration": fr.result.penetration,
        }
        for c, v in zip("xyz", np.asarray(fr.total_contact_force, dtype=float)):
            row[f"force_{c}"] = float(v)
        if "state" in ex:
            st = np.asarray(ex["state"])
            row.update(stick_points=int(np.sum(st == 1)), slip_points=int(np.sum(st == 2)),
                       coulomb=ex.get("coulomb"), cutbacks=ex.get("cutbacks", 0))
            if "dissipation" in ex:  # finite deformation: the frictional dissipation of the step
                row["dissipation"] = float(ex["dissipation"])
        if "seconds" in ex:  # finite deformation: the support reactions of the step (f_int - f_ext - f_c)
            row.update(cutbacks=int(ex.get("cutbacks", 0)), seconds=float(ex["seconds"]))
            for c, v in zip("xyz", fr.equilibrium().reaction):
                row[f"reaction_{c}"] = float(v)
        for label, _kind, boundary, comp in controls:
            _, dofs = model.node_dofs(boundary)
            row[f"u_{label}"] = float(np.mean(np.asarray(fr.u)[dofs[:, comp]]))
        row.update(_prescribed(setup, row["t"]))
        row.update(_rigid_columns(fr.extra.get("rigid_bodies", {})))
        rows.append(row)
    return rows


def _add_tangential_curves(fig, rows, control: str | None, dim: int) -> None:
    """Add the components of the reaction and contact force that :func:`reaction_force_figure` does not
    plot (with friction: the tangential ones) to its axes, against the same abscissa."""
    if not rows or not fig.axes:
        return
    ax = fig.axes[0]
    axes = "xyz"[:dim]
    if control is not None and control[-1:] in axes:
        shown = control[-1]
        x = np.array([float(r[f"u_{control}"]) for r in rows])
    else:  # the component reaction_force_figure picks
        shown = max(axes, key=lambda c: max(abs(float(r.get(f"reaction_{c}", r.get(f"force_{c}", 0.0))))
                                            for r in rows))
        x = np.array([float(r["t"]) for r in rows])
    x = np.concatenate([[0.0], x])
    for c in axes:
        if c == shown:
            continue
        for key, style, label in ((f"reaction_{c}", "^-", f"support reaction R_{c} (tangential)"),
                                  (f"force_{c}", "v--", f"contact force F_{c} on the body (friction)")):
            y = np.concatenate([[0.0], [float(r.get(key, np.nan)) for r in rows]])
            ax.plot(x, y, style, ms=4, label=label)
    ax.legend(fontsize="small")


def _reaction_rows(rows, controls) -> list[dict[str, Any]]:
    """Columns of ``reaction_force.csv``: step, t, the driving displacements, reactions and contact forces."""
    keep = ("step", "t", "requested") + tuple(f"u_{c[0]}" for c in controls)
    lead = ("prescribed_u_", "load_factor_", "obstacle_")
    return [{**{k: v for k, v in r.items() if k in keep or k.startswith(lead)},
             **{k: v for k, v in r.items() if k.startswith(("reaction_", "force_", "rigid_"))}} for r in rows]


def _write_rows_csv(path, rows) -> Path:
    import csv
    import io as _io

    from ..io import write_text_atomic

    cols: list[str] = []
    for r in rows:
        cols += [c for c in r if c not in cols]
    buf = _io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (repr(float(v)) if isinstance(v, (float, np.floating)) else v) for k, v in r.items()})
    return write_text_atomic(path, buf.getvalue())


def write_setup_results(folder: Path, setup, frames, summary: dict) -> list[str]:
    """Write the results folder of a problem-file run; return the file names (``summary.json`` last).

    Files (switched by ``[output]``): ``solution.vtu`` (final state), ``steps/solution_NNNN.vtu``
    and ``solution.pvd`` (stepped runs), ``history.csv`` (outer iterations of
    the last frictionless solve), ``steps.csv``, ``pressure.png``,
    ``convergence.png``, ``load_displacement.png``, ``body_pressure.png`` and
    ``body_von_mises.png`` (pictures of the deformed body), ``report.md``, ``summary.json``.
    Finite-deformation runs write the VTU files in the deformed configuration and
    add ``reaction_force.csv`` and ``reaction_force.png`` (support reaction and
    contact force against the prescribed displacement, per step).
    """
    from ..io import write_history_csv, write_json, write_pvd, write_solution_vtu
    from ..io.report import write_report

    o = setup.output
    units = setup.plot_units()
    final = frames[-1]
    friction = setup.friction > 0
    stepped = len(frames) > 1 or setup.stepped
    files: list[str] = []
    if o["vtu"]:
        write_solution_vtu(folder / "solution.vtu", final)
        files.append("solution.vtu")
        if o["series"] and stepped:
            (folder / "steps").mkdir(exist_ok=True)
            entries = []
            for k, fr in enumerate(frames):
                rel = f"steps/solution_{k + 1:04d}.vtu"
                write_solution_vtu(folder / rel, fr)
                entries.append((fr.extra.get("t", k + 1), rel))
            write_pvd(folder / "solution.pvd", entries)
            files += ["solution.pvd", "steps/"]
    controls = _controls(setup)
    rows = _step_rows(setup, frames, controls)
    if o["csv"]:
        if not friction:
            write_history_csv(folder / "history.csv", final.result.history)
            files.append("history.csv")
        _write_rows_csv(folder / "steps.csv", rows)
        files.append("steps.csv")
        if setup.finite or any(fr.extra.get("rigid_bodies") for fr in frames):  # per step: supports' or rigid bodies' reactions
            _write_rows_csv(folder / "reaction_force.csv", _reaction_rows(rows, controls))
            files.append("reaction_force.csv")
    if o["plots"]:
        from ..viz import save_convergence_plot, save_figure, save_pressure_plot
        from ..viz.plots import load_displacement_figure, steps_figure

        meta = setup.problem.meta
        save_pressure_plot(final, folder / "pressure.png", mindlin=setup.mindlin,
                           axis=int(meta.get("symmetry_axis", 0)), units=units)
        files.append("pressure.png")
        if "master_side" in final.extra:  # a pair between two bodies: the pressure on both sides
            from ..viz.interface import save_interface_pressure_plot

            save_interface_pressure_plot(final, folder / "interface_pressure.png",
                                         axis=int(meta.get("symmetry_axis", 0)), units=units,
                                         title=f"{setup.name}: contact pressure on both sides")
            files.append("interface_pressure.png")
        if friction:
            save_figure(steps_figure(rows, title=f"{setup.name}: {summary['status']}"), folder / "convergence.png")
        else:
            save_convergence_plot(final.result, folder / "convergence.png", tolerances=_tolerances(setup.options))
        files.append("convergence.png")
        from ..viz.plots import force_path_figure

        dim = int(setup.problem.model.dim)
        quantities = _prescribed_quantities(setup, rows, final)  # what the file prescribes and the run moved
        start = _prescribed(setup, 0.0)
        if stepped:
            if quantities and not any(q[0].startswith("load_factor_") for q in quantities):
                # displacement-driven (supports, the obstacle's path): forces against what was prescribed,
                # one panel per phase (press, then slide)
                fig = force_path_figure(rows, quantities, start=start, title=setup.name, units=units, dim=dim)
            else:  # load-driven: the loads' effect, the mean displacement of the loaded boundary
                fig = load_displacement_figure(rows, [(c[0], c[1]) for c in controls], title=setup.name, dim=dim,
                                               units=units)
            save_figure(fig, folder / "load_displacement.png")
            files.append("load_displacement.png")
        if setup.finite:
            from ..viz.plots import reaction_force_figure

            title = f"{setup.name}: reaction-force curve"
            if quantities:  # one panel per phase of the prescribed path, against what was prescribed
                fig = force_path_figure(rows, quantities, start=start, title=title, units=units, dim=dim)
            else:
                control = next((c[0] for c in controls if c[1] == "normal"), None)
                fig = reaction_force_figure(rows, control, title=title, dim=dim, units=units)
                if friction:
                    _add_tangential_curves(fig, rows, control, dim)
            save_figure(fig, folder / "reaction_force.png")
            files.append("reaction_force.png")
        from ..viz.pictures import save_body_pictures

        files += save_body_pictures(final, folder, units=units, title=setup.name)
    if o["report"]:
        files.append("report.md")
        write_report(folder / "report.md", summary, files + ["summary.json"],
                     description=setup.data["problem"]["description"],
                     source=str(setup.source) if setup.source else None, units=units)
    files.append("summary.json")
    write_json(folder / "summary.json", {**summary, **_per_radian(setup.problem.model, summary), "files": files})
    logger.info("results written to %s", folder)
    return files
