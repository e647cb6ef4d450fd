r"""Verification of a returned contact state: the last word on ``converged``.

Every solver path of :func:`~alcontact.contact.solve` (frictionless or Coulomb, direct or
AMG) builds its result through
:func:`verified_status`, which recomputes the physical measures from the state
it is about to return (the full displacement's gaps, not the solver's last
iterate) and turns a positive status into :attr:`ContactStatus.NOT_VERIFIED`
(with a logged warning naming the measure, its value, the tolerance and what to
try) when one fails. The load-stepped solvers check every step before accepting it:
at small deformation with friction and at finite deformation without, a step whose
state fails is cut back like a failed Newton solve (``NOT_VERIFIED`` when the smallest
increment fails too); at finite deformation with friction a failing step ends the run
``NOT_VERIFIED``. The measures are dimensionless, as in the stopping tests
of the algorithms (:mod:`alcontact.contact.algorithms._frictionless`, Algorithm 6.2):

``penetration``
    :math:`\max_i g_i^+ / h` (gap (6.15), :math:`g \le 0` feasible).
``complementarity``
    :math:`\max_i |\lambda_i g_i| / (p_{ref} h)` and :math:`\max_i \lambda_i^- / p_{ref}`
    (a tensile pressure is a complementarity failure too), with
    :math:`p_{ref} = \max_i \lambda_i`.
``coulomb``
    Friction bound :math:`\max_i (|t_{T,i}| - \mu t_{N,i})^+ / p_{ref}`.
``slip``
    Coulomb complementarity and slip direction in one measure, the dissipation
    defect :math:`\max_i (\mu t_{N,i} |\Delta u_{T,i}| - t_{T,i}\cdot\Delta u_{T,i})
    / (p_{ref} \max(h, \max_j |\Delta u_{T,j}|))`. Given the bound, it vanishes
    exactly when every point either sticks (:math:`\Delta u_T = 0`) or slips with
    a saturated traction along the slip (:math:`t_T = \mu t_N \Delta u_T/|\Delta u_T|`,
    dissertation sign: the force on the body, :math:`-t_T`, opposes the slip),
    the time-discrete Coulomb law of (6.47)-(6.50).
``equilibrium``
    The largest residual :math:`|f_{int}(u) - f_{ext} - f_c|` on the free DOFs of the
    returned displacement with the returned contact forces (normal and tangential), or the
    global balance :math:`|F_c + F_{ext} + R|` if larger (the two residuals ``summary.json`` prints),
    relative to the force scale of :func:`~alcontact.contact.solution._estimators.equilibrium`
    (the largest of the applied load, the reactions, the contact and internal forces and
    a stiffness times the displacement, so that it does not vanish with the contact
    force): :func:`state_equilibrium`. Its tolerance is the Newton tolerance, not below the
    round-off of the measure (:func:`equilibrium_tolerance`).
``resolution``
    :math:`\epsilon_{mach} \max(|x| + |u|) / h`: the round-off of the gaps computed at
    positions of that size, over ``h``. Above ``tol_penetration`` the gaps, and with them
    penetration, complementarity and the contact forces, are round-off (a support moved
    by :math:`10^{14}`).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .solution._solution import ContactStatus


logger = logging.getLogger(__name__)

#: Lowest tolerance of the ``equilibrium`` measure: the round-off of :math:`f_{int}(u) - f_{ext} - f_c`
#: itself (terms of size :math:`|K||u|` cancel). Measured: 2.2e-12 on the 2D P2 Hertz problem of the
#: verification tests with Algorithm 6.1 on the condensed direct path, whose forces are exact by
#: construction and whose own Newton stopped at 1.1e-12; the factorization-free paths hold their Newton
#: iterations to the same 1e-11 (``_iterative._NEWTON_TOL_FLOOR``).
ROUNDOFF_FLOOR = 1e-11

_ADVICE = {
    "penetration": "tighten newton_tol, use more outer iterations (maxiter) or a larger penalty_scale, "
                   "or try algorithm='ssn'",
    "complementarity": "tighten tol_multiplier / newton_tol or try algorithm='ssn'",
    "coulomb": "tighten tol_multiplier / newton_tol, use more load steps or try algorithm='ssn'",
    "slip": "tighten tol_slip / tol_multiplier, use more load steps or try algorithm='ssn'",
    "finite": "check loads and supports, try a smaller penalty_scale or algorithm='ssn'",
    "equilibrium": "the returned state is not in equilibrium: tighten newton_tol, raise maxiter_newton, use more "
                   "load steps or try algorithm='ssn'",
    "resolution": "the displacements or coordinates are too large for double precision to resolve the gaps at "
                  "this element size: check the support values and the units (a prescribed displacement should be "
                  "of the order of the body)",
}


@dataclass(frozen=True)
class Check:
    """Measures of one state against their tolerances.

    Attributes
    ----------
    measures : dict
        ``name -> (value, tolerance)``.
    """

    measures: dict

    @property
    def failed(self) -> dict:
        """The measures above their tolerance (a non-finite value fails)."""
        return {k: v for k, v in self.measures.items() if not (np.isfinite(v[0]) and v[0] <= v[1])}

    @property
    def ok(self) -> bool:
        return not self.failed

    def value(self, name: str) -> float:
        """The value of measure ``name`` (``inf`` for a state with non-finite gaps or pressures)."""
        return float(self.measures.get(name, (np.inf, 0.0))[0]) if "finite" not in self.measures else np.inf

    def describe(self) -> str:
        parts = [f"{k} {v:.3e} > tolerance {tol:.1e}" for k, (v, tol) in self.failed.items()]
        advice = "; ".join(dict.fromkeys(_ADVICE[k.split()[0]] for k in self.failed))
        return ", ".join(parts) + (f" ({advice})" if advice else "")


def check_state(gap, pressure, h: float, *, tol_penetration: float, tol_complementarity: float,
                traction_t=None, slip=None, mu=0.0, tol_friction: float | None = None,
                equilibrium: float | None = None, tol_equilibrium: float | None = None,
                reach: float | None = None) -> Check:
    """Measure a contact state (see the module docstring).

    Parameters
    ----------
    gap, pressure : ndarray (m,)
        Gaps (6.15) and normal tractions :math:`\\lambda_N` of all contact points.
    h : float
        Contact-zone element size.
    tol_penetration, tol_complementarity : float
        Tolerances of ``penetration`` and ``complementarity``.
    traction_t : ndarray (m, d-1), optional
        Tangential tractions :math:`t_T` (dissertation sign); with it the
        ``coulomb`` and ``slip`` measures are checked against ``tol_friction``.
    slip : ndarray (m, d-1), optional
        Tangential displacement increment :math:`\\Delta u_T` of the step in the same
        local frame (held directions zero); default no slip.
    mu : float or ndarray (m,)
        Coulomb coefficient at that state (one per point when the contact pairs have their own).
    equilibrium, tol_equilibrium : float, optional
        Relative equilibrium residual of the state (:func:`state_equilibrium`) and its
        tolerance (:func:`equilibrium_tolerance`); checked when given.
    reach : float, optional
        Largest coordinate plus largest displacement of the state (``resolution``).

    Raises
    ------
    alcontact.errors.InputError
        An argument of the wrong type or shape (gaps and pressures of different lengths,
        ``h <= 0``, a negative tolerance or ``mu``), naming it. Non-finite gaps, pressures,
        tractions, slips or measures are not errors: the check fails (``finite``).
    """
    g, p, tT, du, h, tol_penetration, tol_complementarity, mu, tol_friction, equilibrium, tol_equilibrium, \
        reach = _checked_args(gap, pressure, h, tol_penetration, tol_complementarity, traction_t, slip, mu,
                              tol_friction, equilibrium, tol_equilibrium, reach)
    pref = max(float(np.max(p, initial=0.0)), 1e-300)
    both = np.concatenate([g, p])
    if not np.all(np.isfinite(both)):
        return Check({"finite": (np.inf, 0.0)})
    with np.errstate(over="ignore"):  # an overflowing product is an infinite (failed) measure
        measures = {
            "penetration": (float(np.max(g, initial=0.0)) / h, tol_penetration),
            "complementarity": (max(float(np.max(np.abs(p * g), initial=0.0)) / (pref * h),
                                    float(np.max(-p, initial=0.0)) / pref), tol_complementarity),
        }
    if equilibrium is not None:
        measures["equilibrium"] = (float(equilibrium), float(tol_equilibrium))
    if reach is not None:
        measures["resolution"] = (float(np.finfo(float).eps * reach / h), tol_penetration)
    if tT is not None:
        du = np.zeros_like(tT) if du is None else du.reshape(tT.shape)
        if not (np.all(np.isfinite(tT)) and np.all(np.isfinite(du))):
            return Check({"finite": (np.inf, 0.0)})
        tol = tol_complementarity if tol_friction is None else tol_friction
        bound = mu * np.maximum(p, 0.0)
        nT, ndu = np.linalg.norm(tT, axis=1), np.linalg.norm(du, axis=1)
        measures["coulomb"] = (float(np.max(nT - bound, initial=0.0)) / pref, tol)
        defect = bound * ndu - np.einsum("ij,ij->i", tT, du)
        scale = pref * max(h, float(np.max(ndu, initial=0.0)))
        measures["slip"] = (float(np.max(defect, initial=0.0)) / scale, tol)
    return Check(measures)


def _checked_args(gap, pressure, h, tol_penetration, tol_complementarity, traction_t, slip, mu, tol_friction,
                  equilibrium, tol_equilibrium, reach) -> tuple:
    """The arguments of :func:`check_state` as arrays and floats, or an InputError naming the argument.

    Non-finite gaps, pressures, tractions, slips and measures are data (a failed check), not errors;
    the element size, the coefficient and the tolerances must be numbers in their range.
    """
    from alcontact._options import is_real, show
    from alcontact.errors import InputError

    def fail(name, value, want):
        return InputError(f"check_state: {name} = {show(value)}: expected {want}, got {type(value).__name__}.")

    def array(name, value, ndims, want):
        try:
            a = np.asarray(value)
        except (TypeError, ValueError, OverflowError):  # ragged nesting, huge integers
            raise fail(name, value, want) from None
        if a.dtype.kind not in "iuf" or a.ndim not in ndims:
            raise fail(name, value, want)
        return a.astype(float)

    def number(name, value, *, low=None, optional=False, finite=True):
        if value is None and optional:
            return None
        want = "a " + ("finite " if finite else "") + "real number" + ("" if low is None else f" >= {low}")
        if not is_real(value):
            raise fail(name, value, want)
        try:
            x = float(value)
        except OverflowError:  # an integer beyond float: infinite
            x = math.inf if value > 0 else -math.inf
        if (finite and not math.isfinite(x)) or (low is not None and not x >= low):
            raise fail(name, value, want)
        return x

    g = array("gap", gap, (1,), "a 1-D array of gaps")
    p = array("pressure", pressure, (1,), "a 1-D array of normal tractions")
    if p.shape != g.shape:
        raise InputError(f"check_state: pressure has {p.size} entries but gap has {g.size}; pass one normal "
                         "traction per contact point.")
    h = number("h", h)
    if not h > 0:
        raise fail("h", h, "the element size, a number > 0")
    tol_penetration = number("tol_penetration", tol_penetration, low=0.0)
    tol_complementarity = number("tol_complementarity", tol_complementarity, low=0.0)
    if is_real(mu) or mu is None:
        mu = number("mu", mu, low=0.0)
    else:  # one coefficient per point (contact pairs with their own)
        mu = array("mu", mu, (1,), f"a number or {g.size} coefficients >= 0")
        if mu.shape != g.shape or not np.all(np.isfinite(mu) & (mu >= 0)):
            raise fail("mu", mu, f"a number or {g.size} finite coefficients >= 0")
    tol_friction = number("tol_friction", tol_friction, low=0.0, optional=True)
    equilibrium = number("equilibrium", equilibrium, optional=True, finite=False)
    tol_equilibrium = number("tol_equilibrium", tol_equilibrium, low=0.0, optional=equilibrium is None)
    reach = number("reach", reach, optional=True, finite=False)
    tT = du = None
    if traction_t is not None:
        tT = array("traction_t", traction_t, (1, 2), f"tangential tractions of shape ({g.size}, d-1)")
        tT = tT[:, None] if tT.ndim == 1 else tT
        if tT.shape[0] != g.size:
            raise fail("traction_t", traction_t, f"tangential tractions of shape ({g.size}, d-1)")
    if slip is not None:
        du = array("slip", slip, (1, 2), "slips of the shape of traction_t")
        if tT is not None and du.size != tT.size:
            raise fail("slip", slip, f"slips of the shape of traction_t {tT.shape}")
    return g, p, tT, du, h, tol_penetration, tol_complementarity, mu, tol_friction, equilibrium, tol_equilibrium, \
        reach


def verified_status(status: ContactStatus, message: str, check: Check, *, what: str = "contact solve"):
    """``(status, message)`` after verification: a positive status whose state fails becomes NOT_VERIFIED.

    A negative status is returned unchanged (the solver already said why). On a
    flip, a warning is logged with the failing measures and what to try.
    """
    if status < 0 or check.ok:
        return status, message
    text = f"{what} reported {message!r} but the returned state fails verification: {check.describe()}"
    logger.warning("%s", text)
    return ContactStatus.NOT_VERIFIED, text


def equilibrium_tolerance(opts, *, multipliers: bool = False, floor: float = 0.0) -> float:
    r"""Tolerance of the ``equilibrium`` measure: ``newton_tol``.

    With ``multipliers`` (the frictional solvers report the updated multipliers
    :math:`\lambda_{k+1} = t(\lambda_k)` as tractions, while the state balances
    :math:`t(\lambda_k)` to ``newton_tol``) the two differ by the last multiplier change, at
    most ``tol_multiplier`` of the largest pressure at a converged step: ``max(newton_tol,
    tol_multiplier)``. ``floor``: the lowest Newton tolerance of the linear-solver path (the
    factorization-free paths: ``1e-11``, what inexact CG solves and the round-off of :math:`K x`
    reach, :data:`alcontact.contact.systems._krylov._NEWTON_TOL_FLOOR`, to which their Newton
    iterations are held). Never below :data:`ROUNDOFF_FLOOR`. Options with no ``newton_tol``
    (not resolved against an algorithm) take the frictionless default ``1e-12``.
    """
    tol = max(1e-12 if opts.newton_tol is None else float(opts.newton_tol), float(floor), ROUNDOFF_FLOOR)
    return max(tol, float(opts.tol_multiplier)) if multipliers else tol


def state_equilibrium(model, u, fixed, load, contact_dofs, point_forces, h: float, *, pressure=None,
                      weights=None):
    r"""Equilibrium of a returned state (:func:`~alcontact.contact.solution._estimators.equilibrium`).

    Parameters
    ----------
    model : Body
        The body (``internal_force``, ``ndofs``, ``dim``, ``material``).
    u : ndarray (ndofs,)
        Returned displacement.
    fixed : array_like of int
        Dirichlet DOFs.
    load : ndarray (ndofs,)
        External loads at the state's load level.
    contact_dofs : ndarray (m, d)
        DOFs of the contact points.
    point_forces : ndarray (m, d)
        Contact force on the body at every point (normal and tangential).
    h : float
        Contact-zone element size (stiffness scale).
    pressure, weights : ndarray (m,), optional
        Contact pressures (multipliers) and tributary weights of the points: the largest
        pressure times the largest weight joins the force scale. With it, a state whose
        reported tractions differ from the ones it balances by at most ``tol_multiplier``
        times the largest pressure (the frictional stopping test) has a residual of at most
        ``tol_multiplier`` also on a graded mesh, where the point of largest pressure has a
        smaller weight than others.

    Returns
    -------
    Equilibrium
        Its ``largest`` residual is the ``equilibrium`` measure.
    """
    from .solution._estimators import equilibrium, nodal_force_vector

    fc = nodal_force_vector(model.ndofs, contact_dofs, point_forces)
    extra = 0.0
    if pressure is not None and weights is not None and np.size(pressure):
        with np.errstate(over="ignore", invalid="ignore"):
            extra = float(np.max(np.abs(pressure), initial=0.0)) * float(np.max(np.abs(weights), initial=0.0))
    return equilibrium(model, u, fixed, load, fc, length=h, force_scale=extra if np.isfinite(extra) else 0.0)


def reach(points, u) -> float:
    """Largest coordinate of the contact points plus the largest displacement (``resolution``)."""
    with np.errstate(over="ignore", invalid="ignore"):
        return float(np.max(np.abs(points), initial=0.0)) + float(np.max(np.abs(u), initial=0.0))
