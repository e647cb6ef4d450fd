r"""Hyperelastic bodies in total Lagrangian form (finite deformation, chapter 3).

With the deformation gradient :math:`F = I + \nabla_X u` and a strain energy
density :math:`W(F)` (:mod:`alcontact.fem._hyper_materials`), the body stores

.. math::
    \Pi_{int}(u) = \int_{\Omega_0} W(F)\,dV, \qquad
    f_{int}(u) = \int_{\Omega_0} P(F) : \nabla_X \delta u\,dV, \qquad
    K_T(u) = \int_{\Omega_0} \nabla_X \delta u : \mathbb{A}(F) : \nabla_X \Delta u\,dV,

with :math:`P = \partial W/\partial F` the first Piola-Kirchhoff stress and
:math:`\mathbb{A} = \partial P/\partial F` (material plus geometric stiffness in
one tensor). :math:`f_{int}(u) = f_{ext}` is the discrete weak form of the
equilibrium :math:`\operatorname{Div} P + f = 0`, :math:`PN = \bar t` of (3.5),
(3.8) without contact; the contact layer adds the obstacle terms of (3.11). In
2D the body is in plane strain (:math:`F_{33} = 1`).

Everything else (named boundaries, Dirichlet data, load vectors on the reference
configuration, factorizations, rigid-motion checks) is inherited from
:class:`~alcontact.fem.LinearElasticity`; :meth:`Hyperelastic.stiffness` is the
tangent at :math:`u = 0`, which equals the linear elastic stiffness.

Assembly is vectorized: quadrature-point tensors with :func:`numpy.einsum`, and
the CSR sparsity pattern plus the position of every element-matrix entry in it
are computed once per body, so each tangent is one :func:`numpy.bincount`.
"""

from __future__ import annotations

import logging
import time
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from skfem import Basis

from alcontact.errors import ConvergenceError, InputError, InvertedElementError, LawDomainError, NonFiniteError
from alcontact.fem._assembly import default_intorder
from alcontact.fem._geometry import TWO_PI
from alcontact.fem._hyper_materials import HyperelasticLaw, det, make_material
from alcontact.fem._material import Material
from alcontact.fem.elasticity import LinearElasticity
from alcontact.optim import LineSearch, NewtonSettings, NewtonSystem, newton

__all__ = ["Hyperelastic"]

logger = logging.getLogger(__name__)


def _scalar_gradients(basis: Basis) -> np.ndarray:
    """Reference gradients of the local scalar shape functions, ``(nel, nqp, nloc, dim)``."""
    grads = np.stack([np.asarray(phi[0].grad) for phi in basis.basis])  # (nloc, dim, nel, nqp)
    return np.ascontiguousarray(grads.transpose(2, 3, 0, 1))


def _hoop_values(basis: Basis) -> tuple[np.ndarray, np.ndarray]:
    """Axisymmetric bodies: ``N_a / r`` at the quadrature points ``(nel, nqp, nloc)`` and the radius ``(nel, nqp)``."""
    r = np.asarray(basis.global_coordinates())[0]
    N = np.stack([np.asarray(phi[0]) for phi in basis.basis], axis=-1)  # (nel, nqp, nloc)
    return np.ascontiguousarray(N / r[..., None]), r


#: the entries of the flattened 3x3 gradient an axisymmetric displacement reaches: rr, rz, zr, zz, hoop
_AXI_USED = np.array([0, 1, 3, 4, 8])


def _axisymmetric_operators(G: np.ndarray, hoop: np.ndarray) -> np.ndarray:
    r"""``B[e, q, a, k, :]``: the 3x3 gradient :math:`\partial H / \partial u_{ak}` (flattened, row-major) of
    node ``a``'s component ``k`` (0 = r, 1 = z): :math:`e_k \otimes \nabla N_a` in the r-z block, plus
    :math:`N_a / r` at the hoop entry ``(2, 2)`` for ``k = 0``."""
    nel, nqp, nloc, _ = G.shape
    B = np.zeros((nel, nqp, nloc, 2, 9))
    for k in range(2):
        B[..., k, 3 * k: 3 * k + 2] = G
    B[..., 0, 8] = hoop
    return B


def _transpose_positions(indptr: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """``tperm[p]``: position of the transposed entry of CSR entry ``p`` (structurally symmetric pattern)."""
    n = indptr.size - 1
    rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(indptr))
    return np.searchsorted(rows * n + indices, indices.astype(np.int64) * n + rows)


def _pattern_generic(vdofs: np.ndarray, n: int):
    """CSR pattern of the element DOFs ``vdofs`` ``(nel, m)`` (any numbering).

    Returns
    -------
    indptr, indices : numpy.ndarray
        Sorted CSR structure.
    pos : numpy.ndarray, shape (nel, m * m)
        CSR position of each element-matrix entry (row-major ``(r, c)``).
    tperm : numpy.ndarray
        Position of the transposed entry of each CSR entry.
    """
    vdofs = np.asarray(vdofs, dtype=np.int64)  # n**2 overflows 32-bit DOF numbers above 46k DOFs
    keys = (vdofs[:, :, None] * n + vdofs[:, None, :]).ravel()
    # np.unique by hand: a stable (timsort) argsort exploits the runs of element-ordered keys
    order = np.argsort(keys, kind="stable")
    sk = keys[order]
    new = np.empty(sk.size, dtype=bool)
    new[:1] = True
    np.not_equal(sk[1:], sk[:-1], out=new[1:])
    uniq = sk[new]
    pos = np.empty(keys.size, dtype=np.int64)
    pos[order] = np.cumsum(new) - 1
    rows, indices = np.divmod(uniq, n)
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
    return indptr, indices, pos.reshape(vdofs.shape[0], -1), _transpose_positions(indptr, indices)


def _pattern_interleaved(sdofs: np.ndarray, ns: int, d: int):
    """Same as :func:`_pattern_generic` for the interleaved numbering ``dof = d * k + c``.

    The pattern is the scalar node graph with every entry a dense ``d x d``
    block, so only the scalar pattern (``nloc**2`` entries per element instead
    of ``(d nloc)**2``) is sorted and everything else follows in closed form:
    entry ``(d k + i, d m + l)`` sits at ``d^2 sind[k] + i d deg[k] + d rank(k, m) + l``
    with ``rank(k, m)`` the position of ``m`` in the scalar row ``k``.
    """
    nel, nloc = sdofs.shape
    sind, sidx, spos, stperm = _pattern_generic(sdofs, ns)
    deg = np.diff(sind)
    nnz_s = sidx.size
    # vector position of block entry (p_s, i, l) of every scalar entry p_s = (k, m)
    srow = np.repeat(np.arange(ns, dtype=np.int64), deg)
    i = np.arange(d).reshape(1, d, 1)
    l_ = np.arange(d).reshape(1, 1, d)

    def vpos(p, row, ii, ll):
        return (d * d * sind[row] + d * (p - sind[row]))[:, None, None] + ii * (d * deg[row])[:, None, None] + ll

    ps = np.arange(nnz_s, dtype=np.int64)
    where = vpos(ps, srow, i, l_).ravel()
    nnz = d * d * nnz_s
    indices = np.empty(nnz, dtype=np.int64)
    indices[where] = np.broadcast_to(d * sidx[:, None, None] + l_, (nnz_s, d, d)).ravel()
    tperm = np.empty(nnz, dtype=np.int64)
    tperm[where] = vpos(stperm, sidx, np.swapaxes(i, 1, 2), np.swapaxes(l_, 1, 2)).ravel()
    indptr = np.empty(ns * d + 1, dtype=np.int64)
    indptr[:-1] = (d * d * sind[:-1, None] + np.arange(d)[None, :] * d * deg[:, None]).ravel()
    indptr[-1] = nnz
    # element entries: (a, i, b, l) of element e
    k = np.repeat(sdofs, nloc, axis=1)  # row node of each (a, b) entry
    base = (d * d * sind[k] + d * (spos - sind[k])).reshape(nel, nloc, 1, nloc, 1)
    rowstep = (d * deg[sdofs]).reshape(nel, nloc, 1, 1, 1)
    pos = base + i.reshape(1, 1, d, 1, 1) * rowstep + l_.reshape(1, 1, 1, 1, d)
    return indptr, indices, pos.reshape(nel, -1), tperm



def _deformation_gradient(u: np.ndarray, dof_map: np.ndarray, sdofs: np.ndarray, G: np.ndarray,
                          hoop: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    r"""``F`` and ``J = det F`` at the quadrature points of ``G`` for the displacement ``u``; raises if some ``J <= 0``.

    :math:`F_{iJ} = \delta_{iJ} + u_{ai}\,\partial N_a/\partial X_J`, shape ``(nel, nqp, dim, dim)``
    (``dof_map``: the vector DOFs of each scalar DOF, ``sdofs``: the scalar DOFs of each element).
    Axisymmetric (``hoop``: :math:`N_a / r` at the points): the 3x3
    :math:`F = [[F_{rr}, F_{rz}, 0], [F_{zr}, F_{zz}, 0], [0, 0, 1 + u_r/r]]`. Shared by the
    displacement body and the mixed one (:mod:`alcontact.fem.mixed`).
    """
    uloc = np.swapaxes(u[dof_map[sdofs]], 1, 2)  # (nel, dim, nloc)
    F = uloc[:, None] @ G  # F_iJ = u_ai dN_a/dX_J at every point: (nel, nqp, dim, dim)
    F += np.eye(G.shape[-1])
    if hoop is not None:
        F3 = np.zeros(F.shape[:2] + (3, 3))
        F3[..., :2, :2] = F
        F3[..., 2, 2] = 1.0 + np.einsum("eqa,ea->eq", hoop, uloc[:, 0])
        F = F3
    J = det(F)
    bad = ~(J > 0.0)
    if bad.any():
        elements, shown = _listed(bad)
        raise InvertedElementError(
            f"{elements.size} of {F.shape[0]} elements inverted (J = det F <= 0 at a quadrature "
            f"point, min J = {float(np.nanmin(J)):.3g}): elements {shown}. The displacement is too "
            "large for this mesh: reject the Newton step (line search) or cut the load step.",
            elements=elements,
        )
    return F, J


def _listed(flags: np.ndarray) -> tuple[np.ndarray, str]:
    """Elements with a flagged quadrature point (``flags``: (nel, nqp)) and the first 20 of them as text."""
    elements = np.flatnonzero(flags.any(axis=1))
    return elements, ", ".join(map(str, elements[:20])) + (", ..." if elements.size > 20 else "")

#: Line search of the body's own solves: halve the step (at most down to 2**-13) while it inverts an
#: element or does not lower the free residual; a step below 2e-4 is taken as it is.
_BODY_NEWTON = NewtonSettings(line_search=LineSearch(halvings=14, armijo=0.0, merit=False, measure_decrease=True,
                                                     accept_below=2e-4, full_step=False), stall=0.0)


class _BodyNewton(NewtonSystem):
    r"""Equilibrium :math:`f_{int}(u) - f_{ext} = 0` on the free DOFs of one load increment.

    The state at ``u`` is ``(r, |r_free|)``; the measure is the absolute free residual,
    compared with ``tol`` times :attr:`scale` (the larger of the load and the residual at
    the start of the increment, set by the first :meth:`evaluate`). Each step factorizes the
    tangent :math:`K_T(u)` on the free DOFs.
    """

    domain_errors = (InvertedElementError,)

    def __init__(self, body: "Hyperelastic", fext: np.ndarray, dofs: np.ndarray, free: np.ndarray):
        self.body, self.fext, self.dofs, self.free = body, fext, dofs, free
        self.scale: float | None = None

    def evaluate(self, x):
        r = self.body.internal_force(x) - self.fext
        norm = float(np.linalg.norm(r[self.free]))
        if self.scale is None:  # the start of the increment
            self.scale = max(float(np.linalg.norm(self.fext[self.free])), norm, 1e-300)
        return r, norm

    def residual(self, state):
        return state[0][self.free]

    def measure(self, state):
        return state[1]

    def tolerance(self, state, tol):
        return tol * self.scale

    def step(self, x, state, history):
        logger.debug("hyperelastic Newton it %d: |R| = %.3e", len(history) - 1, state[1])
        fac = self.body.factorize(self.dofs, matrix=self.body.tangent(x), check=False)
        du = np.zeros(self.body.ndofs)
        du[self.free] = fac.solve(-state[0][self.free])
        return du


class Hyperelastic(LinearElasticity):
    r"""Total Lagrangian hyperelastic body with vector P1 or P2 Lagrange elements.

    Parameters
    ----------
    mesh : skfem.MeshTri, skfem.MeshTet, skfem.MeshTri2 or skfem.MeshTet2
        (second order: curved, isoparametric P2; see :class:`~alcontact.fem.LinearElasticity`)
        Mesh with named boundaries, e.g. from :mod:`alcontact.fem.meshes`.
    material : Material
        Elastic constants; the law uses the Lamé constants :math:`(\lambda, \mu)`
        (3D values; in 2D ``plane`` must be ``"strain"``).
    order : {1, 2}
        Polynomial degree.
    model : str or HyperelasticLaw
        Registered law name (:func:`~alcontact.fem.available_materials`:
        ``"neo-hookean"``, ``"saint-venant-kirchhoff"``) or a law instance such
        as a :class:`~alcontact.fem.SymbolicMaterial`.
    intorder : int, optional
        Quadrature degree; default ``2 (order - 1)`` (at least 1), exact for the
        linearized stiffness, so that ``stiffness()`` equals the linear elastic one;
        on a curved (``MeshTri2``/``MeshTet2``) mesh 4 (triangles) or 5 (tetrahedra), the
        degree of the linear elastic stiffness there (``alcontact.fem._assembly.default_intorder``).

    Attributes
    ----------
    law : HyperelasticLaw
    linear : bool
        ``False``: the tangent depends on ``u``.

    Notes
    -----
    The inherited load vectors (:meth:`traction_load`, :meth:`pressure_load`,
    :meth:`body_load`) are dead loads on the reference configuration: a traction
    is a nominal traction :math:`PN` per reference area, a pressure acts along the
    reference normal. :meth:`stress` and :meth:`von_mises` return the Cauchy
    stress in the current configuration, :meth:`first_piola` the nominal stress.

    Examples
    --------
    >>> import numpy as np
    >>> from alcontact.fem import Hyperelastic, Material, meshes
    >>> body = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1.0, nu=0.3))
    >>> u = body.interpolate(lambda x: np.stack([0.1 * x[0], 0 * x[1]]))  # 10 % stretch in x
    >>> bool(body.energy(u) > 0), body.tangent(u).shape
    (True, (18, 18))
    """

    #: the internal force is nonlinear in u: Newton on the full tangent
    linear = False

    def __init__(self, mesh, material: Material, order: int = 1, model: str | HyperelasticLaw = "neo-hookean",
                 intorder: int | None = None, geometry: str = "cartesian"):
        super().__init__(mesh, material, order, geometry=geometry)
        mesh = self.mesh  # a curved mesh with order=1 is replaced by its straight-sided vertices
        if self.dim == 2 and material.plane != "strain":
            raise InputError(
                f"material.plane={material.plane!r}: hyperelastic bodies in 2D are plane strain only "
                "(plane stress would need F33 solved at each point); use Material(..., plane='strain') "
                "or a 3D mesh."
            )
        # Material already holds -1 < nu < 0.5, which every compressible law needs
        self.law = make_material(model)
        self._check_moduli(material)
        if intorder is None:  # axisymmetric: the degree of the linear stiffness there (rational in r)
            intorder = default_intorder(mesh, self.order)
            if self.axisymmetric:
                intorder = max(intorder, 2 * self.order)
        if isinstance(intorder, bool) or not isinstance(intorder, (int, np.integer)) or intorder < 1:
            raise InputError(f"intorder={intorder!r} must be a positive integer (quadrature degree).")
        self.intorder = int(intorder)
        self.quadrature_basis = Basis(mesh, self.scalar_element, intorder=self.intorder)
        self._G = _scalar_gradients(self.quadrature_basis)
        self._dx = np.ascontiguousarray(self.quadrature_basis.dx)
        self._hoop = None
        if self.axisymmetric:  # N_a / r at the points and the 2 pi r of the measure
            self._hoop, r = _hoop_values(self.quadrature_basis)
            self._dx = np.ascontiguousarray(self._dx * TWO_PI * r)
        sdofs = np.ascontiguousarray(self.quadrature_basis.element_dofs.T)  # (nel, nloc)
        self._sdofs = sdofs
        self._vdofs = self.dof_map[sdofs].reshape(sdofs.shape[0], -1)  # (nel, nloc*dim), a-major
        self._kept_gradient: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def _check_moduli(self, material: Material) -> None:
        r"""The law linearized at :math:`F = I` must be the material's linear elasticity.

        The linear elastic stiffness of the body (:meth:`stiffness`, contact scalings)
        uses ``material``; a law that fixes :math:`\mu_0` or :math:`K_0` by its own
        parameters (:meth:`~alcontact.fem.HyperelasticLaw.fixed_moduli`) must agree.
        """
        lam, mu = material.lame(3)
        lam0, mu0 = self.law.reference_moduli(lam, mu)
        if not (np.isfinite(lam0) and np.isfinite(mu0)) or abs(mu0 - mu) > 1e-6 * mu \
                or abs(lam0 - lam) > 1e-6 * (lam + 2.0 * mu / 3.0):
            K0 = lam0 + 2.0 * mu0 / 3.0
            fix = ""
            if mu0 > 0 and K0 > 0:
                E0, nu0 = 9.0 * K0 * mu0 / (3.0 * K0 + mu0), (3.0 * K0 - 2.0 * mu0) / (2.0 * (3.0 * K0 + mu0))
                if abs(K0 - (lam + 2.0 * mu / 3.0)) <= 1e-6 * K0:
                    E0, nu0 = 2.0 * mu0 * (1.0 + material.nu), material.nu
                fix = f" Use Material(E={E0:.12g}, nu={nu0:.12g}) for these law parameters."
            raise InputError(
                f"material law {self.law.name!r} linearizes at F = I to shear modulus {mu0:.6g} and lambda "
                f"{lam0:.6g}, but Material(E={material.E:g}, nu={material.nu:g}) has mu = {mu:.6g}, lambda = "
                f"{lam:.6g}: the law's initial moduli must equal the material's (consistency with linear "
                f"elasticity).{fix}"
            )

    # ------------------------------------------------------------- kinematics
    def _check_u(self, u) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        if u.shape != (self.ndofs,):
            raise InputError(f"u must have shape ({self.ndofs},); got {u.shape}.")
        if not np.all(np.isfinite(u)):
            raise NonFiniteError("displacement u contains NaN or infinity; the previous step diverged.")
        return u

    def _gradient(self, u: np.ndarray, G: np.ndarray, sdofs: np.ndarray,
                  hoop: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``F`` and ``J`` at the quadrature points of ``G``; raises if some ``J <= 0``.

        Axisymmetric (``hoop``: ``N_a / r`` at the points): the 3x3
        :math:`F = [[F_{rr}, F_{rz}, 0], [F_{zr}, F_{zz}, 0], [0, 0, 1 + u_r/r]]`.
        """
        F, J = _deformation_gradient(u, self.dof_map, sdofs, G, hoop)
        out = self.law.domain_violation(F)
        if out is not None and out.any():
            elements, shown = _listed(out)
            raise LawDomainError(
                f"{elements.size} of {F.shape[0]} elements deformed beyond the domain of material law "
                f"{self.law.name!r} (e.g. the Gent locking I1b - 3 >= Jm): elements {shown}. Reject the Newton "
                "step or cut the load step; if the stretch is physical, raise the law's limit (Jm).",
                elements=elements,
            )
        return F, J

    def _state_gradient(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``F`` and ``J`` at the quadrature points for a checked ``u``, the last state's kept.

        A Newton iteration evaluates the internal force and the energy of a trial state and,
        once the line search accepts it, the tangent there: all three share one deformation
        gradient (read-only arrays; a state that inverts an element is not kept).
        """
        kept = self._kept_gradient
        if kept is not None and np.array_equal(kept[0], u):
            return kept[1], kept[2]
        F, J = self._gradient(u, self._G, self._sdofs, self._hoop)
        F.flags.writeable = False
        J.flags.writeable = False
        self._kept_gradient = (u.copy(), F, J)
        return F, J

    def deformation_gradient(self, u) -> np.ndarray:
        r"""Deformation gradient :math:`F = I + \nabla_X u` at the quadrature points.

        Returns
        -------
        numpy.ndarray, shape (nel, nqp, dim, dim)
            (axisymmetric: ``(nel, nqp, 3, 3)`` with the hoop stretch :math:`1 + u_r/r` at ``[2, 2]``)

        Raises
        ------
        alcontact.errors.InvertedElementError
            If :math:`J = \det F \le 0` at some quadrature point (``.elements`` lists them).
        """
        return self._gradient(self._check_u(u), self._G, self._sdofs, self._hoop)[0]

    # ------------------------------------------------- Body protocol (fem._body)
    def energy(self, u) -> float:
        r"""Stored energy :math:`\Pi_{int}(u) = \int_{\Omega_0} W(F)\,dV`."""
        F, _ = self._state_gradient(self._check_u(u))
        lam, mu = self.lam, self.mu
        return float(np.sum(self.law.energy(F, lam, mu) * self._dx))

    def strain_energy(self, u) -> float:
        """Same as :meth:`energy` (the linear body's name for it)."""
        return self.energy(u)

    def internal_force(self, u) -> np.ndarray:
        r"""Internal force :math:`f_{int}(u) = \int_{\Omega_0} P(F) : \nabla_X \delta u\,dV`, shape ``(ndofs,)``."""
        F, _ = self._state_gradient(self._check_u(u))
        P = self.law.stress(F, self.lam, self.mu)
        if self._hoop is not None:  # P_iJ dN_a/dX_J in the r-z block, plus P_33 N_a / r for the radial component
            Pw = P * self._dx[:, :, None, None]
            fe = (self._G @ np.swapaxes(Pw[..., :2, :2], -1, -2)).sum(axis=1)
            fe[..., 0] += np.einsum("eqa,eq->ea", self._hoop, Pw[..., 2, 2])
            return np.bincount(self._vdofs.ravel(), weights=fe.ravel(), minlength=self.ndofs)
        fe = (self._G @ np.swapaxes(P * self._dx[:, :, None, None], -1, -2)).sum(axis=1)  # (nel, a, i)
        return np.bincount(self._vdofs.ravel(), weights=fe.ravel(), minlength=self.ndofs)

    @cached_property
    def _pattern(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        t0 = time.perf_counter()
        d = self.dim
        interleaved = np.array_equal(self.dof_map, d * np.arange(self.dof_map.shape[0])[:, None] + np.arange(d))
        if interleaved:
            indptr, indices, pos, tperm = _pattern_interleaved(self._sdofs, self.scalar_basis.N, d)
        else:
            indptr, indices, pos, tperm = _pattern_generic(self._vdofs, self.ndofs)
        idx_t = np.int32 if indptr[-1] < np.iinfo(np.int32).max else np.int64
        out = (indptr.astype(idx_t), indices.astype(idx_t), pos.astype(np.intp, copy=False).ravel(), tperm)
        logger.debug("tangent sparsity pattern: nnz=%d in %.3f s", int(indptr[-1]), time.perf_counter() - t0)
        return out

    @property
    def tangent_pattern(self) -> tuple[np.ndarray, np.ndarray]:
        """``(indptr, indices)`` of the CSR pattern of every :meth:`tangent` (sorted, read-only arrays).

        :meth:`tangent_data` fills it; a caller that keeps sparse structures built on it (the
        free-DOF block, a saddle-point matrix) updates only their values per tangent.
        """
        indptr, indices = self._pattern[:2]
        indptr.flags.writeable = False
        indices.flags.writeable = False
        return indptr, indices

    def tangent_data(self, u) -> np.ndarray:
        r"""Values of :meth:`tangent` at ``u`` in the CSR order of :attr:`tangent_pattern` (a new array)."""
        u = self._check_u(u)
        F, _ = self._state_gradient(u)
        if self._hoop is not None:
            Ke = self._axisymmetric_element_tangent(F)
        else:
            Ke = self.law.element_tangent(F, self._G, self._dx, self.lam, self.mu)  # (nel, a, i, b, k)
        indptr, indices, pos, tperm = self._pattern
        data = np.bincount(pos, weights=Ke.ravel(), minlength=int(indptr[-1]))
        return 0.5 * (data + data[tperm])  # remove round-off asymmetry (exactly symmetric CSR)

    def _axisymmetric_element_tangent(self, F: np.ndarray) -> np.ndarray:
        r"""Element tangents of a body of revolution, :math:`K^e_{aibk} = \sum_q w_q\,B_{ai} : \mathbb{A}(F) : B_{bk}`
        with the 3x3 operators :math:`B` of :func:`_axisymmetric_operators` and :math:`w_q` including :math:`2\pi r`."""
        nel, nqp, nloc, _ = self._G.shape
        B, Bt = self._axisymmetric_B
        A = self.law.tangent(F, self.lam, self.mu).reshape(nel, nqp, 9, 9)[:, :, _AXI_USED[:, None], _AXI_USED]
        A *= self._dx[:, :, None, None]
        K = (np.matmul(B, A) @ Bt).sum(axis=1)
        return K.reshape(nel, nloc, 2, nloc, 2)

    @cached_property
    def _axisymmetric_B(self) -> tuple[np.ndarray, np.ndarray]:
        """The operators of :func:`_axisymmetric_operators` at the quadrature points and their transposes
        (constant: computed once)."""
        nel, nqp, nloc, _ = self._G.shape
        B = _axisymmetric_operators(self._G, self._hoop).reshape(nel, nqp, nloc * 2, 9)[..., _AXI_USED]
        return np.ascontiguousarray(B), np.ascontiguousarray(np.swapaxes(B, -1, -2))

    def tangent(self, u) -> sp.csr_matrix:
        r"""Tangent stiffness :math:`K_T(u) = \partial f_{int}/\partial u` (symmetric CSR, material + geometric)."""
        data = self.tangent_data(u)
        indptr, indices = self._pattern[:2]
        # own copies of the structure: in-place scipy operations (eliminate_zeros, ...) on one
        # tangent must not change the cached pattern of the next
        K = sp.csr_matrix((data, indices.copy(), indptr.copy()), shape=(self.ndofs, self.ndofs))
        K.has_sorted_indices = True
        return K

    def stiffness(self) -> sp.csr_matrix:
        """Tangent at ``u = 0`` (equals the linear elastic stiffness; cached)."""
        if self._stiffness is None:
            self._stiffness = self.tangent(np.zeros(self.ndofs))
        return self._stiffness

    # ----------------------------------------------------------------- solving
    def solve(self, load, dirichlet=(), *, steps: int = 1, rtol: float = 1e-10, max_iter: int = 25) -> np.ndarray:
        r"""Solve :math:`f_{int}(u) = f_{ext}` by Newton's method with load steps.

        The load and the Dirichlet values are applied in ``steps`` equal increments;
        each increment runs Newton (:func:`alcontact.optim.newton`, the one Newton of the
        contact algorithms) from the previous solution, halving the update while it
        inverts an element or raises the residual.

        Parameters
        ----------
        load : numpy.ndarray, shape (ndofs,)
            Dead load on the reference configuration.
        dirichlet : list of (dofs, values)
            As returned by :meth:`dirichlet`.
        steps : int
            Number of load increments.
        rtol : float
            Convergence when the free residual is below ``rtol`` times the larger
            of the load and the first residual of the step.
        max_iter : int
            Newton iterations per increment.

        Raises
        ------
        alcontact.errors.ConvergenceError
            If an increment does not converge: iteration limit, failed line search,
            a tangent that is singular inside the increment, or prescribed displacements
            that invert elements at its start (the message says what to try).
        """
        load = np.asarray(load, dtype=float)
        if load.shape != (self.ndofs,):
            raise InputError(f"load must have shape ({self.ndofs},); got {load.shape}.")
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise InputError(f"steps={steps!r} must be a positive integer.")
        dofs, vals = self._collect_fixed(dirichlet)
        self.check_restrained(dofs)
        free = np.ones(self.ndofs, dtype=bool)
        free[dofs] = False
        u = np.zeros(self.ndofs)
        for step in range(1, int(steps) + 1):
            s = step / steps
            u[dofs] = s * vals
            fext = s * load
            u = self._newton(u, fext, dofs, free, rtol, max_iter, step, steps)
        return u

    def _newton(self, u, fext, dofs, free, rtol, max_iter, step, steps) -> np.ndarray:
        """One load increment by :func:`alcontact.optim.newton` on :class:`_BodyNewton`."""
        system = _BodyNewton(self, fext, dofs, free)
        try:
            out = newton(system, u, tol=rtol, maxiter=max_iter, settings=_BODY_NEWTON)
        except InvertedElementError as exc:
            if system.scale is not None:  # not the start (inside newton an inverted trial only halves the step)
                raise
            raise ConvergenceError(
                f"load step {step}/{steps}: the prescribed displacements invert elements "
                f"({exc.elements.size}); use more load steps (steps={2 * steps})."
            ) from exc
        if out.converged:
            return out.x
        msg = (f"hyperelastic Newton did not converge in load step {step}/{steps} "
               f"({out.message}; |R| = {out.residual:.3e} > {rtol:.1e} * {system.scale:.3e}); use more load steps "
               f"(steps={2 * steps}) or a larger max_iter.")
        logger.warning(msg)
        raise ConvergenceError(msg)

    # ----------------------------------------------------------- postprocess
    @cached_property
    def _output_geometry(self) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        sb = self.scalar_basis
        hoop = _hoop_values(sb)[0] if self.axisymmetric else None
        return _scalar_gradients(sb), np.ascontiguousarray(sb.element_dofs.T), hoop

    def _quadrature_tensors(self, u) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
        """``F, J, P`` and (2D) ``P33`` at the quadrature points of the output basis."""
        G, sdofs, hoop = self._output_geometry
        F, J = self._gradient(self._check_u(u), G, sdofs, hoop)
        P = self.law.stress(F, self.lam, self.mu)
        if hoop is not None:  # the hoop stress P_33
            return F, J, P, P[..., 2, 2]
        P33 = self.law.stress_zz(F, self.lam, self.mu) if self.dim == 2 else None
        return F, J, P, P33

    def _quadrature_stress(self, u) -> list[np.ndarray]:
        r"""Cauchy stress :math:`\sigma = J^{-1} P F^T` at quadrature points (Voigt order, plus zz in 2D)."""
        F, J, P, P33 = self._quadrature_tensors(u)
        s = np.einsum("eqiJ,eqkJ->eqik", P, F) / J[..., None, None]
        if self.dim == 2:  # zz: plane strain P_33 / J (F_33 = 1); axisymmetric the hoop sigma_33 = P_33 F_33 / J
            zz = s[..., 2, 2] if F.shape[-1] == 3 else P33 / J
            return [s[..., 0, 0], s[..., 1, 1], 0.5 * (s[..., 0, 1] + s[..., 1, 0]), zz]
        return [s[..., 0, 0], s[..., 1, 1], s[..., 2, 2], 0.5 * (s[..., 1, 2] + s[..., 2, 1]),
                0.5 * (s[..., 0, 2] + s[..., 2, 0]), 0.5 * (s[..., 0, 1] + s[..., 1, 0])]

    def stress(self, u, *, include_zz: bool = False) -> np.ndarray:
        """Nodal Cauchy stress (current configuration) by L2 projection; columns as
        :meth:`LinearElasticity.stress` (``xx, yy, xy`` [+ ``zz``] or ``xx, yy, zz, yz, xz, xy``).

        Raises
        ------
        alcontact.errors.InvertedElementError
            If ``u`` inverts an element.
        """
        return super().stress(u, include_zz=include_zz)

    def first_piola(self, u, *, include_zz: bool = False) -> np.ndarray:
        r"""Nodal first Piola-Kirchhoff (nominal) stress :math:`P` by L2 projection.

        Returns
        -------
        numpy.ndarray, shape (n_scalar, dim * dim [+ 1])
            Rows aligned with :meth:`all_node_dofs`; columns :math:`P_{iJ}` row-major
            (``xx, xy, yx, yy`` in 2D, plus :math:`P_{33}` if ``include_zz``; nine in 3D).
            :math:`P` is not symmetric: :math:`P_{iJ}` is the force in direction ``i``
            per reference area normal to ``J``.
        """
        _, _, P, P33 = self._quadrature_tensors(u)
        comps = [P[..., i, j] for i in range(self.dim) for j in range(self.dim)]
        if self.dim == 2 and include_zz:
            comps.append(P33)
        return self._project(comps)
