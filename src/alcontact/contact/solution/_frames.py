"""The one place the per-step states of a load-stepped solve become :class:`ContactSolution` frames.

Each stepping engine (:func:`~alcontact.contact.stepping._frictionless.solve_finite`,
:func:`~alcontact.contact.stepping._coulomb.solve_friction`,
:func:`~alcontact.contact.stepping._coulomb.solve_finite_friction`, and the independent static
solves of a path-independent frictionless history) records its accepted steps in its own
shape; the functions here turn them into one :class:`~alcontact.contact.ContactSolution` per
step (the step's state, its loads in ``problem`` so that ``equilibrium()`` is that step's
balance, its counters in ``result``, the frictional fields in ``extra``) and return the last
one carrying every step as a :class:`~alcontact.contact.ContactFrame`. Nothing built here is
changed afterwards.

Frictional fields in ``extra`` (read by :func:`~alcontact.contact.solution._solution.frame_of`, the
VTU writer and the summaries): ``slip`` (accumulated), ``slip_increment``, ``state``, ``shear``
(tangential traction on the body, global components, :math:`(m, d)`), ``tangential_force``,
``mu``, ``coulomb`` (small) or ``dissipation`` (finite), ``t``, ``requested``, ``cutbacks``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._verify import check_state
from ..problem._loading import problem_at
from ._solution import ContactResult, ContactSolution, ContactStatus, frame_of


def _complementarity(gap, pressure, h: float) -> float:
    """The ``complementarity`` measure of :func:`~alcontact.contact._verify.check_state` of a returned step
    (the one its verification checked)."""
    return check_state(gap, pressure, h, tol_penetration=1.0, tol_complementarity=1.0).value("complementarity")


def _combine(views, record=None) -> ContactSolution:
    """The last view carrying every view as a frame (and the engine's record)."""
    frames = tuple(frame_of(v) for v in views)
    return dataclasses.replace(views[-1], frames=frames, record=record)


def _at(problem, history, t: float):
    return problem_at(problem, history, t) if history is not None else problem


def stepped_solution(views) -> ContactSolution:
    """Independent static solves at the step times of a frictionless small-deformation history."""
    return _combine(list(views))


#: keys of a two-body run's ``extra`` that belong to its final state only
_FINAL_TWO_BODY = ("master_contact_force", "contact_force_balance", "contact_force_points",
                   "pair_slave_contact_forces")


def _step_extra(extra: dict, step) -> dict:
    """The run's ``extra`` for the frame of an earlier ``step``: a two-body pair's slave force is the step's
    own (:attr:`FiniteStep.force`), the final state's master force and balance are left out."""
    if extra.get("slave_contact_force") is None:
        return extra
    out = {k: v for k, v in extra.items() if k not in _FINAL_TWO_BODY}
    out["slave_contact_force"] = np.asarray(step.force, dtype=float).tolist()
    return out


def finite_solution(fs, problem, history, path) -> ContactSolution:
    """Frames of a frictionless finite-deformation run (:class:`~alcontact.contact.FiniteSolution`).

    The last frame is the run's verified solution; the others carry the state each step
    accepted (gaps and normals at the current configuration of the moved obstacle).
    """
    from ..masters.obstacles import RigidMotion, move, translate

    base = fs.solution
    model = problem.model
    _, dofs = problem.slave_nodes()
    views = []
    steps = list(fs.steps)
    for step in steps[:-1]:
        u, pressure = step.u, step.pressure
        off = None if path is None else path(step.t)
        ob = problem.obstacle if off is None else (move(problem.obstacle, off) if isinstance(off, RigidMotion)
                                                   else translate(problem.obstacle, off))
        if getattr(step, "normals", None) is not None:  # a deformable master: the step's own gaps and normals
            gap, normals = step.gap, step.normals
        else:
            gap, normals = ob.evaluate(base.points + u[dofs])
        nodal = base.weights * pressure
        res = dataclasses.replace(base.result, status=step.status, message=step.message,
                                  outer_iterations=int(step.outer_iterations),
                                  newton_iterations=int(step.newton_iterations),
                                  linear_solves=int(step.linear_solves), history=(),
                                  penetration=float(max(np.max(gap, initial=0.0), 0.0)) / float(base.extra["h"]))
        views.append(ContactSolution(
            problem=_at(problem, history, step.t), u=u, points=base.points, pressure=pressure,
            gap=np.asarray(gap, dtype=float), weights=base.weights, active=pressure > 0,
            normals=np.asarray(normals, dtype=float), total_contact_force=np.asarray(step.force, dtype=float),
            result=res, nodal_forces=nodal, timings={"total_s": float(step.seconds)},
            extra={**_step_extra(base.extra, step), "t": float(step.t), "cutbacks": int(step.cutbacks),
                   "seconds": float(step.seconds),
                   "requested": bool(getattr(step, "requested", True)),
                   "step_newton_iterations": int(step.newton_iterations),
                   "step_outer_iterations": int(step.outer_iterations),
                   "step_linear_solves": int(step.linear_solves)}))
    extra = dict(base.extra, load_steps=fs.steps)
    if steps:
        last = steps[-1]
        views.append(dataclasses.replace(base, problem=_at(problem, history, last.t), extra={
            **extra, "t": float(last.t), "cutbacks": int(last.cutbacks), "seconds": float(last.seconds),
            "requested": bool(getattr(last, "requested", True)),
            "step_newton_iterations": int(last.newton_iterations), "step_outer_iterations": int(last.outer_iterations),
            "step_linear_solves": int(last.linear_solves)}))
    else:  # no step was accepted: the undeformed start with the failure status
        views.append(dataclasses.replace(base, extra={**extra, "t": 0.0, "cutbacks": 0}))
    return _combine(views, fs)


def friction_solution(fsol) -> ContactSolution:
    """Frames of a small-deformation frictional run (:class:`~alcontact.contact.FrictionSolution`)."""
    problem = fsol.problem
    m, d = fsol.points.shape
    steps = list(fsol.steps)
    views = []
    timings = {**fsol.timings, "linear_solve_s": fsol.timings.get("factor_s", float("nan"))}
    for k, st in enumerate(steps):
        last = k == len(steps) - 1
        status = fsol.status if last else ContactStatus.CONVERGED
        result = ContactResult(
            status=status, message=fsol.message if last else "converged", algorithm=fsol.algorithm,
            penalty=fsol.penalty, outer_iterations=int(st.outer_iterations), newton_iterations=int(st.newton_iterations),
            linear_solves=int(fsol.linear_solves), factorizations=int(fsol.factorizations),
            penetration=float(st.penetration), complementarity=_complementarity(st.gap, st.pressure, fsol.h),
            residual=float("nan"), eps_n=float(fsol.eps_n), history=())
        views.append(ContactSolution(  # the loads and supports of the history at the step's time
            problem=problem_at(problem, fsol.history, st.t), u=st.u, points=fsol.points, pressure=st.pressure,
            gap=st.gap, weights=fsol.weights,
            active=st.state != 0, normals=fsol.normals, total_contact_force=st.contact_force, result=result,
            timings=timings,
            extra={"t": float(st.t), "requested": bool(st.requested), "slip": st.slip_total,
                   "slip_increment": st.slip, "state": st.state, "shear": st.shear,
                   "tangential_force": np.asarray(st.tangential_force, dtype=float),
                   "mu": float(fsol.friction) * float(fsol.history.friction_factor(st.t)),
                   "coulomb": float(st.coulomb), "cutbacks": int(st.cutbacks), "h": fsol.h,
                   "step_linear_solves": int(st.linear_solves),
                   "candidates": fsol.extra.get("candidates"), "dofs": fsol.extra.get("dofs"),
                   **{k: fsol.extra[k] for k in ("linear_solver", "strategy", "schur_prediction", "prediction_cg_iterations")
                      if k in fsol.extra},
                   **st.two_body}))
    if not views:  # nothing converged: report the contact-free start
        z = np.zeros(m)
        result = ContactResult(status=fsol.status, message=fsol.message, algorithm=fsol.algorithm,
                               penalty=fsol.penalty, outer_iterations=0, newton_iterations=0,
                               linear_solves=int(fsol.linear_solves), factorizations=1, penetration=0.0,
                               complementarity=float("nan"), residual=float("nan"), eps_n=float(fsol.eps_n))
        views.append(ContactSolution(
            problem=problem, u=np.zeros(problem.model.ndofs), points=fsol.points, pressure=z, gap=z,
            weights=fsol.weights, active=z.astype(bool), normals=fsol.normals, total_contact_force=np.zeros(d),
            result=result, timings=timings,
            extra={"t": 0.0, "slip": np.zeros((m, d)), "slip_increment": np.zeros((m, d)),
                   "state": np.zeros(m, int), "shear": np.zeros((m, d)), "tangential_force": np.zeros(d),
                   "mu": float(fsol.friction), "h": fsol.h, "dofs": problem.model.ndofs}))
    return _combine(views, fsol)


def finite_friction_solution(fs, problem, history) -> ContactSolution:
    """Frames of a finite-deformation frictional run (:class:`~alcontact.contact.FiniteFrictionSolution`):
    deformed configuration, the step's loads in ``problem``, ``extra["shear"]`` the global tangential
    traction on the body (:math:`-t_T` of the step record) and ``extra["dissipation"]``."""
    ex = fs.extra
    points, weights, h = ex["points"], ex["weights"], float(ex["h"])
    m, d = points.shape
    views = []
    slip_total = np.zeros((m, d))
    for k, st in enumerate(fs.steps):
        last = k == len(fs.steps) - 1
        slip_total = slip_total + st.slip
        result = ContactResult(
            status=fs.status if last else st.status, message=fs.message if last else st.message,
            algorithm=str(ex["algorithm"]), penalty=str(ex["penalty"]), outer_iterations=int(st.outer_iterations),
            newton_iterations=int(st.newton_iterations), linear_solves=int(st.linear_solves),
            factorizations=int(st.linear_solves), penetration=float(max(np.max(st.gap, initial=0.0), 0.0)) / h,
            complementarity=_complementarity(st.gap, st.pressure, h), residual=float("nan"), eps_n=float(ex["eps_n"]))
        views.append(ContactSolution(
            problem=_at(problem, history, st.t), u=st.u, points=points, pressure=st.pressure, gap=st.gap,
            weights=weights, active=st.states != 0, normals=st.normals,
            total_contact_force=np.asarray(st.force, dtype=float), result=result, nodal_forces=weights * st.pressure,
            timings={"total_s": float(ex["total_s"]), "linear_solve_s": float(ex.get("linear_solve_s", float("nan")))}
            if last else {"total_s": float(st.seconds)},
            extra={"t": float(st.t), "cutbacks": int(st.cutbacks), "seconds": float(st.seconds),
                   "requested": bool(getattr(st, "requested", True)),
                   "step_newton_iterations": int(st.newton_iterations),
                   "step_outer_iterations": int(st.outer_iterations), "slip": slip_total.copy(),
                   "slip_increment": st.slip, "state": st.states, "shear": -np.asarray(st.traction_t, dtype=float),
                   "tangential_force": np.asarray(st.tangential_force, dtype=float), "mu": float(ex["mu"]),
                   "dissipation": float(st.dissipation), "h": h, "dofs": int(ex["dofs"]),
                   "penalty_scale": ex.get("penalty_scale")}))
    if not views:  # nothing converged: the undeformed start with the failure status
        z = np.zeros(m)
        result = ContactResult(status=fs.status, message=fs.message, algorithm=str(ex["algorithm"]),
                               penalty=str(ex["penalty"]), outer_iterations=0, newton_iterations=0,
                               linear_solves=int(ex["linear_solves"]), factorizations=int(ex["linear_solves"]),
                               penetration=0.0, complementarity=float("nan"), residual=float("nan"),
                               eps_n=float(ex["eps_n"]))
        views.append(ContactSolution(
            problem=problem, u=np.asarray(fs.u, dtype=float), points=points, pressure=z, gap=np.asarray(fs.gap),
            weights=weights, active=z.astype(bool), normals=fs.normals, total_contact_force=np.zeros(d),
            result=result, timings={"total_s": float(ex["total_s"])},
            extra={"t": 0.0, "cutbacks": 0, "seconds": 0.0, "slip": np.zeros((m, d)),
                   "slip_increment": np.zeros((m, d)), "state": np.zeros(m, int), "shear": np.zeros((m, d)),
                   "tangential_force": np.zeros(d), "mu": float(ex["mu"]), "dissipation": 0.0, "h": h,
                   "dofs": int(ex["dofs"]), "penalty_scale": ex.get("penalty_scale")}))
    return _combine(views, fs)
