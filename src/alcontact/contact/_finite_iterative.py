r"""AMG + CG solver of the Newton systems of finite-deformation contact (``linear_solver="amg"``).

:class:`~alcontact.contact._finite.FiniteContact` solves one symmetric system per Newton
iteration of subproblem (S) (module doc of :mod:`alcontact.contact._finite`),

.. math::

    J(x_k)\,\Delta x = -R(x_k), \qquad
    J = K_T + B^T \operatorname{diag}(w \circ dt_N/dg)\, B + \sum_i w_i t_{N,i} H_i,

and a few more with the same matrix (the dual Newton step of Algorithm 6.1,
:meth:`~alcontact.contact._finite.FiniteContact.multiplier_step`). The direct path
factorizes every :math:`J` (:class:`~alcontact.contact._finite.NewtonSolver`, MKL PARDISO).
:class:`AMGNewtonSolver` offers the same surface (``newton_step``, ``solve``, ``resolve``,
``info``) without a factorization: it is :class:`alcontact.linalg.NewtonKrylovSolver`
(preconditioned CG with the factors of an approximate solver, reused across Newton iterations
and load steps while they stay good, an Eisenstat-Walker forcing term, a symmetric-indefinite
factorization for a system with negative curvature, counted in ``direct_fallbacks``; the
measurements of its constants are those of this path) with the near-null space of the body:
the rigid-body modes at the *current configuration* :math:`x = X + u` of the load step's start
(:meth:`AMGNewtonSolver.near_null`); at finite rotations the modes of the reference
configuration are no longer the kernel of the tangent's elastic part. The curvature term
:math:`w_i t_{N,i} H_i` of a convex obstacle is negative semidefinite, so a buckling or strongly
curved contact state can make :math:`J` indefinite: with ``fallback=False`` that Newton step
fails (:class:`numpy.linalg.LinAlgError`) and the load step is cut back.

The semi-smooth reference ``ssn`` solves saddle-point systems (indefinite by construction)
and stays direct-only (its registry entry lists ``direct`` only).
"""

from __future__ import annotations

import numpy as np

from .. import linalg as _linalg
from ..errors import InputError
from ..fem.elasticity import rigid_body_modes
from ._finite import NewtonSolver

__all__ = ["AMGNewtonSolver", "finite_solver"]

#: configuration of the rigid-body near-null modes (:meth:`AMGNewtonSolver.near_null`). The reference
#: configuration's gave the same CG and Newton counts on both cases of the rebuild factor of
#: :class:`alcontact.linalg.NewtonKrylovSolver` (half-cylinder to delta/R = 0.4: 26.4 CG per Newton step
#: either way); the current one costs nothing more
_MODES = "current"


class AMGNewtonSolver(_linalg.NewtonKrylovSolver):
    r"""Solver of the Newton systems of :class:`~alcontact.contact._finite.FiniteContact` by AMG + CG.

    :class:`alcontact.linalg.NewtonKrylovSolver` (module doc) with the near-null space of the body:
    its rigid-body modes on the free DOFs at the configuration of :attr:`modes`.

    Parameters
    ----------
    fc : FiniteContact
        The model whose systems are solved (its free DOFs and current configuration give the
        rigid-body near-null space).
    solver : alcontact.linalg.SolverChoice, optional
        The approximate solver whose factors precondition CG (:func:`alcontact.linalg.select_solver`;
        default ``"amg"``, PyAMG smoothed aggregation with sparse LU on a coarsest level of at most
        500 rows).
    modes : {"current", "reference"}, optional
        Configuration of the rigid-body near-null modes; default ``_MODES`` (``"current"``).
    **options
        ``rtol``, ``forcing_max``, ``rebuild_factor``, ``fallback`` of :class:`~alcontact.linalg.NewtonKrylovSolver`.
    """

    def __init__(self, fc, *, solver: _linalg.SolverChoice | None = None, modes: str | None = None, **options):
        modes = _MODES if modes is None else modes
        if modes not in ("current", "reference"):
            raise InputError(f"modes={modes!r}; allowed: current, reference.")
        model = fc.model
        solver = _linalg.select_solver("amg", dim=model.dim, ndofs=model.ndofs) if solver is None else solver
        self.fc = fc
        self.modes = modes
        pts, dofs = model.all_node_dofs()
        self._pts = np.asarray(pts, dtype=float)
        self._dofs = np.asarray(dofs, dtype=np.int64)
        super().__init__(solver, near_null=self.near_null, dim=model.dim, **options)

    def near_null(self) -> np.ndarray:
        """Rigid-body modes ``(n_free, k)`` of the body at the configuration of :attr:`modes`.

        ``"current"``: at :math:`X + u` with ``u`` the displacement of the load step's start
        (:attr:`FiniteContact.u_free <alcontact.contact._finite.FiniteContact>`).
        """
        pts = self._pts
        if self.modes == "current":
            u = getattr(self.fc, "u_free", None)
            if u is not None:
                pts = pts + np.asarray(u, dtype=float)[self._dofs]
        modes, _ = rigid_body_modes(pts)
        R = np.zeros((self.fc.model.ndofs, modes.shape[-1]))
        R[self._dofs.ravel()] = modes.reshape(-1, modes.shape[-1])
        return np.ascontiguousarray(R[self.fc.free])

    def info(self) -> dict:
        """:meth:`alcontact.linalg.NewtonKrylovSolver.info` and the near-null configuration."""
        return {**super().info(), "near_null": self.modes}


def finite_solver(linear_solver: str, entry, model, **options):
    """Factory ``fc -> solver`` of the Newton systems of :class:`~alcontact.contact._finite.FiniteContact`.

    The solver of the ``linear_solver`` option is :func:`alcontact.linalg.select_solver`'s (its
    ``"auto"`` size rule where the algorithm ``entry`` has a Krylov path, :attr:`Algorithm.linear_solvers
    <alcontact.contact._algorithms.Algorithm>` listing ``amg``; an exact solver registered for
    symmetric indefinite matrices otherwise). An exact solver factorizes every Newton matrix
    (:class:`~alcontact.contact._finite.NewtonSolver`); an approximate one preconditions CG with an
    inexact-Newton forcing term (:class:`AMGNewtonSolver`) where the entry has a Krylov path, else
    GMRES around its factor of each matrix (:class:`~alcontact.linalg.SequenceSolver`).
    """
    solver = _linalg.select_solver(linear_solver, dim=model.dim, ndofs=model.ndofs, matrix_type="symmetric-indefinite",
                                   allow_iterative="amg" in entry.linear_solvers)
    if solver.exact or "amg" not in entry.linear_solvers:
        return lambda fc: NewtonSolver(solver.name)
    return lambda fc: AMGNewtonSolver(fc, solver=solver, **options)
