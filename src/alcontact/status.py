"""One table of termination codes for contact solves and :func:`alcontact.optim.minimize`.

Positive codes mean converged, negative ones failed (as PETSc's ``KSPConvergedReason``
and ``SNESConvergedReason``).  :class:`alcontact.contact.ContactStatus` and
:class:`alcontact.optim.Status` are this enum, so the same failure has the same
code everywhere:

=========================  ====  ===============================================
member (aliases)           code  meaning
=========================  ====  ===============================================
CONVERGED (CONVERGED_KKT)     1  all stopping tests met (contact: penetration,
                                 complementarity, multiplier change; optim: the
                                 KKT conditions (C1)-(C4))
UNCONSTRAINED_CONVERGED       2  no constraints; gradient norm below ``gtol``
NO_CONTACT                   -1  no candidate point can touch the obstacle
MAXITER                      -2  outer iteration limit reached
NEWTON_FAILED (INNER_FAILED) -3  the inner (Newton) solver of a subproblem failed
NONFINITE                    -4  NaN or infinity in a callback, traction or state
PENALTY_LIMIT                -5  the penalty reached its bound, still infeasible
UNBOUNDED                    -6  a subproblem appears unbounded below (contact: a
                                 body held by friction only slides away)
LINE_SEARCH_FAILED           -7  a line search found no decrease (inner solvers)
NOT_VERIFIED                 -8  the solver stopped, but the returned state fails
                                 the tolerances (contact: ``contact/_verify.py``)
=========================  ====  ===============================================

The contact codes are those the results folders have always recorded
(``summary.json``: ``status_code``).  The optimization codes changed when the two
tables were merged (old ``alcontact.optim.Status``: MAXITER -1, INNER_FAILED -2,
NONFINITE -3, PENALTY_LIMIT -4, UNBOUNDED -5); compare members, not integers.

Examples
--------
>>> from alcontact.status import Status
>>> Status.INNER_FAILED is Status.NEWTON_FAILED, Status.CONVERGED_KKT.label
(True, 'converged')
>>> int(Status.MAXITER), Status.MAXITER.label, Status.from_inner("line-search").name
(-2, 'maxiter', 'LINE_SEARCH_FAILED')
"""

from __future__ import annotations

import enum

__all__ = ["Status", "INNER_REASONS", "CONTACT_CODES", "OPTIM_CODES"]


class Status(enum.IntEnum):
    """Termination reason; positive = converged, negative = failed (see the module table).

    Attributes
    ----------
    CONVERGED, CONVERGED_KKT
        All stopping tests are met (contact: physical measures; optimization:
        stationarity (C1), complementarity (C2), dual (C3) and primal (C4) feasibility).
    UNCONSTRAINED_CONVERGED
        No constraints; the gradient norm is below ``gtol``.
    NO_CONTACT
        The body never reaches the obstacle: no candidate contact point.
    MAXITER
        The outer iteration limit (``maxiter``) was reached.
    NEWTON_FAILED, INNER_FAILED
        The inner solver (Newton's method on a subproblem) failed (repeatedly, for
        the optimization engine), or no starting point lies inside a barrier's domain.
    NONFINITE
        A callback, traction or displacement is NaN or infinite.
    PENALTY_LIMIT
        The penalty parameter reached its bound and the constraints are still
        violated: the problem may be (locally) infeasible.
    UNBOUNDED
        A subproblem appears unbounded below.
    LINE_SEARCH_FAILED
        A line search found no decrease of the merit function (reported by inner
        solvers; the outer loops turn repeated inner failures into NEWTON_FAILED).
    NOT_VERIFIED
        The algorithm reported success, but the state it returns fails the
        penetration, complementarity or Coulomb tolerances when checked where the
        result is built (:mod:`alcontact.contact._verify`).
    """

    CONVERGED = 1
    CONVERGED_KKT = 1
    UNCONSTRAINED_CONVERGED = 2
    NO_CONTACT = -1
    MAXITER = -2
    NEWTON_FAILED = -3
    INNER_FAILED = -3
    NONFINITE = -4
    PENALTY_LIMIT = -5
    UNBOUNDED = -6
    LINE_SEARCH_FAILED = -7
    NOT_VERIFIED = -8

    @property
    def label(self) -> str:
        """``"converged"`` for every positive code, else the name in kebab case (``"newton-failed"``)."""
        return "converged" if self > 0 else self.name.lower().replace("_", "-")

    @property
    def success(self) -> bool:
        """``True`` for the positive (converged) codes."""
        return self > 0

    @classmethod
    def from_inner(cls, reason: str) -> "Status":
        """The code of an inner solver's reason string (see :data:`INNER_REASONS`).

        Unknown reasons map to :attr:`NEWTON_FAILED`.
        """
        return INNER_REASONS.get(reason, cls.NEWTON_FAILED)


#: Reasons of the inner solvers of :mod:`alcontact.optim` (``InnerResult.status``)
#: mapped onto the table; ``"small-step"`` (no further progress possible at the
#: requested precision) is accepted as converged, as the outer loop does.
INNER_REASONS: dict[str, Status] = {
    "converged": Status.CONVERGED,
    "small-step": Status.CONVERGED,
    "maxiter": Status.MAXITER,
    "line-search": Status.LINE_SEARCH_FAILED,
    "unbounded": Status.UNBOUNDED,
    "nonfinite": Status.NONFINITE,
}

#: The codes a contact solve (:func:`alcontact.contact.solve`: small or finite deformation, with or
#: without friction) can return; every failure among them is exercised by
#: ``tests/unit/test_failure_statuses.py``.
CONTACT_CODES: frozenset[Status] = frozenset({
    Status.CONVERGED, Status.NO_CONTACT, Status.MAXITER, Status.NEWTON_FAILED, Status.NONFINITE,
    Status.PENALTY_LIMIT, Status.NOT_VERIFIED, Status.UNBOUNDED,
})

#: The codes :func:`alcontact.optim.minimize` can return (inner-solver reasons such as
#: ``LINE_SEARCH_FAILED`` are turned into ``INNER_FAILED`` by the outer loop).
OPTIM_CODES: frozenset[Status] = frozenset({
    Status.CONVERGED_KKT, Status.UNCONSTRAINED_CONVERGED, Status.MAXITER, Status.INNER_FAILED,
    Status.NONFINITE, Status.PENALTY_LIMIT, Status.UNBOUNDED,
})
