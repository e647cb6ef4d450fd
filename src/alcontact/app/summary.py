"""The ``summary.json`` dictionary of a run: :func:`summarize` (one state against its reference),
:func:`setup_summary` (a problem-file run, its steps and totals) and :func:`what_to_try`."""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
from typing import Any

import numpy as np

from .. import __version__

__all__ = ["summarize", "setup_summary", "equilibrium_keys", "what_to_try", "ADVICE"]

#: keys of ``solution.extra`` of a two-body (mortar) pair copied to ``summary.json``: the contact force on each
#: side and ``contact_force_balance`` = |F_slave + F_master| / |F_slave| (action = reaction); ``rigid_bodies``: the pose,
#: contact force and moment, applied load and reaction of every rigid body (:class:`alcontact.contact.RigidBody`)
TWO_BODY_KEYS = ("slave_contact_force", "master_contact_force", "contact_force_balance", "rigid_bodies",
                 "body_contact_forces", "contact_pairs")


def _finite_or_none(x) -> float | None:
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _error_pct(num, exact) -> float | None:
    if num is None or exact is None or exact == 0:
        return None
    return 100.0 * (num - exact) / exact


def _complementarity(gap, pressure, h: float) -> float:
    """The ``complementarity`` measure of :func:`alcontact.contact.check_state` of a returned step (the one its
    verification checked)."""
    from ..contact import check_state

    return check_state(gap, pressure, h, tol_penetration=1.0, tol_complementarity=1.0).value("complementarity")


def equilibrium_keys(eq) -> dict[str, Any]:
    """``summary.json`` keys of an :class:`~alcontact.contact.solution._estimators.Equilibrium`."""
    return {
        "equilibrium_residual": float(eq.residual),
        "equilibrium_free_residual": float(eq.free_residual),
        "reaction_force_vector": [float(x) for x in eq.reaction],
        "applied_load_vector": [float(x) for x in eq.applied_load],
        "contact_force_from_nodal_forces": [float(x) for x in eq.contact_force],
    }


def _half_width_measure(solution, axis: int, center) -> str:
    from ..viz.plots import contact_center

    return "from the contact centre" if contact_center(solution, center, declared=False) is not None \
        else "half the extent of the loaded zone"


def summarize(problem, solution, *, problem_name: str | None = None, level: int | None = None,
              options: dict | None = None, build_time_s: float | None = None) -> dict[str, Any]:
    r"""The ``summary.json`` dictionary of a solved problem.

    Stable keys (:data:`alcontact.io.SUMMARY_KEYS`):

    ``status``
        ``"converged"`` or the failure label (``"maxiter"``, ``"newton-failed"``,
        ``"no-contact"``, ``"nonfinite"``, ``"penalty-limit"``).
    ``algorithm``, ``penalty``
        Registry names (the penalty actually used, e.g. ``"rockafellar"`` for simo-laursen).
    ``dofs``, ``outer_iterations``, ``newton_iterations``, ``linear_solves``
        Model size and solver counters.
    ``wall_time_s``
        Wall time of :func:`alcontact.contact.solve` (setup, factorization,
        contact iterations; not the mesh generation nor the file output).
    ``linear_solve_time_s``
        One factorization plus one solve of the same stiffness, measured in the
        same run (``solution.timings["linear_solve_s"]``), so
        ``time_ratio_contact_to_linear`` compares the contact solve with a linear one.
        Finite-deformation runs (:func:`run_setup`): the mean of the run's Newton linear
        solves (``linear_solve_time_kind = "mean Newton linear solve"``), with their total
        ``linear_solve_time_total_s`` and number ``linear_solve_count``.
    ``contact_half_width``, ``contact_half_width_exact``
        Computed half-width ``a`` (contact radius in 3D) and the analytical one
        for the load the model carries. Measured from the contact centre
        (``problem.meta["center"]``); a problem file's centre that is only the default
        origin (``meta["center_declared"]`` false) is used while it lies in the
        contact zone, otherwise ``a`` is half the extent of the loaded zone
        (:func:`alcontact.viz.contact_half_width`), never the distance of the zone
        from the origin.
    ``peak_pressure``, ``peak_pressure_exact``
        Estimated peak pressure and the analytical ``p0``.
    ``total_contact_force``
        Total load ``P`` of the full (unsymmetrized) body:
        ``reference.load(normal_force)``, i.e. 2x the half model's contact force
        in 2D (per unit thickness) and 4x the quarter model's in 3D; the
        model's own force is ``model_contact_force``, the sum of the normal nodal
        contact forces the solver applied. Without a reference, the model's force.

    Estimators (``docs/estimators.md``): for a problem whose reference is a Hertz
    profile, ``peak_pressure`` is ``p0`` of the L2 least-squares fit of
    :math:`p_0\sqrt{1-r^2/a^2}` to the recovered pressure and ``contact_half_width``
    is ``a`` of the load-matched fit (the profile carries the model's contact load);
    otherwise the largest recovered pressure and the outermost loaded point
    interpolated along the boundary. ``peak_pressure_nodal_max`` is the raw
    largest nodal pressure, ``contact_half_width_edge`` the interpolated edge.
    ``equilibrium_residual`` is :math:`|F_c + F_{ext} + R|` (contact force, applied loads,
    support reactions; ``contact_force_vector``, ``applied_load_vector``,
    ``reaction_force_vector``) and ``equilibrium_free_residual`` the largest imbalance on a
    free DOF, both over the force scale of :func:`alcontact.contact.solution._estimators.equilibrium`
    (which does not vanish with the contact force); a converged result has both below its
    equilibrium tolerance (``newton_tol``, at least 1e-11; see :mod:`alcontact.contact._verify`),
    as ``penetration`` and ``complementarity``, the measures the verification checked on the
    returned state, are below theirs.

    ``linear_solver`` is the registry name of the linear solver that ran
    (``solution.extra["linear_solver"]``, e.g. ``"mkl-pardiso"`` for ``linear_solver = "auto"``),
    ``linear_solver_strategy`` how its systems were solved (``"condensed"`` on the contact points,
    ``"krylov"`` in the full space, ``"full-space-newton"`` at finite deformation); a problem-file run
    (:func:`setup_summary` through :func:`~alcontact.app.pipeline.run_setup`) adds ``petsc_options``,
    the PETSc options the solve ran with.

    Exact values and errors are ``None`` when the problem has no analytical reference.
    Extras: ``problem``, ``problem_label``, ``level``, ``dim``, ``order``,
    ``status_code``, ``message``, the errors in percent, ``penetration``,
    ``complementarity``, ``residual``, ``eps_n``, ``time_ratio_contact_to_linear``,
    ``timings``, ``options``, ...
    """
    res = solution.result
    model = problem.model
    meta = getattr(problem, "meta", None) or {}
    ref = getattr(problem, "reference", None)
    center = meta.get("center")
    axis = int(meta.get("symmetry_axis", 0))

    from ..viz.plots import edge_search_applies, contact_half_width

    declared = bool(meta.get("center_declared", True))
    if (declared or center is None) and edge_search_applies(solution):
        a_num = float(solution.contact_half_width(axis=axis, center=center))
        a_edge = float(solution.contact_half_width_edge(axis=axis, center=center))
    else:  # a problem file's default centre (the origin) only while it lies in the contact zone; a curved 3D
        # boundary has no line of a flat plane to search the edge on (viz.contact_half_width)
        a_num = a_edge = contact_half_width(solution, axis=axis, center=center, declared=declared)
    p_num = float(solution.peak_pressure)
    p_max = float(solution.peak_pressure_nodal_max)
    f_model = float(solution.normal_force)
    eq = solution.equilibrium()
    a_ex = p_ex = None
    load = f_model
    if ref is not None:
        load = float(ref.load(f_model))
        if load > 0:
            try:  # a load or radius at the edge of double precision: no reference rather than a traceback
                a_ex = float(ref.half_width(load))
                p_ex = float(ref.peak_pressure(load))
            except (ZeroDivisionError, OverflowError):
                a_ex = p_ex = None
            a_ex, p_ex = (None, None) if a_ex is None or not (math.isfinite(a_ex) and a_ex > 0
                                                               and math.isfinite(p_ex)) else (a_ex, p_ex)
    wall = float(solution.timings.get("total_s", float("nan")))
    lin = float(solution.timings.get("linear_solve_s", float("nan")))
    ratio = wall / lin if lin > 0 else None

    summary: dict[str, Any] = {
        # --- stable contract (SUMMARY_KEYS) ---
        "status": res.status.label,
        "algorithm": res.algorithm,
        "penalty": res.penalty,
        "dofs": int(solution.extra.get("dofs", model.ndofs)),
        "outer_iterations": int(res.outer_iterations),
        "newton_iterations": int(res.newton_iterations),
        "linear_solves": int(res.linear_solves),
        "wall_time_s": _finite_or_none(wall),
        "linear_solve_time_s": _finite_or_none(lin),
        "contact_half_width": a_num,
        "contact_half_width_exact": a_ex,
        "peak_pressure": p_num,
        "peak_pressure_exact": p_ex,
        "total_contact_force": load,
        # --- extras ---
        "problem": problem_name or getattr(problem, "name", "contact"),
        "problem_label": getattr(problem, "name", None),
        "level": level,
        "dim": int(model.dim),
        "order": int(getattr(model, "order", 1)),
        "status_code": int(res.status),
        "message": res.message,
        "contact_half_width_error_pct": _error_pct(a_num, a_ex),
        "contact_half_width_measure": "from the contact centre" if declared or center is None or a_ex is not None
        else _half_width_measure(solution, axis, center),
        "peak_pressure_error_pct": _error_pct(p_num, p_ex),
        "model_contact_force": f_model,
        "contact_force_vector": np.asarray(solution.total_contact_force, dtype=float).tolist(),
        **{k: solution.extra[k] for k in TWO_BODY_KEYS if k in solution.extra},
        "pair_contact_forces": _pair_forces(problem, solution),
        **equilibrium_keys(eq),
        "peak_pressure_nodal_max": p_max,
        "peak_pressure_nodal_max_error_pct": _error_pct(p_max, p_ex),
        "contact_half_width_edge": a_edge,
        "contact_half_width_edge_error_pct": _error_pct(a_edge, a_ex),
        "penetration": float(res.penetration),
        "complementarity": float(res.complementarity),
        "residual": float(res.residual),
        "eps_n": float(res.eps_n),
        # the multiplier of the automatic eps_n that ran, where the solver records it (it may be the algorithm's)
        **({"penalty_scale": solution.extra["penalty_scale"]} if "penalty_scale" in solution.extra else {}),
        "factorizations": int(res.factorizations),
        "linear_solver": solution.extra.get("linear_solver"),
        "linear_solver_strategy": solution.extra.get("strategy"),
        "time_ratio_contact_to_linear": ratio,
        "build_time_s": build_time_s,
        "element_size_h": solution.extra.get("h"),
        "contact_candidates": solution.extra.get("candidates"),
        "active_points": int(np.count_nonzero(solution.active)),
        "timings": dict(solution.timings),
        "options": dict(options or {}),
        "alcontact_version": __version__,
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
    }
    return summary


def _pair_forces(problem, solution) -> list[dict[str, Any]]:
    """Per contact pair: its slave boundary, its master and the contact force it puts on the body."""
    pairs = getattr(problem, "pairs", ())
    forces = solution.pair_contact_forces()
    return [{"slave": p.slave.name, "master": p.master.describe(), "force": [float(x) for x in f]}
            for p, f in zip(pairs, forces)]


def _tolerances(options: dict) -> dict[str, float]:
    from ..contact import ContactOptions

    known = {f.name for f in dataclasses.fields(ContactOptions)}
    opts = ContactOptions(**{k: v for k, v in options.items() if k in known})
    return {
        "penetration": opts.tol_penetration,
        "complementarity": opts.tol_complementarity,
        "multiplier_change": opts.tol_multiplier,
    }


#: One line of advice per failure label (:func:`what_to_try`).
ADVICE = {
    "maxiter": "raise the iteration limit (--maxiter), try another algorithm (--algorithm ssn or "
               "--algorithm family-p), or a different penalty stiffness (--penalty-scale).",
    "newton-failed": "lower the penalty stiffness (--penalty-scale 10), try another penalty "
                     "(--algorithm family-p --penalty NAME, see `alcontact list`) or --algorithm ssn.",
    "nonfinite": "lower the penalty stiffness (--penalty-scale), or use a penalty without a barrier "
                 "(--penalty exp-met1); check the material constants and loads.",
    "penalty-limit": "the penalty stiffness hit its limit: raise --maxiter, or use an augmented "
                     "Lagrangian algorithm (simo-laursen, family-p) instead of the pure penalty.",
    "no-contact": "the body does not reach the obstacle: move the obstacle closer, increase the "
                  "load or check the contact boundary name.",
    "unbounded": "no static equilibrium: the loads exceed what the supports, the obstacle and friction can "
                 "hold (see the message); prescribe that motion as a displacement, or add a support.",
    "not-verified": "the returned state fails a tolerance (see the message): tighten newton_tol, raise "
                    "--maxiter, or try --algorithm ssn; report it if the reference fails too.",
}


def what_to_try(status) -> str:
    """One line of advice for a failed solve (empty when it converged).

    ``status``: a ``ContactResult``, a ``ContactStatus`` or its label
    (``summary["status"]``).
    """
    status = getattr(status, "status", status)
    label = getattr(status, "label", status)
    if label == "converged":
        return ""
    return ADVICE.get(str(label), "try another algorithm (see `alcontact list`).")


def _finite_friction_summary(setup, fs, frames) -> dict[str, Any]:
    """``summary.json`` keys of the friction of a finite-deformation run (per accepted step, and the totals)."""
    final = frames[-1]
    steps = fs.steps
    tf = np.asarray(final.extra["tangential_force"], dtype=float)
    st = np.asarray(final.extra["state"])
    return {
        "step_dissipation": [float(s.dissipation) for s in steps],
        "dissipation": float(sum(s.dissipation for s in steps)),
        "step_normal_force": [float(s.normal_force) for s in steps],
        "step_tangential_force": [[float(x) for x in s.tangential_force] for s in steps],
        "step_stored_energy": [float(s.stored_energy) for s in steps],
        "step_obstacle_offset": [[float(x) for x in s.offset] for s in steps],
        "tangential_force": float(np.linalg.norm(tf)), "tangential_force_vector": tf.tolist(),
        "coulomb_limit": float(setup.friction * final.normal_force),
        "stick_points": int(np.sum(st == 1)), "slip_points": int(np.sum(st == 2)), "open_points": int(np.sum(st == 0)),
        "eps_t": float(fs.extra["eps_t"]),
    }


#: keys of ``solution.extra`` of a finite-deformation run copied to ``summary.json``
_FINITE_SOLVER_KEYS = ("amg_setups", "cg_iterations", "cg_per_newton",
                       "direct_fallbacks")


def _formulation(model) -> str:
    """``"mixed"`` for the Taylor-Hood u-p body, else ``"displacement"`` (``[material] formulation``)."""
    from ..fem import MixedHyperelastic

    return "mixed" if isinstance(model, MixedHyperelastic) else "displacement"


def _finite_summary(setup, fs, frames, wall: float) -> dict[str, Any]:
    """``summary.json`` keys of a finite-deformation run (the per-step lists have one entry per accepted step)."""
    final = frames[-1]
    steps = fs.steps
    res = final.result
    out: dict[str, Any] = {
        "kinematics": "finite",
        "material_model": getattr(setup.problem.model.law, "name", None),
        "formulation": _formulation(setup.problem.model),
        "status": res.status.label, "status_code": int(res.status), "message": res.message,
        "converged_steps": sum(1 for t in setup.times if steps and t <= steps[-1].t + 1e-12 * max(1.0, abs(t))),
        "accepted_steps": len(steps),
        "outer_iterations": int(sum(s.outer_iterations for s in steps)),
        "newton_iterations": int(sum(s.newton_iterations for s in steps)),
        "linear_solves": int(sum(s.linear_solves for s in steps)),
        "wall_time_s": float(final.timings.get("total_s", wall)),
        "step_times": [float(s.t) for s in steps],
        # False: a sub-step a cut-back inserted (halved increment); step_times holds both kinds
        "step_requested": [bool(getattr(s, "requested", True)) for s in steps],
        "step_newton_iterations": [int(s.newton_iterations) for s in steps],
        "step_outer_iterations": [int(s.outer_iterations) for s in steps],
        "step_cutbacks": [int(s.cutbacks) for s in steps],
        "step_seconds": [float(s.seconds) for s in steps],
        "step_contact_force": [[float(x) for x in s.force] for s in steps],
        "cutbacks": int(sum(s.cutbacks for s in steps)),
        "final_contact_force": [float(x) for x in final.total_contact_force],
        "max_cutbacks": int(setup.max_cutbacks),
        "obstacle_path": list(setup.obstacle_path) if setup.obstacle_path is not None else None,
        # the linear-solver path of the Newton systems (direct factorization or AMG + CG) and its counters
        **{k: final.extra[k] for k in _FINITE_SOLVER_KEYS if k in final.extra},
    }
    if steps:
        out.update(equilibrium_keys(final.equilibrium()))
    # the solver times all its Newton linear solves together: one solve is their mean
    total = final.timings.get("linear_solve_s")
    total = total if total is not None and math.isfinite(total) else None
    count = int(fs.extra.get("linear_solves", final.result.linear_solves))  # the run's (friction: its extra)
    lin = total / count if total and count > 0 else None
    out["linear_solve_time_s"] = lin
    out["linear_solve_time_total_s"] = total
    out["linear_solve_count"] = count
    out["linear_solve_time_kind"] = "mean Newton linear solve" if lin else None
    out["time_ratio_contact_to_linear"] = out["wall_time_s"] / lin if lin else None
    if not fs.success:
        reached = float(steps[-1].t) if steps else 0.0
        out["message"] = (f"stopped at t={reached:g} of t={setup.times[-1]:g} ({len(steps)} accepted steps, "
                          f"{out['cutbacks']} cut-backs): {fs.message}")
    return out


def _stick_half_width(frame, axis: int, center) -> float | None:
    st = np.asarray(frame.extra.get("state", []))
    if st.size == 0 or not np.any(st == 1):
        return None
    r = np.abs(frame.points[:, axis] - (0.0 if center is None else center[axis]))
    last = float(np.max(r[st == 1]))
    beyond = r[(r > last) & (st != 1)]
    return 0.5 * (last + float(beyond.min())) if beyond.size else last


def setup_summary(setup, solution, raw, options: dict, wall: float) -> dict[str, Any]:
    """The ``summary.json`` dictionary of a problem-file run (:func:`~alcontact.app.pipeline.run_setup`).

    ``solution`` is what :func:`alcontact.contact.solve` returned (its frames are the steps),
    ``raw`` the stepping engine's record (``solution.record``; the list of per-step solutions for
    a frictionless small-deformation run), ``options`` the command-line overrides and ``wall``
    the wall time of the solve.
    """
    frames = solution.frame_solutions()
    final = frames[-1]
    prob = setup.problem
    summary = summarize(prob, final, problem_name=setup.name, options=options)
    summary["problem_label"] = setup.name
    summary["source"] = str(setup.source) if setup.source is not None else None
    summary["load_steps"] = len(setup.times)
    summary["converged_steps"] = sum(1 for f in frames if f.result.success)
    summary["wall_time_total_s"] = wall
    summary["friction"] = setup.friction
    if setup.finite:
        summary.update(_finite_summary(setup, raw, frames, wall))
        if setup.friction > 0:
            summary.update(_finite_friction_summary(setup, raw, frames))
    elif setup.friction > 0:
        summary.update(_small_friction_summary(setup, raw, final, wall))
    elif len(setup.times) > 1:
        summary.update(_stepped_summary(summary, frames, len(setup.times)))
    record = getattr(raw, "extra", None)  # the solution's own record (the frames of a stepped run lack it)
    if isinstance(record, dict) and record.get("linear_solver") is not None:
        summary.update(linear_solver=record["linear_solver"], linear_solver_strategy=record.get("strategy"))
    if setup.friction > 0 and "shear" in final.extra:
        # |Q| = |sum of q_i| <= sum of |q_i| <= mu N: the two differ where the tangents turn over the zone
        q = np.linalg.norm(np.asarray(final.extra["shear"], dtype=float), axis=1)
        summary["tangential_force_magnitude_sum"] = float(np.sum(np.asarray(final.weights, dtype=float) * q))
    if len(prob.pairs) > 1:  # the force of each pair at every step (the final ones: pair_contact_forces)
        summary["step_pair_contact_forces"] = [f.pair_contact_forces().tolist() for f in frames]
    summary["units"] = setup.plot_units().as_dict(int(prob.model.dim))
    return summary


def _small_friction_summary(setup, raw, final, wall: float) -> dict[str, Any]:
    """``summary.json`` keys of a small-deformation frictional run (``raw``: its ``FrictionSolution``)."""
    out: dict[str, Any] = dict(
        outer_iterations=int(raw.outer_iterations), newton_iterations=int(raw.newton_iterations),
        status=raw.status.label, status_code=int(raw.status), message=raw.message, cutbacks=int(raw.cutbacks),
        wall_time_s=float(raw.timings.get("total_s", wall)))
    if raw.steps:  # loads and supports of the history at the final step's time
        out.update(equilibrium_keys(raw.equilibrium()))
    tf = np.asarray(final.extra["tangential_force"], dtype=float)
    st = np.asarray(final.extra["state"])
    out.update(tangential_force=float(np.linalg.norm(tf)), tangential_force_vector=tf.tolist(),
               coulomb_limit=float(setup.friction * final.normal_force),
               stick_points=int(np.sum(st == 1)), slip_points=int(np.sum(st == 2)),
               open_points=int(np.sum(st == 0)), eps_t=float(raw.eps_t))
    meta = setup.problem.meta
    axis = int(meta.get("symmetry_axis", 0))
    c_num = _stick_half_width(final, axis, meta.get("center"))
    out["stick_half_width"] = c_num
    if setup.mindlin is not None and final.normal_force > 0:
        sym = setup.mindlin.hertz.symmetry
        c_ex = setup.mindlin.stick_half_width(sym * final.normal_force, sym * abs(float(tf[axis])))
        out["stick_half_width_exact"] = c_ex
        out["stick_half_width_error_pct"] = _error_pct(c_num, c_ex)
    return out


def _stepped_summary(summary: dict, frames, n: int) -> dict[str, Any]:
    """``summary.json`` totals of a frictionless small-deformation run over ``n`` step times."""
    final = frames[-1]
    out: dict[str, Any] = dict(
        outer_iterations=sum(f.result.outer_iterations for f in frames),
        newton_iterations=sum(f.result.newton_iterations for f in frames),
        linear_solves=sum(f.result.linear_solves for f in frames),
        wall_time_s=sum(float(f.timings.get("total_s", 0.0)) for f in frames))
    # the total time of all steps against one linear solve (summarize() took the last step's time)
    lin = summary.get("linear_solve_time_s")
    out["time_ratio_contact_to_linear"] = out["wall_time_s"] / lin if lin else None
    if len(frames) < n:
        out["message"] = f"step {len(frames)} of {n} failed: {final.result.message}"
    return out
