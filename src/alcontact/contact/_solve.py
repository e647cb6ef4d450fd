"""Entry point :func:`solve` for frictionless contact."""

from __future__ import annotations

import logging
import time

import numpy as np

from ..linalg import select_solver
from ._algorithms import DEFAULT_PENALTY, ContactOptions, _Run, available_algorithms, check_solve_args, \
    find_algorithm, options_with
from ._discrete import DiscreteContact
from ._solution import ContactResult, ContactSolution, ContactStatus
from ._verify import check_state, equilibrium_tolerance, reach, state_equilibrium, verified_status

__all__ = ["solve", "DEFAULT_ALGORITHM", "DEFAULT_PENALTY", "penalty_stiffness"]

logger = logging.getLogger(__name__)

DEFAULT_ALGORITHM = "simo-laursen"



def penalty_stiffness(model, h: float, scale: float = 1.0) -> float:
    """Automatic penalty stiffness ``scale * E' / h`` (pressure per length).

    ``E' = E/(1-nu^2)`` in plane strain and 3D, ``E`` in plane stress: the
    stiffness of a layer of thickness ``h`` under uniaxial strain, so the
    penalty spring is as stiff as the first element row under the surface.
    """
    mat = model.material
    e_prime = mat.E if (model.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus
    return scale * e_prime / h


def solve(problem, algorithm: str = DEFAULT_ALGORITHM, penalty: str | None = None,
          options: ContactOptions | None = None, **option_overrides) -> ContactSolution:
    """Solve a frictionless contact problem.

    Parameters
    ----------
    problem : ContactProblem
    algorithm : str
        One of :func:`available_algorithms`: ``"penalty"``, ``"simo-laursen"``
        (Algorithm 6.1), ``"family-p"`` (Algorithm 6.3), ``"ssn"``.
    penalty : str, optional
        Penalty of ``"family-p"`` (one of :func:`contact_penalties`; default
        ``"exp-met1"``).
    options : ContactOptions or dict, optional
        Options; a dict holds :class:`ContactOptions` fields (as ``optim.minimize`` takes them).
    **option_overrides
        Fields of :class:`ContactOptions` (e.g. ``penalty_scale=10``).

    Returns
    -------
    ContactSolution
        ``solution.result.status`` is negative when the solve failed; a warning
        is logged saying what to try.

    Raises
    ------
    InputError
        ``problem`` not a :class:`ContactProblem`, unknown algorithm, penalty or
        option (with the closest match), or an option value of the wrong type or
        out of range (naming the key, the value, the allowed range and the default).

    Notes
    -----
    A problem with ``kinematics="finite"`` is solved by
    :func:`~alcontact.contact.solve_finite` (10 uniform load steps unless
    ``steps=...`` is given, also ``obstacle_path``, ``history``, ``max_cutbacks``);
    the solution of its last step is returned, with the per-step records in
    ``solution.extra["load_steps"]``.
    """
    check_solve_args(problem, algorithm, penalty, available_algorithms(), "")
    kinematics = getattr(problem, "kinematics", "small")
    if kinematics in _KINEMATICS_SOLVERS:
        return _KINEMATICS_SOLVERS[kinematics](problem, algorithm, penalty, options, **option_overrides)
    t_start = time.perf_counter()
    entry = find_algorithm(algorithm)
    run = entry.run
    pen_name = entry.penalty_for(penalty)
    opts = options_with(options, ContactOptions, option_overrides, "contact", entry)

    from ._iterative import IterativeContact

    # both strategies offer the interface the outer loops use (start, gaps, subproblem, solve_active, ...):
    # the condensed (Delassus) one needs an exact factorization, an approximate solver preconditions CG
    solver = select_solver(opts.linear_solver, dim=problem.model.dim, ndofs=problem.model.ndofs)
    if solver.exact:
        dc = DiscreteContact(problem, linear_solver=solver.name)
    else:
        dc = IterativeContact(problem, solver=solver)
    eps0 = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, dc.h, opts.penalty_scale)
    t_solve = time.perf_counter()

    if dc.cand.size == 0:
        i = int(np.argmax(np.where(dc.movable, dc.g_free, -np.inf)))
        msg = (
            f"the body never reaches the obstacle: smallest clearance {-dc.g_free[i]:.4g} at point "
            f"{np.round(dc.points[i], 6).tolist()}; move the obstacle closer, increase the load, or check "
            "the contact boundary name"
        )
        out = _Run(dc.start(), np.zeros(0), np.zeros(0), ContactStatus.NO_CONTACT, msg, 0, 0, eps0, 0.0, [])
        u = dc.u_free
    else:
        for _attempt in range(8):
            out = run(dc, opts, eps0, pen_name)
            u = dc.final_displacement(out.r)
            if out.status < 0:  # a failed run: its multipliers belong to the candidates it had
                break
            added = dc.extend(dc.all_gaps(u), opts.tol_penetration * dc.h)
            if added.size == 0:
                break
    g_all = dc.all_gaps(u)
    m = dc.points.shape[0]
    pressure = np.zeros(m)
    if out.lam.size:
        pressure[dc.cand[: out.lam.size]] = dc.applied_pressure(out)  # candidates added later carry none
    if out.status > 0 and not np.all(np.isfinite(u)):
        out.status, out.message = ContactStatus.NONFINITE, "non-finite displacement"
    nodal = dc.weights * np.maximum(pressure, 0.0)  # the normal nodal forces r = w lambda the solver applied
    # the one place a small-deformation frictionless result is built: every measure of the returned state
    # (gaps of u, the applied pressures, equilibrium of u with those forces) against its tolerance. The
    # condensed direct path reports the forces u carries (r / w); the AMG path its multipliers, which differ
    # from the tractions u balances by the last multiplier change (the ssn reference's inner Uzawa iteration
    # stops at a relative update of 1e-8): its equilibrium tolerance has tol_multiplier in it
    fixed, _ = problem.dirichlet()
    eq = state_equilibrium(problem.model, u, fixed, problem.load_vector(),
                           problem.model.node_dofs(problem.contact_boundary)[1], nodal[:, None] * dc.normals, dc.h,
                           pressure=pressure, weights=dc.weights)
    check = check_state(g_all, pressure, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity, equilibrium=eq.largest,
                        tol_equilibrium=equilibrium_tolerance(opts, multipliers=not isinstance(dc, DiscreteContact)),
                        reach=reach(dc.points, u))
    out.status, out.message = verified_status(out.status, out.message, check, what=f"contact solve {algorithm}")
    pressure = np.maximum(pressure, 0.0)
    force = np.sum(nodal[:, None] * dc.normals, axis=0)
    if np.any(pressure > 0):  # pressure field of the nodal forces (differs from lambda for 3D P2)
        pressure = problem.model.boundary_pressure(problem.contact_boundary, nodal)
    closed = g_all > -max(1e-6, 10 * opts.tol_penetration) * dc.h
    active = closed & (pressure > 1e-12 * max(float(pressure.max(initial=0.0)), 1e-300))
    # the printed invariants are the checked ones (of the applied pressures, not of the recovered field)
    pen_final = check.value("penetration")
    compl = check.value("complementarity")
    result = ContactResult(
        status=out.status,
        message=out.message,
        algorithm=algorithm,
        penalty=pen_name,
        outer_iterations=int(out.outer),
        newton_iterations=int(out.newton),
        linear_solves=int(dc.linear_solves),
        factorizations=dc.factorizations,
        penetration=pen_final,
        complementarity=compl,
        residual=float(out.residual),
        eps_n=float(out.eps),
        history=tuple(out.history),
    )
    if out.status < 0:
        logger.warning("contact solve %s/%s failed (%s): %s", algorithm, pen_name, out.status.label, out.message)
    t_end = time.perf_counter()
    timings = dict(dc.timings(), solve_s=t_end - t_solve, total_s=t_end - t_start)
    return ContactSolution(
        problem=problem,
        u=u,
        points=dc.points,
        pressure=pressure,
        gap=g_all,
        weights=dc.weights,
        active=active,
        normals=dc.normals,
        total_contact_force=force,
        result=result,
        timings=timings,
        nodal_forces=nodal,
        extra={"h": dc.h, "candidates": int(dc.cand.size), "dofs": int(problem.model.ndofs), **dc.extra()},
    )


def _solve_finite(problem, algorithm, penalty, options, **kwargs) -> ContactSolution:
    from ._stepping import solve_finite

    fs = solve_finite(problem, algorithm, penalty, options, **kwargs)
    fs.solution.extra["load_steps"] = fs.steps
    return fs.solution


#: solvers of the kinematics other than the default ``"small"`` (the body of :func:`solve`)
_KINEMATICS_SOLVERS = {"finite": _solve_finite}
