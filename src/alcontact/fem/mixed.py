r"""Mixed displacement-pressure hyperelastic bodies for (nearly) incompressible rubber.

A displacement element with a compressible law whose bulk modulus :math:`\kappa` is
thousands of times its shear modulus :math:`\mu` locks: the discrete displacements
cannot keep :math:`J = 1` in every element, and the volumetric energy stiffens the
body. The perturbed-Lagrangian (two-field) form adds an independent pressure
:math:`p` (Simo, Taylor and Pister 1985; Holzapfel, *Nonlinear Solid Mechanics*,
2000, section 8.5; dissertation chapter 3 leaves :math:`W` open):

.. math::
    \Pi(u, p) = \int_{\Omega_0} \Bigl[\bar W(\bar F) + p\,(J - 1) - \frac{p^2}{2\kappa}\Bigr]dV
    - \Pi_{ext}(u), \qquad \bar F = J^{-1/3} F,

stationary (a saddle point: a minimum in :math:`u`, a maximum in :math:`p`). Its
residual and consistent tangent are

.. math::
    R_u &= \int_{\Omega_0} \bigl(\bar P + p\,J F^{-T}\bigr) : \nabla_X\delta u\,dV - f_{ext},
    \qquad R_p = \int_{\Omega_0} \Bigl(J - 1 - \frac{p}{\kappa}\Bigr)\,\delta p\,dV,

    K = \begin{bmatrix} K_{uu} & K_{up} \\ K_{up}^T & -M_p/\kappa \end{bmatrix}, \quad
    K_{uu} = \int \nabla\delta u : \bigl(\bar{\mathbb A} + p\,J\,(F^{-T}\otimes F^{-T}
    - F^{-T}\,\bar\otimes\,F^{-T})\bigr) : \nabla\Delta u, \quad
    K_{up} = \int J F^{-T} : \nabla\delta u\;\Delta p ,

symmetric and indefinite. Eliminating :math:`p` gives the volumetric energy
:math:`\frac{\kappa}{2}(J - 1)^2` pointwise: at the same :math:`\mu, \kappa` the
material is the split law of :mod:`alcontact.fem._hyper_laws` (with
:math:`K = \kappa`). :math:`\kappa = \infty` (``nu = 0.5``) is the exactly
incompressible solid, :math:`p` the Lagrange multiplier of :math:`J = 1`
(:math:`M_p/\kappa = 0`). :math:`p` is the hydrostatic Cauchy stress
(positive in tension, :math:`\sigma = \bar\sigma + p I`).

The discretization is Taylor-Hood: vector P2 displacement and continuous P1 pressure
on triangles (plane strain, :math:`F_{33} = 1`; or a body of revolution in the r-z
half-plane, :math:`F_{33} = 1 + u_r/r` and the weight :math:`2\pi r`,
:mod:`alcontact.fem._geometry`) or tetrahedra, inf-sup stable, so the pressure neither
locks nor oscillates. On a curved second-order mesh (``MeshTri2``/``MeshTet2``) both
fields live on its isoparametric map (the P1 pressure on the vertices). The unknown vector is
``x = [u, p]``, the displacement DOFs (numbered as in a P2
:class:`~alcontact.fem.Hyperelastic` on the same mesh) first, then ``npressure``
pressure DOFs (one per vertex): Dirichlet data, node DOFs, boundary weights and load
vectors of the displacement part keep their numbers. Each Newton system is solved by
a direct factorization of symmetric indefinite matrices
(:class:`~alcontact.linalg.SequenceSolver`, MKL PARDISO with Bunch-Kaufman pivoting
when installed, SuperLU otherwise), or, with ``linear_solver = "amg"``, by a Krylov method
preconditioned block-diagonally (:meth:`saddle_point`: AMG on the displacement block, the
lumped pressure mass on the pressure rows; :mod:`alcontact.linalg._saddle`).

Examples
--------
>>> import numpy as np
>>> from alcontact.fem import meshes
>>> from alcontact.fem.mixed import MixedHyperelastic
>>> body = MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), E=3.0, nu=0.5)
>>> body.ndofs_u, body.npressure, body.ndofs
(50, 9, 59)
>>> x = body.solve(body.traction_load("right", [0.1, 0.0]),
...                [body.dirichlet("left", [0]), body.dirichlet("bottom", [1])])
>>> J = np.linalg.det(body.deformation_gradient(x))
>>> bool(np.allclose(J, 1.0))
True
"""

from __future__ import annotations

import logging
import math
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTetP1, ElementTriP1

from alcontact.errors import ConvergenceError, InputError, InvertedElementError, NonFiniteError
from alcontact.fem._assembly import default_intorder
from alcontact.fem._hyper_laws import InvariantLaw, _isochoric
from alcontact.fem._hyper_materials import HyperelasticLaw, NeoHookean, inv, make_material
from alcontact.fem._material import Material, material_issues
from alcontact.fem.elasticity import LinearElasticity
from alcontact.fem._geometry import TWO_PI
from alcontact.fem.hyperelastic import (_AXI_USED, _axisymmetric_operators, _deformation_gradient, _hoop_values,
                                       _scalar_gradients)

__all__ = ["FORMULATIONS", "IsochoricNeoHookean", "MixedHyperelastic"]

logger = logging.getLogger(__name__)

#: values of ``material.formulation``: the displacement element, or the mixed u-p element of this module
FORMULATIONS = ("displacement", "mixed")


class IsochoricNeoHookean(InvariantLaw):
    r"""Neo-Hookean isochoric energy :math:`\bar W = \frac{\mu}{2}(\bar I_1 - 3)`, :math:`\bar I_1 = J^{-2/3}I_1`.

    The mixed body adds the volumetric part through its pressure; at :math:`\kappa = \infty`
    this is the incompressible neo-Hookean solid (Treloar), :math:`P = \mu F - \hat p F^{-T}`.
    """

    name = "neo-hookean"
    SUMMARY = "W = mu/2 (I1b - 3) (isochoric; the mixed body adds p (J - 1) - p^2 / (2 kappa))."

    def energy_expression(self, I1, I2, J, lam, mu, p):
        return mu / 2 * (_isochoric(I1, I2, J)[0] - 3)


def _isochoric_law(model: str | HyperelasticLaw, mu: float) -> tuple[HyperelasticLaw, float]:
    r"""The law of the deviatoric part and the :math:`\lambda` that removes its volumetric term.

    The split laws (:mod:`alcontact.fem._hyper_laws`) carry :math:`\frac{K}{2}(J-1)^2` with
    :math:`K = \lambda + 2\mu/3`: evaluated at :math:`\lambda = -2\mu/3` they are purely
    isochoric. The compressible ``"neo-hookean"`` of :mod:`~alcontact.fem._hyper_materials` is
    not split; its isochoric counterpart :class:`IsochoricNeoHookean` is used. Any other law is
    checked: with :math:`K = 0` its energy must not change under a dilatation :math:`F \to sF`.
    """
    lam_iso = -2.0 * mu / 3.0
    if (isinstance(model, str) and model == "neo-hookean") or type(model) is NeoHookean:
        return IsochoricNeoHookean(), lam_iso
    law = make_material(model)
    # W_iso(F_bar) does not change under a dilatation F -> s F
    F0 = np.array([[1.1, 0.2, 0.0], [-0.1, 0.9, 0.05], [0.0, 0.1, 1.05]])
    F = np.array([1.0, 1.2, 0.8])[:, None, None] * F0
    W = np.asarray(law.energy(F, lam_iso, mu), dtype=float)
    if not np.all(np.abs(W - W[0]) <= 1e-12 * mu):
        raise InputError(
            f"material law {law.name!r} is not in isochoric/volumetric split form (its energy changes by "
            f"{float(np.max(np.abs(W - W[0]))):.3g} under a dilatation once K = lambda + 2 mu / 3 = 0): the mixed "
            "formulation needs W = W_iso(F_bar) + U(J). Use 'neo-hookean', 'mooney-rivlin', 'yeoh', 'gent', "
            "'arruda-boyce' or 'ogden', or formulation = 'displacement'."
        )
    return law, lam_iso


class MixedHyperelastic:
    r"""Total Lagrangian Taylor-Hood (P2 displacement / P1 pressure) hyperelastic body (module doc).

    Parameters
    ----------
    mesh : skfem.MeshTri, skfem.MeshTet, skfem.MeshTri2 or skfem.MeshTet2
        Mesh with named boundaries, e.g. from :mod:`alcontact.fem.meshes`; on a second-order
        (curved) mesh both fields use its isoparametric map (the P2 displacement on every node, the
        P1 pressure on the vertices).
    E : float
        Young's modulus of the linearized material, ``> 0``.
    nu : float
        Poisson's ratio, ``-1 < nu <= 0.5``; ``0.5`` is exactly incompressible.
        :math:`\mu = E/(2(1+\nu))`, :math:`\kappa = E/(3(1-2\nu))` (:math:`\infty` at 0.5).
    model : str or HyperelasticLaw
        ``"neo-hookean"`` (:class:`IsochoricNeoHookean`) or a split law by name or instance
        (``"mooney-rivlin"``, ``"yeoh"``, ... with its parameters already set); its
        volumetric term is replaced by the pressure's.
    intorder : int, optional
        Quadrature degree; default that of a P2 :class:`~alcontact.fem.Hyperelastic` on the same
        mesh and geometry (2 on straight-sided meshes, exact for the linearized Taylor-Hood matrices;
        4 or 5 on curved ones; at least 4 for a body of revolution, whose hoop terms are rational in r).
    linear_solver : str, optional
        Registry name of the solver of its own Newton systems (:meth:`solve`,
        :class:`~alcontact.linalg.SequenceSolver`): a direct solver for symmetric indefinite matrices
        (default: the preferred installed one), or ``"amg"`` (GMRES with the block-diagonal
        preconditioner of :meth:`saddle_point`).
    geometry : {"cartesian", "axisymmetric"}
        ``"axisymmetric"``: a body of revolution in the r-z half-plane
        (:mod:`alcontact.fem._geometry`). :math:`F` is then 3x3 with the hoop stretch
        :math:`F_{33} = 1 + u_r/r`, so :math:`J = F_{33}\det F_{rz}` and the pressure term
        :math:`p\,J F^{-T}:\nabla\delta u` has the hoop part :math:`p\,J F_{33}^{-1}\,\delta u_r/r`;
        every volume integral carries :math:`2\pi r` (forces are totals over the revolution).

    Attributes
    ----------
    ndofs_u, npressure, ndofs : int
        Displacement DOFs, pressure DOFs, and their sum (the length of ``x``).
    mu, kappa : float
        Shear and bulk modulus (``kappa = inf`` when incompressible).
    newton_iterations : list of int
        Newton iterations of each load step of the last :meth:`solve`.
    linear_solves : int
        Saddle-point factorizations of the last :meth:`solve`.
    linear_solver_used : str or None
        Registry name of the linear solver of the last :meth:`solve`.
    """

    #: the internal force is nonlinear in x
    linear = False
    order = 2

    def __init__(self, mesh, E: float, nu: float, *, model: str | HyperelasticLaw = "neo-hookean",
                 intorder: int | None = None, linear_solver: str | None = None, geometry: str = "cartesian"):
        incompressible = isinstance(nu, (int, float, np.floating)) and not isinstance(nu, bool) and nu == 0.5
        issues = material_issues(E, 0.25 if incompressible else nu)
        if issues:
            raise InputError(" ".join(f"MixedHyperelastic {key}={msg[2:]}" for key, msg in issues)
                             + (" (the mixed formulation also allows nu = 0.5)" if any(k == "nu" for k, _ in issues)
                                else ""))
        E, nu = float(E), float(nu)
        self.E, self.nu = E, nu
        self.mu = E / (2.0 * (1.0 + nu))
        self.kappa = math.inf if incompressible else E / (3.0 * (1.0 - 2.0 * nu))
        #: the linearized constants (nu = 1/2 held as 1/2 - 1e-9, which Material accepts): the contact
        #: layer's automatic penalty reads E / (1 - nu^2) from it; no stiffness is built from it
        self.material = Material(E=E, nu=min(nu, 0.5 - 1e-9), plane="strain")
        # geometry, DOF numbering, boundaries, loads and Dirichlet data of the P2 displacement field
        self.geometry = LinearElasticity(mesh, self.material, order=2, geometry=geometry)
        self.mesh = mesh = self.geometry.mesh
        self.dim = self.geometry.dim
        self.law, self._lam_iso = _isochoric_law(model, self.mu)
        lam0, mu0 = self.law.reference_moduli(self._lam_iso, self.mu)
        if not abs(mu0 - self.mu) <= 1e-6 * self.mu:
            raise InputError(
                f"material law {self.law.name!r} has initial shear modulus {mu0:.6g}, but E={E:g}, nu={nu:g} give "
                f"mu = {self.mu:.6g}; use E = {2.0 * mu0 * (1.0 + nu):.12g} for these law parameters."
            )
        if intorder is None:  # as a P2 Hyperelastic: axisymmetric, the degree of the linear stiffness there
            intorder = default_intorder(mesh, 2)
            if self.geometry.axisymmetric:
                intorder = max(intorder, 4)
        if isinstance(intorder, bool) or not isinstance(intorder, (int, np.integer)) or not 1 <= intorder <= 10:
            raise InputError(f"intorder={intorder!r} must be an integer in 1..10 (quadrature degree; default 2, "
                             "exact for the linearized Taylor-Hood matrices).")
        self.intorder = int(intorder)
        self.ndofs_u = self.geometry.ndofs
        qb = Basis(mesh, self.geometry.scalar_element, intorder=self.intorder)
        pb = Basis(mesh, ElementTriP1() if self.dim == 2 else ElementTetP1(), intorder=self.intorder)
        self.pressure_basis = pb
        # the P1 pressure lives on the vertices: on a curved mesh scikit-fem numbers its DOFs over every
        # node of the mesh (mesh.p holds the edge nodes too); the vertices are numbered first
        self.npressure = int(mesh.t.max()) + 1
        self.ndofs = self.ndofs_u + self.npressure
        self._G = _scalar_gradients(qb)  # (nel, nqp, nloc, dim)
        self._dx = np.ascontiguousarray(qb.dx)
        self._hoop = None
        if self.geometry.axisymmetric:  # N_a / r at the points and the 2 pi r of the measure
            self._hoop, r = _hoop_values(qb)
            self._dx = np.ascontiguousarray(self._dx * TWO_PI * r)
        self._sdofs = np.ascontiguousarray(qb.element_dofs.T)
        self._vdofs = self.geometry.dof_map[self._sdofs].reshape(self._sdofs.shape[0], -1)  # a-major
        self._N = np.ascontiguousarray(np.stack([np.asarray(phi[0]) for phi in pb.basis], axis=-1))  # (e, q, m)
        self._pdofs = np.ascontiguousarray(pb.element_dofs.T) + self.ndofs_u  # (nel, m) in x
        if int(pb.element_dofs.max()) + 1 != self.npressure:
            raise InputError("MixedHyperelastic: the P1 pressure DOFs are not the mesh vertices (an unexpected "
                             "node numbering of this mesh); renumber the mesh with its vertices first.")
        self._linear_solver = linear_solver
        self.newton_iterations: list[int] = []
        self.linear_solves = 0
        self.linear_solver_used: str | None = None

    # ------------------------------------------------------------ geometry (displacement part)
    def __getattr__(self, name):
        # boundaries, node DOFs, boundary weights, load vectors and Dirichlet data are those of the
        # displacement field (same numbers in x): delegated to the P2 geometry
        if name in ("boundary_names", "facets", "node_dofs", "all_node_dofs", "boundary_weights",
                    "traction_load", "pressure_load", "body_load", "dirichlet", "dof_map", "scalar_doflocs",
                    "scalar_basis", "basis", "interpolate", "check_restrained", "probe", "free_rigid_motions",
                    "boundary_pressure", "boundary_field_at_quadrature", "release_geometry", "scalar_element",
                    "element", "scalar_dofs", "axisymmetric", "axis_dofs"):
            return getattr(self.__dict__["geometry"], name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def split(self, x) -> tuple[np.ndarray, np.ndarray]:
        """``(u, p)``: the displacement (``ndofs_u``) and the nodal pressure (``npressure``) of ``x``."""
        x = self._check_x(x)
        return x[: self.ndofs_u], x[self.ndofs_u:]

    def pad(self, f_u) -> np.ndarray:
        """A displacement-sized vector (a load) extended by zeros for the pressure rows."""
        f_u = np.asarray(f_u, dtype=float)
        if f_u.shape == (self.ndofs,):
            return f_u
        if f_u.shape != (self.ndofs_u,):
            raise InputError(f"vector must have shape ({self.ndofs_u},) or ({self.ndofs},); got {f_u.shape}.")
        return np.concatenate([f_u, np.zeros(self.npressure)])

    def _check_x(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (self.ndofs,):
            raise InputError(f"x must have shape ({self.ndofs},) (displacement then pressure); got {x.shape}.")
        if not np.all(np.isfinite(x)):  # the error the contact layer's step control handles, as for Hyperelastic
            raise NonFiniteError("x contains NaN or infinity; the previous step diverged.")
        return x

    # ----------------------------------------------------------------- kinematics
    def _state(self, x, where=None):
        """``F, J, p`` at the quadrature points of the forms, or of ``where = (G, sdofs, N, pdofs, hoop)``
        (axisymmetric: ``F`` 3x3 with the hoop stretch :math:`1 + u_r/r` at ``[2, 2]``)."""
        x = self._check_x(x)
        G, sdofs, N, pdofs, hoop = (self._G, self._sdofs, self._N, self._pdofs, self._hoop) if where is None \
            else where
        u = x[: self.ndofs_u]
        F, J = _deformation_gradient(u, self.geometry.dof_map, sdofs, G, hoop)
        p = np.einsum("eqm,em->eq", N, x[pdofs])
        return F, J, p

    def deformation_gradient(self, x) -> np.ndarray:
        """:math:`F` at the quadrature points, shape ``(nel, nqp, dim, dim)`` (axisymmetric ``(nel, nqp, 3, 3)``)."""
        return self._state(x)[0]

    # ------------------------------------------------------------- postprocess
    @cached_property
    def _output_points(self):
        """``(G, sdofs, N, pdofs, hoop)`` at the quadrature points of the stress projection (:attr:`scalar_basis`)."""
        sb = self.geometry.scalar_basis
        pb = Basis(self.mesh, self.pressure_basis.elem, quadrature=sb.quadrature)
        N = np.ascontiguousarray(np.stack([np.asarray(phi[0]) for phi in pb.basis], axis=-1))
        hoop = _hoop_values(sb)[0] if self._hoop is not None else None
        return (_scalar_gradients(sb), np.ascontiguousarray(sb.element_dofs.T), N,
                np.ascontiguousarray(pb.element_dofs.T) + self.ndofs_u, hoop)

    def _quadrature_stress(self, x) -> list[np.ndarray]:
        r"""Cauchy stress :math:`\sigma = J^{-1}\bar P F^T + p I` at the projection's quadrature points
        (Voigt order, plus zz in 2D: :math:`J^{-1}\bar P_{33} + p`; axisymmetric: the hoop stress)."""
        F, J, p = self._state(x, self._output_points)
        P = self.law.stress(F, self._lam_iso, self.mu)
        s = np.einsum("eqiJ,eqkJ->eqik", P, F) / J[..., None, None] + p[..., None, None] * np.eye(F.shape[-1])
        if self.dim == 2:
            szz = s[..., 2, 2] if F.shape[-1] == 3 else self.law.stress_zz(F, self._lam_iso, self.mu) / J + p
            return [s[..., 0, 0], s[..., 1, 1], 0.5 * (s[..., 0, 1] + s[..., 1, 0]), szz]
        return [s[..., 0, 0], s[..., 1, 1], s[..., 2, 2], 0.5 * (s[..., 1, 2] + s[..., 2, 1]),
                0.5 * (s[..., 0, 2] + s[..., 2, 0]), 0.5 * (s[..., 0, 1] + s[..., 1, 0])]

    def stress(self, x, *, include_zz: bool = False) -> np.ndarray:
        """Nodal Cauchy stress by L2 projection, columns as :meth:`~alcontact.fem.LinearElasticity.stress`."""
        comps = self._quadrature_stress(x)
        if self.dim == 2 and not include_zz:
            comps = comps[:3]
        return self.geometry._project(comps)

    def von_mises(self, x) -> np.ndarray:
        """Nodal von Mises stress of the Cauchy stress (plane strain includes ``zz``), shape ``(n_scalar,)``."""
        return LinearElasticity.von_mises(self, x)

    def _inv_kappa(self) -> float:
        return 0.0 if math.isinf(self.kappa) else 1.0 / self.kappa

    # -------------------------------------------------------------------- forms
    def energy(self, x) -> float:
        """``nan``: the two-field functional is stationary at a saddle point, not a minimum, so it is no
        merit function for a line search (the :class:`~alcontact.fem.Body` protocol's "no stored energy";
        the contact layer then globalizes on the residual). Its value is :meth:`functional`."""
        self._check_x(x)
        return float("nan")

    def functional(self, x) -> float:
        r"""Value of the two-field functional :math:`\int \bar W + p(J-1) - p^2/(2\kappa)\,dV` (a saddle point)."""
        F, J, p = self._state(x)
        W = self.law.energy(F, self._lam_iso, self.mu) + p * (J - 1.0) - 0.5 * self._inv_kappa() * p * p
        return float(np.sum(W * self._dx))

    def internal_force(self, x) -> np.ndarray:
        r"""Residual of the internal forces :math:`[R_u + f_{ext};\ R_p]` (module doc), shape ``(ndofs,)``."""
        F, J, p = self._state(x)
        Fi = inv(F, J)
        P = self.law.stress(F, self._lam_iso, self.mu) + (p * J)[..., None, None] * np.swapaxes(Fi, -1, -2)
        Pw = P * self._dx[:, :, None, None]
        if self._hoop is not None:  # P_iJ dN_a/dX_J in the r-z block, plus P_33 N_a / r for the radial component
            fe = (self._G @ np.swapaxes(Pw[..., :2, :2], -1, -2)).sum(axis=1)
            fe[..., 0] += np.einsum("eqa,eq->ea", self._hoop, Pw[..., 2, 2])
        else:
            fe = (self._G @ np.swapaxes(Pw, -1, -2)).sum(axis=1)  # (nel, a, i)
        out = np.bincount(self._vdofs.ravel(), weights=fe.ravel(), minlength=self.ndofs)
        rp = ((J - 1.0 - self._inv_kappa() * p) * self._dx)[..., None] * self._N
        out += np.bincount(self._pdofs.ravel(), weights=rp.sum(axis=1).ravel(), minlength=self.ndofs)
        return out

    @cached_property
    def _coo(self) -> tuple[np.ndarray, np.ndarray]:
        el = np.concatenate([self._vdofs, self._pdofs], axis=1)  # (nel, m)
        rows = np.repeat(el, el.shape[1], axis=1).ravel()
        cols = np.tile(el, (1, el.shape[1])).ravel()
        return rows, cols

    def tangent(self, x) -> sp.csr_matrix:
        r"""Consistent tangent :math:`\partial[R_u; R_p]/\partial[u; p]` (symmetric indefinite CSR, module doc)."""
        F, J, p = self._state(x)
        nel, nqp, nloc, d = self._G.shape
        if self._hoop is not None:
            Kuu, Kup = self._axisymmetric_blocks(F, J, p)
        else:
            Kuu = self.law.element_tangent(F, self._G, self._dx, self._lam_iso, self.mu)  # (nel, a, i, b, k)
            g = self._G @ inv(F, J)  # g_ai = G_aJ Fi_Ji: J F^{-T} : grad(N_a e_i) = J g_ai
            w = p * J * self._dx
            Kuu = Kuu + np.einsum("eq,eqai,eqbk->eaibk", w, g, g) - np.einsum("eq,eqak,eqbi->eaibk", w, g, g)
            Kup = np.einsum("eq,eqai,eqm->eaim", J * self._dx, g, self._N).reshape(nel, nloc * d, -1)
        Kpp = -self._inv_kappa() * np.einsum("eq,eqm,eqn->emn", self._dx, self._N, self._N)
        m = nloc * d + Kpp.shape[1]
        Ke = np.zeros((nel, m, m))
        Ke[:, : nloc * d, : nloc * d] = Kuu.reshape(nel, nloc * d, nloc * d)
        Ke[:, : nloc * d, nloc * d:] = Kup
        Ke[:, nloc * d:, : nloc * d] = np.swapaxes(Kup, 1, 2)
        Ke[:, nloc * d:, nloc * d:] = Kpp
        rows, cols = self._coo
        K = sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(self.ndofs, self.ndofs))
        K.sum_duplicates()
        return ((K + K.T) * 0.5).tocsr()  # exactly symmetric (round-off of the isochoric tangent)

    @cached_property
    def _axisymmetric_B(self) -> np.ndarray:
        """The 3x3 gradient operators of the displacement DOFs (:func:`~alcontact.fem.hyperelastic`'s
        ``_axisymmetric_operators``) restricted to the entries ``rr, rz, zr, zz, hoop``: ``(nel, nqp, 2 nloc, 5)``."""
        nel, nqp, nloc, _ = self._G.shape
        B = _axisymmetric_operators(self._G, self._hoop).reshape(nel, nqp, nloc * 2, 9)[..., _AXI_USED]
        return np.ascontiguousarray(B)

    def _axisymmetric_blocks(self, F, J, p) -> tuple[np.ndarray, np.ndarray]:
        r""":math:`K_{uu}` ``(nel, a, i, b, k)`` and :math:`K_{up}` ``(nel, 2 nloc, m)`` of a body of revolution.

        With the 3x3 operators :math:`B` (:math:`\nabla\delta u` including the hoop entry
        :math:`\delta u_r / r`): :math:`K_{uu} = \sum_q w_q B : (\bar{\mathbb A} + pJ(F^{-T}\otimes F^{-T}
        - F^{-T}\bar\otimes F^{-T})) : B^T`, :math:`K_{up} = \sum_q w_q (B : J F^{-T}) N_m`,
        :math:`w_q` including :math:`2\pi r`.
        """
        nel, nqp, nloc, _ = self._G.shape
        B = self._axisymmetric_B
        FiT = np.swapaxes(inv(F, J), -1, -2)  # F^{-T}
        A = self.law.tangent(F, self._lam_iso, self.mu)  # (nel, nqp, 3, 3, 3, 3): dP_iJ / dF_kL
        pJ = (p * J)[..., None, None, None, None]
        A = A + pJ * (np.einsum("eqij,eqkl->eqijkl", FiT, FiT) - np.einsum("eqil,eqkj->eqijkl", FiT, FiT))
        A = A.reshape(nel, nqp, 9, 9)[:, :, _AXI_USED[:, None], _AXI_USED] * self._dx[:, :, None, None]
        Kuu = (np.matmul(B, A) @ np.swapaxes(B, -1, -2)).sum(axis=1).reshape(nel, nloc, 2, nloc, 2)
        a = (FiT * (J * self._dx)[..., None, None]).reshape(nel, nqp, 9)[..., _AXI_USED]
        Kup = np.einsum("eqas,eqs,eqm->eam", B, a, self._N)
        return Kuu, Kup

    # ------------------------------------------------------------- saddle point
    @cached_property
    def lumped_pressure_mass(self) -> np.ndarray:
        r"""Row sums of the P1 pressure mass matrix :math:`M_p = \int N_m N_n\,dV` (:math:`2\pi r` in
        :math:`dV` for a body of revolution), one per pressure DOF, all positive."""
        w = (self._dx[..., None] * self._N).sum(axis=1)  # (nel, m): int N_m over each element
        return np.bincount((self._pdofs - self.ndofs_u).ravel(), weights=w.ravel(), minlength=self.npressure)

    def saddle_point(self, free=None):
        r"""The blocks of the Newton matrices on the DOFs ``free`` (:class:`~alcontact.linalg.SaddlePoint`).

        The Newton matrix :math:`[K_{uu}, K_{up}; K_{up}^T, -M_p/\kappa]` restricted to ``free`` (a boolean
        mask of length :attr:`ndofs` or the sorted free DOFs; default all) has its displacement rows first,
        since the pressure DOFs are numbered last and never prescribed. The Schur complement
        :math:`S = M_p/\kappa + K_{up}^T K_{uu}^{-1} K_{up}` is approximated by the lumped pressure mass
        scaled by :math:`1/\mu + 1/\kappa` (Elman, Silvester and Wathen 2014, section 9.3 for nearly
        incompressible elasticity; :math:`K_{uu} \approx \mu\,\nabla:\nabla` on the displacements and
        :math:`K_{up}` the divergence at :math:`F = I`): spectrally equivalent to :math:`S` uniformly in the
        mesh size and in :math:`\kappa`, including :math:`\kappa = \infty` (:mod:`alcontact.linalg._saddle`).
        The factor of :math:`1/\mu` was measured at 0.5, 1 and 2 (MINRES iterations within 5 %:
        ``docs/benchmarks/mixed_amg.md``).
        """
        from alcontact.linalg import SaddlePoint

        free = np.ones(self.ndofs, dtype=bool) if free is None else np.asarray(free)
        if free.dtype != bool:  # sorted indices of the free DOFs
            idx = free.astype(np.int64)
            if idx.ndim != 1 or np.any(np.diff(idx) <= 0) or (idx.size and (idx[0] < 0 or idx[-1] >= self.ndofs)):
                raise InputError(f"free must be a boolean mask of shape ({self.ndofs},) or sorted DOF indices.")
            free = np.zeros(self.ndofs, dtype=bool)
            free[idx] = True
        if free.shape != (self.ndofs,):
            raise InputError(f"free must be a boolean mask of shape ({self.ndofs},); got {free.shape}.")
        if not np.all(free[self.ndofs_u:]):
            raise InputError("MixedHyperelastic.saddle_point: a pressure DOF is not free (the pressure is never "
                             "prescribed); pass the mask of the free displacement DOFs plus every pressure DOF.")
        scale = 1.0 / self.mu + self._inv_kappa()
        return SaddlePoint(int(np.count_nonzero(free[: self.ndofs_u])), self.lumped_pressure_mass * scale,
                           label="lumped pressure mass x (1/mu + 1/kappa)")

    def near_null(self) -> np.ndarray:
        """Rigid-body modes of the reference configuration on every DOF of ``x`` (zero on the pressure rows),
        shape ``(ndofs, k)``: the near-null space of the displacement block for algebraic multigrid."""
        from alcontact.fem.elasticity import rigid_body_modes

        pts, dofs = self.geometry.all_node_dofs()
        modes, _ = rigid_body_modes(pts)
        out = np.zeros((self.ndofs, modes.shape[-1]))
        out[np.asarray(dofs).ravel()] = modes.reshape(-1, modes.shape[-1])
        return out

    # ------------------------------------------------------------------ solving
    def solve(self, load, dirichlet=(), *, steps: int = 1, rtol: float = 1e-10, max_iter: int = 25) -> np.ndarray:
        r"""Solve :math:`R(x) = 0` by Newton's method on the saddle-point system, with load steps.

        Parameters
        ----------
        load : numpy.ndarray, shape (ndofs_u,) or (ndofs,)
            Dead load on the reference configuration (displacement rows).
        dirichlet : list of (dofs, values)
            Displacement data from :meth:`dirichlet` (the pressure is never prescribed).
        steps : int
            Equal increments of the load and of the Dirichlet values.
        rtol : float
            Convergence when the free residual is below ``rtol`` times the larger of the load
            and the first residual of the step (displacement and pressure rows together).
        max_iter : int
            Newton iterations per increment.

        Returns
        -------
        numpy.ndarray, shape (ndofs,)
            ``x = [u, p]`` (:meth:`split`).

        Raises
        ------
        alcontact.errors.ConvergenceError
            If an increment does not converge (the message says what to try).
        """
        from alcontact.linalg import SequenceSolver

        fext_full = self.pad(load)
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise InputError(f"steps={steps!r} must be a positive integer.")
        dofs, vals = self.geometry._collect_fixed(dirichlet)  # plus u_r = 0 on the axis of a body of revolution
        self.geometry.check_restrained(dofs)
        free = np.ones(self.ndofs, dtype=bool)
        free[dofs] = False
        # an approximate solver (AMG) preconditions GMRES block-diagonally on the saddle-point systems
        solver = SequenceSolver(self._linear_solver, matrix_type="symmetric-indefinite",
                                saddle=self.saddle_point(free), near_null=lambda: self.near_null()[free])
        self.newton_iterations, self.linear_solves = [], 0
        self.linear_solver_used = solver.backend
        x = np.zeros(self.ndofs)
        try:
            for step in range(1, int(steps) + 1):
                s = step / steps
                x = self._newton(x, s * fext_full, dofs, s * vals, free, solver, rtol, max_iter, step, steps)
        finally:
            solver.release()
        return x

    def _newton(self, x, fext, dofs, target, free, solver, rtol, max_iter, step, steps) -> np.ndarray:
        # the increment of the prescribed displacements enters the Newton systems (consistent
        # linearization), so that it is spread over the body instead of inverting the boundary layer
        def residual(v):
            r = self.internal_force(v) - fext
            return r, float(np.linalg.norm(r[free]))

        r, norm = residual(x)
        scale = max(float(np.linalg.norm(fext[free])), norm, 1e-300)
        for it in range(max_iter + 1):
            logger.debug("mixed newton step %d/%d it %d: |R| = %.3e", step, steps, it, norm)
            dd = target - x[dofs]
            if norm <= rtol * scale and not np.any(dd):
                self.newton_iterations.append(it)
                return x
            if it == max_iter:
                break
            K = self.tangent(x)
            dx = np.zeros(self.ndofs)
            dx[dofs] = dd
            kick = K[free][:, dofs] @ dd
            if it == 0:  # the force the prescribed increment alone would produce sets the scale too
                scale = max(scale, float(np.linalg.norm(kick)))
            dx[free] = solver.solve(K[free][:, free], -r[free] - kick)
            self.linear_solves += 1
            t = 1.0
            while t > 1e-4:
                try:
                    r_new, norm_new = residual(x + t * dx)
                except InvertedElementError:
                    t *= 0.5
                    continue
                if norm_new < norm or t < 2e-4 or np.any(dd):  # a Dirichlet increment raises |R| by design
                    break
                t *= 0.5
            else:
                break
            x = x + t * dx
            if t == 1.0:
                x[dofs] = target  # exactly, not up to round-off
                r, norm = residual(x)
            else:
                r, norm = r_new, norm_new
        msg = (f"mixed u-p Newton did not converge in load step {step}/{steps} (|R| = {norm:.3e} > {rtol:.1e} * "
               f"{scale:.3e}); use more load steps (steps={2 * steps}) or a larger max_iter.")
        logger.warning(msg)
        raise ConvergenceError(msg)
