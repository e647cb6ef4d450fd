r"""Small-strain linear elasticity on triangles and tetrahedra (P1/P2) with scikit-fem.

The model assembles

.. math::
    a(u, v) = \int_\Omega 2\mu\,\varepsilon(u):\varepsilon(v) + \lambda\,
    \operatorname{tr}\varepsilon(u)\,\operatorname{tr}\varepsilon(v)\,dx,
    \qquad \ell(v) = \int_\Omega f\cdot v\,dx + \int_{\Gamma_N} t\cdot v\,ds,

with :math:`\lambda` the plane-stress corrected constant in 2D when
``material.plane == "stress"`` (see :meth:`Material.lame`).

DOF numbering
-------------
scikit-fem's :class:`~skfem.ElementVector` interleaves the components: the
vector DOF of component ``c`` at scalar DOF ``k`` is ``dof_map[k, c]`` (equal
to ``dim * k + c`` for the Lagrange elements used here, but always use the
map). Scalar DOF ``k`` sits at ``scalar_doflocs[:, k]`` (vertices first,
then edge midpoints for P2).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
import skfem
from scipy.sparse.linalg import cg
from skfem import Basis, BilinearForm, ElementVector, FacetBasis, LinearForm, asm
from skfem.assembly import Dofs
from skfem.helpers import ddot, dot, sym_grad, trace

from alcontact._options import VALUE_RANGE, show
from alcontact.errors import InputError, MeshError
from alcontact.fem._assembly import default_intorder, elasticity_stiffness, is_curved, scalar_doflocs, straight_mesh
from alcontact.fem._geometry import AXISYMMETRIC, TWO_PI, axis_points, check_geometry
from alcontact.fem._linalg import Factorization, nested_dissection
from alcontact.linalg import MatrixHints
from alcontact.fem._material import Material
from alcontact.fem.quality import check_mesh_quality, element_mapping

__all__ = ["VOLUMETRIC_FORMULATIONS", "LinearElasticity", "numerical_rank", "rigid_body_modes"]

logger = logging.getLogger(__name__)

_ELEMENTS = {
    (skfem.MeshTri1, 1): skfem.ElementTriP1,
    (skfem.MeshTri1, 2): skfem.ElementTriP2,
    (skfem.MeshTet1, 1): skfem.ElementTetP1,
    (skfem.MeshTet1, 2): skfem.ElementTetP2,
    # second-order (curved) meshes: the P2 field uses the isoparametric map of the mesh
    (skfem.MeshTri2, 2): skfem.ElementTriP2,
    (skfem.MeshTet2, 2): skfem.ElementTetP2,
}

_AXES = "xyz"


def rigid_body_modes(points: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Rigid-body displacement fields evaluated at ``points``.

    Parameters
    ----------
    points : numpy.ndarray, shape (m, dim)
        Locations (dim 2 or 3).

    Returns
    -------
    modes : numpy.ndarray, shape (m, dim, n_modes)
        Translations then rotations (about the centroid, scaled by the extent
        so all columns have comparable size).
    names : list of str
        ``"translation x"``, ..., ``"rotation about z"``.
    """
    try:
        points = np.asarray(points, dtype=float)
    except (TypeError, ValueError, OverflowError):
        points = None
    if points is None or points.ndim != 2 or points.shape[1] not in (2, 3) or not np.all(np.isfinite(points)):
        raise InputError("rigid_body_modes: points must be a finite (m, 2) or (m, 3) array of coordinates.")
    m, dim = points.shape
    c = points - points.mean(axis=0) if m else points
    scale = float(np.max(np.abs(c))) if m and np.max(np.abs(c)) > 0 else 1.0
    c = c / scale
    cols, names = [], []
    for i in range(dim):
        e = np.zeros((m, dim))
        e[:, i] = 1.0
        cols.append(e)
        names.append(f"translation {_AXES[i]}")
    axes = [2] if dim == 2 else [0, 1, 2]
    for ax in axes:  # rotation about axis ax: omega x r
        omega = np.zeros(3)
        omega[ax] = 1.0
        r3 = np.zeros((m, 3))
        r3[:, :dim] = c
        rot = np.cross(omega, r3)[:, :dim]
        cols.append(rot)
        names.append(f"rotation about {_AXES[ax]}")
    return np.stack(cols, axis=-1), names


def _floats(value, what: str) -> np.ndarray:
    """``value`` as a float array; :class:`InputError` naming ``what`` for strings, None, huge ints, ragged lists."""
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None:
        raise InputError(f"{what} must be numbers; got {show(value)}. Pass numbers (not strings, None or bools).")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"{what} must be finite numbers; got {show(value)} ({exc}).") from None
    lo, hi = VALUE_RANGE
    mag = np.abs(arr[np.isfinite(arr)])
    if np.any((mag > hi) | ((mag > 0) & (mag < lo))):
        raise InputError(f"{what} = {show(value)}: magnitudes outside {lo:g} .. {hi:g} overflow or underflow in "
                         "the solver (energies square them); express the loads and E in other units (e.g. MPa "
                         "instead of Pa), or use 0 for no load.")
    return arr


def _rank(a: np.ndarray) -> int:
    """Numerical rank (relative tolerance 1e-9) of a small dense matrix."""
    if a.size == 0:
        return 0
    s = np.linalg.svd(a, compute_uv=False)
    return int(np.sum(s > 1e-9 * s[0])) if s[0] > 0 else 0


def numerical_rank(a: Any) -> int:
    """Numerical rank of a small dense matrix: the singular values above ``1e-9`` times the largest.

    The test of the rigidity checks (supports and contact points against the rigid-body
    modes, :meth:`LinearElasticity.free_rigid_motions`).

    Raises
    ------
    InputError
        ``a`` is not a 2D array of finite real numbers.

    Examples
    --------
    >>> numerical_rank([[1.0, 2.0], [2.0, 4.0]])
    1
    """
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError, OverflowError):
        arr = None
    if arr is None or arr.ndim != 2 or not np.all(np.isfinite(arr)):
        raise InputError(f"numerical_rank: a = {show(a)}: expected a 2D array of finite real numbers, e.g. "
                         "[[1.0, 0.0], [0.0, 1.0]].")
    return _rank(arr)


def describe_motions(null: np.ndarray, names: list[str]) -> str:
    """The free rigid motions ``null`` (rows: coefficients of the modes ``names``) in words."""
    out = []
    for vec in null:
        vec = vec / np.max(np.abs(vec))
        out.append(" + ".join(names[i] for i in np.flatnonzero(np.abs(vec) > 1e-6)))
    return "; ".join(out)


def _rref(a: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Reduced row echelon form of a small full-row-rank matrix (for readable messages)."""
    a = np.array(a, dtype=float)
    row = 0
    for col in range(a.shape[1]):
        if row == a.shape[0]:
            break
        piv = row + int(np.argmax(np.abs(a[row:, col])))
        if abs(a[piv, col]) <= tol:
            continue
        a[[row, piv]] = a[[piv, row]]
        a[row] /= a[row, col]
        others = np.arange(a.shape[0]) != row
        a[others] -= np.outer(a[others, col], a[row])
        row += 1
    a[np.abs(a) < tol] = 0.0
    return a


class _FullVolumetric:
    r"""The standard volumetric term :math:`\lambda\,\operatorname{tr}\varepsilon(u)\operatorname{tr}\varepsilon(v)`.

    Standard displacement elements; P1 and, less so, P2 lock as :math:`\nu \to 1/2`.
    """

    name = "full"
    orders = (1, 2)

    def stiffness(self, model: LinearElasticity) -> sp.spmatrix:
        if is_curved(model.mesh):  # isoparametric map: scikit-fem's assembly (already in dof_map numbering)
            lam, mu = model.lam, model.mu

            @BilinearForm
            def full(u, v, w):
                eu, ev = sym_grad(u), sym_grad(v)
                return 2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)

            K = asm(full, _stiffness_basis(model)).tocsr()
            K = (0.5 * (K + K.T)).tocsr()  # remove round-off asymmetry
            K.sum_duplicates()
            K.sort_indices()
            return K
        # strains are of degree order-1 on affine simplices: intorder 2(order-1) is exact
        K = elasticity_stiffness(model.mesh, model.scalar_element, model.scalar_dofs.element_dofs,
                                 int(model.scalar_dofs.N), model.lam, model.mu,
                                 intorder=max(1, 2 * (model.order - 1)))
        dm = model.dof_map
        interleaved = np.array_equal(dm, model.dim * np.arange(dm.shape[0])[:, None] + np.arange(model.dim))
        if not interleaved:  # K is in the numbering d k + c: permute to the DOFs of dof_map
            perm = np.empty(model.ndofs, dtype=np.int64)
            perm[dm.ravel()] = np.arange(model.ndofs)
            K = K[perm][:, perm].tocsr()
            K.sort_indices()
        return K  # exactly symmetric

    def isotropic_stress(self, model: LinearElasticity, tr: np.ndarray, dx: np.ndarray) -> np.ndarray:
        r"""Isotropic part of the stress at quadrature points: :math:`\lambda\operatorname{tr}\varepsilon`."""
        return model.lam * tr


class _ProjectedP0Volumetric:
    r"""The volumetric strain projected onto element-wise constants (P2-P0 mixed element, pressure condensed).

    With :math:`c = 2\mu/3` and :math:`\kappa = \lambda + c` the bulk modulus
    (plane stress: :math:`\lambda^*` for :math:`\lambda`), the energy
    :math:`2\mu\,\varepsilon:\varepsilon + \lambda(\operatorname{tr}\varepsilon)^2`
    is split into a deviatoric and a volumetric part, and only the latter is
    projected (:math:`\Pi_0`: mean over each element):

    .. math::
        a(u, v) = \int_\Omega 2\mu\,\varepsilon(u):\varepsilon(v)
        - c\,\operatorname{tr}\varepsilon(u)\operatorname{tr}\varepsilon(v)\,dx
        + \kappa \sum_e \frac{1}{|e|}\int_e \operatorname{div} u\,dx \int_e \operatorname{div} v\,dx,

    i.e. :math:`K = K_{dev} + \kappa B^T M_0^{-1} B` with :math:`B_{e i} = \int_e \operatorname{div}\phi_i`
    and :math:`M_0 = \operatorname{diag}(|e|)`: the mixed displacement/pressure
    element P2-P0 with its pressure eliminated element by element. It is the
    same energy when :math:`\operatorname{div} u` is constant per element (so the
    patch test holds), symmetric positive definite for :math:`\nu < 1/2`, and
    free of volumetric locking: P2-P0 satisfies the inf-sup condition
    (Boffi, Brezzi, Fortin 2013, section 8.4), so the error bounds do not depend
    on :math:`\lambda` (displacement in H1 and pressure in L2 of order :math:`h`).
    The stress uses the projected mean pressure:
    :math:`\sigma = 2\mu\,\varepsilon + (\kappa\,\Pi_0\operatorname{tr}\varepsilon
    - c\operatorname{tr}\varepsilon)\,I`.
    """

    name = "p0"
    orders = (2,)

    def stiffness(self, model: LinearElasticity) -> sp.spmatrix:
        lam, mu = model.lam, model.mu
        c = 2.0 * mu / 3.0

        @BilinearForm
        def dev(u, v, w):
            eu, ev = sym_grad(u), sym_grad(v)
            return 2.0 * mu * ddot(eu, ev) - c * trace(eu) * trace(ev)

        basis = _stiffness_basis(model)
        K_dev = asm(dev, basis)
        # B[e, dof]: integral of div phi over element e (exact: div phi is of degree order-1)
        dx = np.asarray(basis.dx)  # (nel, nqp)
        vol = dx.sum(axis=1)
        ed = np.asarray(basis.element_dofs)  # (nloc, nel)
        vals = np.empty(ed.shape)
        for i in range(ed.shape[0]):
            grad = np.asarray(basis.basis[i][0].grad)  # (dim, dim, nel, nqp)
            vals[i] = np.sum(np.trace(grad, axis1=0, axis2=1) * dx, axis=1)
        nel = ed.shape[1]
        B = sp.csr_matrix((vals.ravel(), (np.tile(np.arange(nel), ed.shape[0]), ed.ravel())),
                          shape=(nel, model.ndofs))
        K = (K_dev + (lam + c) * (B.T @ sp.diags(1.0 / vol) @ B)).tocsr()
        K = (0.5 * (K + K.T)).tocsr()  # remove round-off asymmetry
        K.sum_duplicates()
        return K

    def isotropic_stress(self, model: LinearElasticity, tr: np.ndarray, dx: np.ndarray) -> np.ndarray:
        r""":math:`\kappa\,\Pi_0\operatorname{tr}\varepsilon - c\operatorname{tr}\varepsilon` at quadrature points."""
        c = 2.0 * model.mu / 3.0
        mean = np.sum(tr * dx, axis=-1, keepdims=True) / np.sum(dx, axis=-1, keepdims=True)
        return (model.lam + c) * mean - c * tr


#: Discretizations of the volumetric term, by name (``LinearElasticity(volumetric=...)``).
VOLUMETRIC_FORMULATIONS = {f.name: f for f in (_FullVolumetric(), _ProjectedP0Volumetric())}


def _axisymmetric_stiffness(model: LinearElasticity) -> sp.csr_matrix:
    r"""Stiffness of a body of revolution (``geometry="axisymmetric"``, :mod:`alcontact.fem._geometry`).

    .. math::
        a(u, v) = \int_\Omega \left[2\mu\,\varepsilon(u):\varepsilon(v) + \lambda\,
        \operatorname{tr}\varepsilon(u)\,\operatorname{tr}\varepsilon(v)\right] 2\pi r\,dr\,dz,
        \qquad \varepsilon_{\theta\theta} = u_r / r,

    with the hoop strain in the double contraction and in the trace. The integrand is rational
    in r (the hoop terms :math:`u_r v_r / r`): the quadrature (degree ``2 order``, at least the
    default) has interior points only, so it never evaluates :math:`1/r` on the axis.
    """
    lam, mu = model.lam, model.mu

    @BilinearForm
    def axi(u, v, w):
        r = w.x[0]
        eu, ev = sym_grad(u), sym_grad(v)
        hu, hv = u[0] / r, v[0] / r
        tu, tv = trace(eu) + hu, trace(ev) + hv
        return TWO_PI * r * (2.0 * mu * (ddot(eu, ev) + hu * hv) + lam * tu * tv)

    K = asm(axi, model.basis).tocsr()
    K = (0.5 * (K + K.T)).tocsr()  # remove round-off asymmetry
    K.sum_duplicates()
    K.sort_indices()
    return K


def _stiffness_basis(model: LinearElasticity) -> Basis:
    # strains are of degree order-1 on affine simplices: intorder 2(order-1) is exact (curved: 4 or 5)
    return Basis(model.mesh, model.element, intorder=default_intorder(model.mesh, model.order))


class LinearElasticity:
    r"""Linear elastic body discretized with vector P1 or P2 Lagrange elements.

    Parameters
    ----------
    mesh : skfem.MeshTri, skfem.MeshTet, skfem.MeshTri2 or skfem.MeshTet2
        Mesh with named boundaries (``mesh.boundaries``), e.g. from
        :mod:`alcontact.fem.meshes`. A second-order mesh (``MeshTri2``/``MeshTet2``,
        e.g. a Gmsh ``triangle6``/``tetra10`` file) is curved: with ``order=2`` the
        body uses its isoparametric map (edge nodes on the true boundary); with
        ``order=1`` only its vertices are used (straight elements).
    material : Material
        Elastic constants.
    order : {1, 2}
        Polynomial degree.
    volumetric : {"full", "p0"}
        Discretization of the volumetric term (:data:`VOLUMETRIC_FORMULATIONS`):
        ``"full"`` (default) the standard displacement element; ``"p0"`` (P2 only)
        the volumetric strain projected onto element-wise constants, the
        locking-free P2-P0 element with the pressure condensed element by element
        (still symmetric positive definite): use it for :math:`\nu` near 1/2.
    geometry : {"cartesian", "axisymmetric"}
        ``"axisymmetric"``: a 2D mesh in the r-z half-plane (``x = r >= 0``) is a body of
        revolution (:mod:`alcontact.fem._geometry`): the hoop strain :math:`u_r/r` enters the
        energy, every integral carries :math:`2\pi r` (stiffness, loads, boundary weights: forces
        are totals over the revolution), and :math:`u_r = 0` on the axis (:attr:`axis_dofs`).
    checked_mesh : bool
        The mesh is a piece of a mesh whose quality was checked already (a rank's elements of
        the distributed path): the element-quality check (inverted or degenerate elements)
        is not run again. Default False.

    Examples
    --------
    >>> from alcontact.fem import Material, LinearElasticity, meshes
    >>> model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 4, 4), Material(E=1.0, nu=0.3))
    >>> bc = [model.dirichlet("left", components=[0]), model.dirichlet("bottom", components=[1])]
    >>> u = model.solve(model.traction_load("right", [1.0, 0.0]), dirichlet=bc)
    >>> float(model.stress(u)[:, 0].round(8).min())
    1.0
    """

    def __init__(self, mesh, material: Material, order: int = 1, volumetric: str = "full",
                 geometry: str = "cartesian", *, checked_mesh: bool = False):
        if not isinstance(material, Material):
            raise InputError(f"material must be an alcontact.fem.Material; got {type(material).__name__}.")
        if not (isinstance(order, (int, np.integer)) and not isinstance(order, bool) and order in (1, 2)):
            raise InputError(f"order={show(order)} is not supported; use 1 (P1) or 2 (P2).")
        form = VOLUMETRIC_FORMULATIONS.get(volumetric) if isinstance(volumetric, str) else None
        if form is None:
            raise InputError(f"volumetric={show(volumetric)} is not known; use one of "
                             f"{', '.join(map(repr, VOLUMETRIC_FORMULATIONS))}.")
        if order not in form.orders:
            raise InputError(f"volumetric={volumetric!r} needs order in {form.orders}; got order={order!r}. "
                             "P1-P0 is not inf-sup stable (it locks like P1): use order=2 with 'p0', or "
                             "volumetric='full'.")
        if is_curved(mesh) and order == 1:  # P1 sees the vertices only: the straight-sided mesh
            mesh = straight_mesh(mesh)
        key = (type(mesh), order)
        if key not in _ELEMENTS:
            raise MeshError(
                f"LinearElasticity needs a triangle (MeshTri, MeshTri2) or tetrahedron (MeshTet, MeshTet2) "
                f"mesh; got {type(mesh).__name__}. Build it with alcontact.fem.meshes or read a Gmsh file "
                "with triangles/tetrahedra (first or second order)."
            )
        if not checked_mesh:
            check_mesh_quality(mesh)  # MeshError naming inverted or degenerate elements
        self.geometry = check_geometry(geometry, mesh.dim(), mesh.p, plane=material.plane)
        if self.geometry == AXISYMMETRIC and volumetric != "full":
            raise InputError(f"volumetric={volumetric!r} is not available with geometry='axisymmetric'; use "
                             "volumetric='full' (P2 for nu near 0.5).")
        self.mesh = mesh
        self.material = material
        self.order = int(order)
        self.volumetric = volumetric
        self._volumetric = form
        self.dim = int(mesh.dim())
        self.scalar_element = _ELEMENTS[key]()
        self.element = ElementVector(self.scalar_element)
        # DOF numbering only (no quadrature): the bases with their basis-function values at every
        # quadrature point of every element are built on first use (:attr:`basis`, :attr:`scalar_basis`)
        self.scalar_dofs = Dofs(mesh, self.scalar_element)
        self.ndofs = self.dim * int(self.scalar_dofs.N)
        # axisymmetric: the 3D constants (the hoop direction is a third, strained direction)
        self.lam, self.mu = material.lame(3 if self.geometry == AXISYMMETRIC else self.dim)
        self._stiffness: sp.csr_matrix | None = None
        self._facet_cache: dict[str, Any] = {}

    # ------------------------------------------------------------------ DOFs
    @cached_property
    def basis(self) -> Basis:
        """Vector basis (built on first use: it holds every basis function at every quadrature point)."""
        if self.geometry == AXISYMMETRIC:  # the hoop terms are rational in r: one degree more
            return Basis(self.mesh, self.element, intorder=max(default_intorder(self.mesh, self.order),
                                                                2 * self.order))
        return Basis(self.mesh, self.element)

    @property
    def axisymmetric(self) -> bool:
        """``True`` for a body of revolution (``geometry="axisymmetric"``)."""
        return self.geometry == AXISYMMETRIC

    @cached_property
    def axis_dofs(self) -> np.ndarray:
        """Radial DOFs on the axis ``r = 0`` of an axisymmetric body (:math:`u_r = 0` there); empty otherwise.

        Every solve prescribes them to zero (:func:`alcontact.contact.merge_supports`), whatever the supports.
        """
        if self.geometry != AXISYMMETRIC:
            return np.empty(0, dtype=np.int64)
        r = self.scalar_doflocs[0]
        on = axis_points(r, float(np.ptp(self.mesh.p, axis=1).max()))
        return np.sort(self.dof_map[on, 0])

    def _weight(self, x: np.ndarray):
        r"""The measure's weight at points ``x`` (dim, ...): :math:`2\pi r` (axisymmetric) or 1."""
        return TWO_PI * x[0] if self.geometry == AXISYMMETRIC else 1.0

    @cached_property
    def scalar_basis(self) -> Basis:
        """Scalar basis (built on first use; same numbering as :attr:`scalar_dofs`)."""
        return Basis(self.mesh, self.scalar_element, dofs=self.scalar_dofs)

    @cached_property
    def scalar_doflocs(self) -> np.ndarray:
        """``(dim, n_scalar)`` locations of the scalar DOFs (vertices, then midpoints), from the mesh alone."""
        return scalar_doflocs(self.mesh, self.order)

    @cached_property
    def dof_map(self) -> np.ndarray:
        """``(n_scalar, dim)`` int array: vector DOF of each component at each scalar DOF."""
        sed = self.scalar_dofs.element_dofs
        ved = Dofs(self.mesh, self.element).element_dofs
        out = np.empty((self.scalar_dofs.N, self.dim), dtype=np.int64)
        for c in range(self.dim):  # ElementVector: local dof i -> scalar i // dim, component i % dim
            out[sed.ravel(), c] = ved[c :: self.dim].ravel()
        return out

    @property
    def boundary_names(self) -> list[str]:
        """Names of the boundaries of the mesh."""
        return sorted((self.mesh.boundaries or {}).keys())

    def facets(self, name: str) -> np.ndarray:
        """Facet indices of boundary ``name``.

        Raises
        ------
        alcontact.errors.MeshError
            If the mesh has no boundary of that name.
        """
        bnd = self.mesh.boundaries or {}
        if name not in bnd:
            known = ", ".join(self.boundary_names) or "(none)"
            raise MeshError(f"boundary {name!r} not found; known: {known}.")
        return np.asarray(bnd[name], dtype=np.int64)

    def node_dofs(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """DOF locations on boundary ``name`` and their vector DOFs.

        Returns
        -------
        points : numpy.ndarray, shape (m, dim)
            Vertices (and edge midpoints for P2) on the boundary, sorted by scalar DOF.
        dofs : numpy.ndarray of int, shape (m, dim)
            ``dofs[i, c]`` is the global DOF of component ``c`` at ``points[i]``.
        """
        sdofs = self._boundary_scalar_dofs(name)
        return self.scalar_doflocs[:, sdofs].T.copy(), self.dof_map[sdofs]

    def probe(self, points: np.ndarray, *, tol: float = 1e-10) -> tuple[sp.csr_matrix, np.ndarray]:
        r"""Interpolation of scalar nodal fields at ``points`` of the reference configuration.

        Parameters
        ----------
        points : ndarray (n, dim)
        tol : float
            Barycentric tolerance of the point location (points on a face or an edge are inside).

        Returns
        -------
        P : scipy.sparse.csr_matrix (k, n_scalar)
            Rows of the ``k`` points inside the mesh: ``P @ v`` is the finite-element
            interpolant :math:`\sum_j v_j \phi_j(x)` of a scalar field ``v`` (one value per
            scalar DOF, :attr:`scalar_dofs`) at them.
        inside : ndarray of bool (n,)
            Which points lie in the mesh (the rows of ``P``, in order).

        Points are located on the straight-sided simplices (mesh vertices) among the 8 (then 32)
        elements with the nearest centroids; a point in none of them is outside.
        """
        from scipy.spatial import cKDTree

        x = np.asarray(points, dtype=float).reshape(-1, self.dim)
        p, t = self.mesh.p, self.mesh.t
        tree = getattr(self, "_centroid_tree", None)
        if tree is None:
            tree = self._centroid_tree = cKDTree(p[:, t].mean(axis=1).T)
        cells = -np.ones(x.shape[0], dtype=np.int64)
        for j, near in self._nearest_cells(tree, x, cells, t.shape[1]):
            todo = np.flatnonzero(cells < 0)
            c = near[todo, j]
            v0 = p[:, t[0, c]].T  # (k, d)
            A = np.stack([p[:, t[i + 1, c]].T - v0 for i in range(self.dim)], axis=-1)  # (k, d, d)
            lam = np.linalg.solve(A, (x[todo] - v0)[..., None])[..., 0]
            bary = np.concatenate([1.0 - lam.sum(axis=1, keepdims=True), lam], axis=1)
            ok = np.all(bary >= -tol, axis=1)
            cells[todo[ok]] = c[ok]
        inside = cells >= 0
        if not np.any(inside):
            return sp.csr_matrix((0, int(self.scalar_dofs.N))), inside
        # the rows of skfem's Basis.probes, on the cells located here (its own finder raises for a point
        # outside the mesh or on its boundary within round-off)
        basis = self.scalar_basis
        xi, ci = x[inside].T, cells[inside]
        loc = self._element_mapping.invF(xi[:, :, np.newaxis], tind=ci)
        phis = np.array([basis.elem.gbasis(basis.mapping, loc, k, tind=ci)[0] for k in range(basis.Nbfun)])
        rows = np.tile(np.arange(ci.size), basis.Nbfun)
        cols = basis.element_dofs[:, ci].ravel()
        P = sp.csr_matrix((phis.ravel(), (rows, cols)), shape=(ci.size, basis.N))
        return P, inside

    @staticmethod
    def _nearest_cells(tree, x, cells, ncells):
        """``(j, near)``: the ``j``-th nearest cell (by centroid) of every point, the first 8, then the next 24
        for the points :meth:`probe` has not located yet (``cells < 0``; slender elements)."""
        done = 0
        for k in (8, 32):
            k = min(k, ncells)
            if done >= k or not np.any(cells < 0):
                return
            _, near = tree.query(x, k=k)
            near = np.asarray(near).reshape(x.shape[0], -1)
            for j in range(done, k):
                if not np.any(cells < 0):
                    return
                yield j, near
            done = k

    def all_node_dofs(self) -> tuple[np.ndarray, np.ndarray]:
        """All scalar DOF locations ``(n_scalar, dim)`` and vector DOFs ``(n_scalar, dim)``."""
        return self.scalar_doflocs.T.copy(), self.dof_map.copy()

    def _boundary_scalar_dofs(self, name: str) -> np.ndarray:
        key = ("sdofs", name)
        if key not in self._facet_cache:
            f = self.facets(name)
            self._facet_cache[key] = np.unique(self.scalar_dofs.get_facet_dofs(f).flatten()).astype(np.int64)
        return self._facet_cache[key]

    @cached_property
    def _element_mapping(self):
        """The element map of the mesh, whose inverse the facet bases and probes use (:func:`~alcontact.fem.quality.element_mapping`)."""
        return element_mapping(self.mesh)

    def _facet_basis(self, name: str, *, vector: bool, intorder: int | None = None) -> FacetBasis:
        key = ("fb", name, vector, intorder)
        if key not in self._facet_cache:
            elem = self.element if vector else self.scalar_element
            kw = {} if intorder is None else {"intorder": intorder}
            self._facet_cache[key] = FacetBasis(self.mesh, elem, mapping=self._element_mapping, facets=self.facets(name),
                                                **kw)
        return self._facet_cache[key]

    def release_geometry(self) -> None:
        """Drop the cached facet bases and the mesh's element mapping (rebuilt on demand).

        Large solves call this once the contact points are set up: on a graded 3D mesh
        these caches hold about 620 bytes per DOF that the solve itself never reads.
        """
        for key in [k for k in self._facet_cache if isinstance(k, tuple) and k and k[0] == "fb"]:
            del self._facet_cache[key]
        if hasattr(self.mesh, "_cached_mapping"):  # scikit-fem's cache of Mesh.mapping()
            del self.mesh._cached_mapping
        self.__dict__.pop("_element_mapping", None)

    def boundary_weights(self, name: str) -> np.ndarray:
        r"""Tributary length/area of each DOF location of boundary ``name``.

        ``w_i = \int_\Gamma \phi_i\,ds`` (axisymmetric: :math:`\int_\Gamma \phi_i\,2\pi r\,ds`, the
        area of the surface of revolution), aligned with :meth:`node_dofs`. For 3D P2 that
        integral vanishes at vertices, so the weights of the P1 sub-triangulation
        of each quadratic face are returned instead (each face split into four;
        a vertex gets ``area/12``, an edge midpoint ``area/4`` per face). The
        weights always sum to the boundary measure.
        """
        sdofs = self._boundary_scalar_dofs(name)
        if self.dim == 3 and self.order == 2:
            f = self.facets(name)
            p = self.mesh.p
            v = self.mesh.facets[:, f]
            if is_curved(self.mesh):  # the area of the curved face (isoparametric map)
                fb = self._facet_basis(name, vector=False)
                area = np.asarray(fb.dx).sum(axis=1)
            else:
                area = 0.5 * np.linalg.norm(
                    np.cross((p[:, v[1]] - p[:, v[0]]).T, (p[:, v[2]] - p[:, v[0]]).T), axis=1
                )
            w = np.zeros(self.scalar_dofs.N)
            vdofs = self.scalar_dofs.nodal_dofs[0][v]  # (3, nf)
            edofs = self.scalar_dofs.edge_dofs[0][self.mesh.f2e[:, f]]  # (3, nf)
            np.add.at(w, vdofs.ravel(), np.tile(area / 12.0, 3))
            np.add.at(w, edofs.ravel(), np.tile(area / 4.0, 3))
            return w[sdofs]
        if self.axisymmetric and self.order == 2:
            return self._axisymmetric_p2_weights(name)[sdofs]

        weight = self._weight

        @LinearForm
        def one(v, w):
            return weight(w.x) * v

        return asm(one, self._facet_basis(name, vector=False))[sdofs]

    def _axisymmetric_p2_weights(self, name: str) -> np.ndarray:
        r"""P2 boundary weights of a body of revolution, on the P1 sub-segments of each edge.

        :math:`\int_\Gamma \phi_i\,2\pi r\,ds` vanishes at a P2 vertex on the axis (the vertex
        function times r integrates to zero), so, as for 3D P2, each edge (vertex, midpoint, vertex)
        is split into its two straight halves and every node gets the integral of the P1 hat
        functions there: a half from :math:`r_p` to :math:`r_q` of length L gives
        :math:`2\pi L (2r_p + r_q)/6` to p and :math:`2\pi L (r_p + 2r_q)/6` to q. They sum to the
        area of the revolved polygon through the nodes (exact on straight edges).
        """
        f = self.facets(name)
        x = self.scalar_doflocs
        vdofs = self.scalar_dofs.nodal_dofs[0][self.mesh.facets[:, f]]  # (2, nf)
        mdofs = self.scalar_dofs.facet_dofs[0][f]  # (nf,)
        w = np.zeros(self.scalar_dofs.N)
        for v in vdofs:
            L = np.linalg.norm(x[:, v] - x[:, mdofs], axis=0)
            rp, rq = x[0, v], x[0, mdofs]
            np.add.at(w, v, TWO_PI * L * (2.0 * rp + rq) / 6.0)
            np.add.at(w, mdofs, TWO_PI * L * (rp + 2.0 * rq) / 6.0)
        return w

    def boundary_pressure(self, name: str, forces) -> np.ndarray:
        r"""Pressure at the DOF locations of boundary ``name`` from nodal normal forces.

        ``forces`` aligned with :meth:`node_dofs`. The forces of a pressure field ``p``
        are :math:`\int_\Gamma p\,\phi_i`, so normally ``forces / boundary_weights``.
        For 3D P2 (and axisymmetric P2 on the axis) the vertex integrals vanish and the sub-triangle weights are not
        consistent (a uniform pressure would read 0 at vertices, 4/3 p at edge
        midpoints), so the boundary mass matrix is solved instead, :math:`M_\Gamma p = r`.
        """
        forces = np.asarray(forces, dtype=float)
        if not (self.order == 2 and (self.dim == 3 or self.axisymmetric)):
            return forces / self.boundary_weights(name)
        from scipy.sparse.linalg import spsolve

        weight = self._weight

        @BilinearForm
        def mass(u, v, w):
            return weight(w.x) * u * v

        sdofs = self._boundary_scalar_dofs(name)
        M = asm(mass, self._facet_basis(name, vector=False)).tocsr()[sdofs][:, sdofs]
        return spsolve(M.tocsc(), forces)

    def boundary_field_at_quadrature(self, name: str, values, *, near=None, intorder: int = 16):
        r"""A scalar field of the boundary space at the quadrature points of boundary ``name``.

        Parameters
        ----------
        name : str
            Boundary name.
        values : array_like (m,)
            Nodal values aligned with :meth:`node_dofs` (e.g. :meth:`boundary_pressure`).
        near : array_like of bool (m,), optional
            Keep only the facets with at least one of these points (default: all).
        intorder : int
            Quadrature order (high by default: integrands such as a Hertz profile
            :math:`\sqrt{1 - r^2/a^2}` have a square-root edge).

        Returns
        -------
        x : ndarray (nq, dim)
            Quadrature points.
        dx : ndarray (nq,)
            Quadrature weights (facet measure included): :math:`\int_\Gamma f\,ds \approx \sum_q dx_q f(x_q)`
            (axisymmetric: the :math:`2\pi r` of the surface of revolution included).
        v : ndarray (nq,)
            The field :math:`\sum_i v_i \phi_i` at the points.
        """
        sdofs = self._boundary_scalar_dofs(name)
        f = self.facets(name)
        if near is not None:
            mark = np.zeros(self.scalar_dofs.N, dtype=bool)
            mark[sdofs[np.asarray(near, dtype=bool)]] = True
            facet_dofs = np.asarray(self._facet_basis(name, vector=False).element_dofs)  # (nloc, nf)
            f = f[np.any(mark[facet_dofs], axis=0)]
        fb = FacetBasis(self.mesh, self.scalar_element, mapping=self._element_mapping, facets=f, intorder=intorder)
        full = np.zeros(self.scalar_dofs.N)
        full[sdofs] = np.asarray(values, dtype=float)
        val = np.asarray(fb.interpolate(full))  # (nf, nqp)
        xq = np.asarray(fb.global_coordinates())
        x = xq.reshape(self.dim, -1).T
        dx = (np.broadcast_to(np.asarray(fb.dx), val.shape) * self._weight(xq)).ravel()
        return x, dx, val.ravel()

    # ---------------------------------------------------------------- matrices
    def stiffness(self) -> sp.csr_matrix:
        """Global stiffness matrix (``ndofs x ndofs``, symmetric, cached; see ``volumetric``).

        The standard element is assembled in chunks of elements straight into its block
        sparsity pattern (:func:`alcontact.fem._assembly.elasticity_stiffness`): peak memory
        about twice the matrix, no per-element dense intermediates of the whole mesh.
        """
        if self._stiffness is None:
            t0 = time.perf_counter()
            if self.geometry == AXISYMMETRIC:
                K = _axisymmetric_stiffness(self)
            else:
                K = self._volumetric.stiffness(self).tocsr()
            K.eliminate_zeros()
            self._stiffness = K
            logger.debug("assembled stiffness (%s volumetric term): %d DOFs, nnz=%d in %.3f s",
                         self.volumetric, self.ndofs, K.nnz, time.perf_counter() - t0)
        return self._stiffness

    def clear_stiffness(self) -> None:
        """Drop the cached :meth:`stiffness` (frees its memory; the next call assembles it again).

        A cached factorization of that matrix is dropped too (its cache compares the matrix object).
        """
        if self._factor_cache is not None and self._factor_cache[0] is self._stiffness:
            self._factor_cache = None
        self._stiffness = None

    @cached_property
    def _mass_scalar(self) -> sp.csr_matrix:
        @BilinearForm
        def m(u, v, w):
            return u * v

        return asm(m, self.scalar_basis).tocsr()

    # ------------------------------------------------------------------ loads
    def _vector_field(self, value, x: np.ndarray, what: str) -> np.ndarray:
        if callable(value):
            out = np.asarray(value(x), dtype=float)
            if out.shape[0] != self.dim:
                raise InputError(f"{what} callable must return an array of shape ({self.dim}, ...); got {out.shape}.")
            return np.broadcast_to(out, x.shape)
        vec = _floats(value, what).ravel()
        if vec.shape != (self.dim,) or not np.all(np.isfinite(vec)):
            raise InputError(f"{what} must be {self.dim} finite numbers or a callable; got {value!r}.")
        return np.broadcast_to(vec.reshape((self.dim,) + (1,) * (x.ndim - 1)), x.shape)

    def traction_load(self, name: str, traction) -> np.ndarray:
        r"""Load vector :math:`\int_{\Gamma} t\cdot v\,ds` on boundary ``name`` (axisymmetric: times :math:`2\pi r`).

        Parameters
        ----------
        name : str
            Boundary name.
        traction : array_like of length dim, or callable
            Constant traction, or ``x -> (dim, ...)`` evaluated at the quadrature
            points ``x`` of shape ``(dim, n_facets, n_qp)``.
        """
        fb = self._facet_basis(name, vector=True, intorder=None if not callable(traction) else 2 * self.order + 2)
        t = self._vector_field(traction, np.asarray(fb.global_coordinates()), "traction")
        weight = self._weight

        @LinearForm
        def form(v, w):
            return weight(w.x) * dot(w.t, v)

        return asm(form, fb, t=np.ascontiguousarray(t))

    def pressure_load(self, name: str, p) -> np.ndarray:
        r"""Load of a pressure: traction :math:`-p\,n` with :math:`n` the outward normal.

        ``p > 0`` pushes into the body. ``p`` is a number or a callable
        ``x -> (n_facets, n_qp)``.
        """
        fb = self._facet_basis(name, vector=True, intorder=None if not callable(p) else 2 * self.order + 2)
        x = np.asarray(fb.global_coordinates())
        if callable(p):
            pv = np.broadcast_to(np.asarray(p(x), dtype=float), x.shape[1:])
        else:
            pf = _floats(p, "pressure")
            if pf.ndim != 0 or not np.isfinite(pf):
                raise InputError(f"pressure must be a finite number or a callable; got {show(p)}.")
            pv = np.full(x.shape[1:], float(pf))

        weight = self._weight

        @LinearForm
        def form(v, w):
            return -weight(w.x) * w.p * dot(w.n, v)

        return asm(form, fb, p=np.ascontiguousarray(pv))

    def body_load(self, f) -> np.ndarray:
        r"""Load vector :math:`\int_\Omega f\cdot v\,dx` (constant vector or callable ``x -> (dim, ...)``;
        axisymmetric: times :math:`2\pi r`)."""
        basis = self.basis
        fv = self._vector_field(f, np.asarray(basis.global_coordinates()), "body force")
        weight = self._weight

        @LinearForm
        def form(v, w):
            return weight(w.x) * dot(w.f, v)

        return asm(form, basis, f=np.ascontiguousarray(fv))

    # ------------------------------------------------------------ constraints
    def dirichlet(self, name: str, components: Sequence[int] | None = None, value: Any = 0.0):
        """Prescribed DOFs and values on boundary ``name``.

        Parameters
        ----------
        name : str
            Boundary name.
        components : sequence of int, optional
            Displacement components to fix (default all).
        value : float, array_like of length dim, or callable
            Prescribed value; a callable gets ``x`` of shape ``(dim, m)`` (the
            DOF locations) and returns ``(dim, m)``.

        Returns
        -------
        dofs : numpy.ndarray of int
        values : numpy.ndarray of float
            Same length, node-major (all chosen components of node 0, then node 1, ...).
        """
        points, dofs = self.node_dofs(name)
        comps = list(range(self.dim)) if components is None else [int(c) for c in components]
        bad = [c for c in comps if not 0 <= c < self.dim]
        if bad or len(set(comps)) != len(comps):
            raise InputError(f"components {components!r} invalid; use distinct indices in 0..{self.dim - 1}.")
        m = points.shape[0]
        if callable(value):
            vals = np.asarray(value(points.T), dtype=float)
            if vals.shape != (self.dim, m):
                raise InputError(f"Dirichlet value callable must return shape ({self.dim}, {m}); got {vals.shape}.")
            vals = vals.T
        else:
            arr = _floats(value, "Dirichlet value")
            if arr.ndim == 0:
                vals = np.full((m, self.dim), float(arr))
            elif arr.shape == (self.dim,):
                vals = np.tile(arr, (m, 1))
            else:
                raise InputError(f"Dirichlet value must be a number, {self.dim} numbers or a callable; got {value!r}.")
        if not np.all(np.isfinite(vals)):
            raise InputError(f"Dirichlet values on {name!r} contain NaN or infinity.")
        if self.geometry == AXISYMMETRIC and 0 in comps:
            on = np.isin(dofs[:, 0], self.axis_dofs)
            bad = on & (np.abs(vals[:, 0]) > 0.0)
            if np.any(bad):
                i = int(np.flatnonzero(bad)[0])
                raise InputError(f"support on {name!r}: radial displacement u_r = {vals[i, 0]:g} prescribed on the "
                                 f"axis (node at r = 0, z = {points[i, 1]:g}); a body of revolution has u_r = 0 on "
                                 "its axis (imposed automatically). Prescribe component 0 = 0 there, or leave it "
                                 "free (components = [1]).")
        return dofs[:, comps].ravel().copy(), vals[:, comps].ravel().copy()

    def _collect_fixed(self, dirichlet) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`_collect` plus :math:`u_r = 0` on the axis of a body of revolution (:attr:`axis_dofs`)."""
        dofs, vals = self._collect(dirichlet)
        axis = np.setdiff1d(self.axis_dofs, dofs)
        if axis.size == 0:
            return dofs, vals
        out = np.concatenate([dofs, axis])
        order = np.argsort(out)
        return out[order], np.concatenate([vals, np.zeros(axis.size)])[order]

    @staticmethod
    def _collect(dirichlet) -> tuple[np.ndarray, np.ndarray]:
        if dirichlet is None:
            return np.empty(0, dtype=np.int64), np.empty(0)
        if (isinstance(dirichlet, tuple) and len(dirichlet) == 2
                and isinstance(dirichlet[0], np.ndarray) and dirichlet[0].ndim == 1):
            dirichlet = [dirichlet]  # a single (dofs, values) pair
        dofs = [np.asarray(d, dtype=np.int64).ravel() for d, _ in dirichlet]
        vals = [np.broadcast_to(np.asarray(v, dtype=float), np.shape(d)).ravel()
                for (_, v), d in zip(dirichlet, dofs)]
        dofs_all = np.concatenate(dofs) if dofs else np.empty(0, dtype=np.int64)
        vals_all = np.concatenate(vals) if vals else np.empty(0)
        # the last prescription of a DOF wins
        uniq, idx = np.unique(dofs_all[::-1], return_index=True)
        return uniq, vals_all[::-1][idx]

    def free_rigid_motions(self, dirichlet_dofs) -> tuple[np.ndarray, list[str], np.ndarray, np.ndarray]:
        """Rigid motions the fixed DOFs leave free: ``(null, names, R, row_of)``.

        ``null`` ``(k, n_modes)``: coefficient vectors of the free motions in the basis of
        :func:`rigid_body_modes` (named ``names``), in echelon form (each free motion led
        by one named mode; ``k = 0`` when the supports stop every rigid motion); ``R``
        ``(n_scalar dim, n_modes)`` the modes at every DOF, row ``row_of[dof]`` for a
        vector DOF.
        """
        fixed = np.unique(np.asarray(dirichlet_dofs, dtype=np.int64).ravel())
        pts, _ = self.all_node_dofs()
        modes, names = self._rigid_modes(pts)
        R = modes.reshape(-1, modes.shape[-1])  # (n_scalar*dim, n_modes), row = scalar*dim + c
        # map vector DOF -> row of R
        row_of = np.empty(self.ndofs, dtype=np.int64)
        row_of[self.dof_map.ravel()] = np.arange(self.dof_map.size)
        nm = R.shape[1]
        Rf = R[row_of[fixed]]
        if Rf.shape[0] < nm:  # pad so that the thin SVD returns all nm singular values
            Rf = np.vstack([Rf, np.zeros((nm - Rf.shape[0], nm))])
        _, s, vt = np.linalg.svd(Rf, full_matrices=False)
        null = vt[s <= 1e-9 * s[0]] if s[0] > 0 else vt
        if null.shape[0]:
            null = _rref(null)  # echelon form: each free motion led by one named mode
        return null, names, R, row_of

    def check_restrained(self, dirichlet_dofs, *, path: str | None = None, alternative: str | None = None,
                         contact: str | None = None) -> None:
        """Raise :class:`InputError` if the fixed DOFs leave a rigid-body motion free.

        The check is exact for connected meshes: a rigid motion ``r`` is free iff
        ``r`` vanishes on every fixed DOF.

        Parameters
        ----------
        dirichlet_dofs : array_like of int
            Fixed DOFs.
        path : str, optional
            The solver path that needs the supports (e.g. ``"The AMG path"``); the
            message then says that this path cannot let the obstacle hold the body.
        alternative : str, optional
            A path that would work, appended to the way out.
        contact : str, optional
            The contact boundary (suggested last for a support).

        Raises
        ------
        InputError
            Naming the free motions and supports that stop them, both as
            ``Support(boundary, components=[c])`` (Python) and as ``[[support]]``
            (problem file).
        """
        null, names, R, row_of = self.free_rigid_motions(dirichlet_dofs)
        if null.shape[0] == 0:
            return
        free = describe_motions(null, names)
        hint = self._support_hint(null, R, row_of, contact)
        if path is None:
            msg = (f"the stiffness matrix is singular with these supports: rigid-body motion(s) not stopped: "
                   f"{free}. {hint}.")
        else:
            msg = (f"rigid-body motion(s) not stopped by the supports: {free}. {path} needs supports that stop "
                   "every rigid motion: it cannot let the obstacle hold the body (the stiffness matrix would be "
                   f"singular). {hint}")
            msg += f"; or {alternative}." if alternative else "."
        raise InputError(msg)

    def _support_hint(self, null: np.ndarray | None = None, R: np.ndarray | None = None,
                      row_of: np.ndarray | None = None, contact: str | None = None) -> str:
        """Supports that stop the free motions ``null`` (rows: coefficients of the rigid modes ``R``).

        Chooses greedily, boundary by boundary and component by component, the
        support that stops the most free motions not yet stopped (the contact
        boundary last), and writes it for Python and for problem files.
        """
        names = sorted(self.boundary_names, key=lambda b: (b == contact, b))
        generic = ("Fix displacement components on some boundary (Python: Support(boundary, components=[c]) in "
                   "ContactProblem(supports=...), or model.dirichlet(boundary, components=[c]); problem file: "
                   "[[support]] boundary = ..., components = [c]) until every rigid motion is stopped")
        if not names or null is None or R is None or row_of is None:
            return generic
        k = null.shape[0]
        blocks = {}
        for b in names:
            _, dofs = self.node_dofs(b)
            for c in range(self.dim):
                blocks[(b, c)] = R[row_of[dofs[:, c]]] @ null.T  # motions seen by component c on b
        chosen: list[tuple[str, int]] = []
        rows = np.zeros((0, k))
        rank = 0
        while rank < k:
            best = None
            for key, blk in blocks.items():
                if key in chosen:
                    continue
                r = _rank(np.vstack([rows, blk]))
                if best is None or r > best[0]:
                    best = (r, key)
            if best is None or best[0] <= rank:
                break
            rank = best[0]
            chosen.append(best[1])
            rows = np.vstack([rows, blocks[best[1]]])
        if rank < k:
            return generic
        per: dict[str, list[int]] = {}
        for b, c in chosen:
            per.setdefault(b, []).append(c)
        per = {b: sorted(cs) for b, cs in per.items()}
        py = ", ".join(f"Support({b!r}, components={cs})" for b, cs in per.items())
        toml = " and ".join(f"[[support]] boundary = {b!r}, components = {cs}" for b, cs in per.items())
        what = "; ".join(f"{', '.join(_AXES[c] for c in cs)} on {b!r}" for b, cs in per.items())
        return (f"Add {'a support that stops' if len(per) == 1 else 'supports that stop'} "
                f"{'it' if k == 1 else 'them'} (fixes {what}): in Python {py} in ContactProblem(supports=...), "
                f"in a problem file {toml}")

    # ----------------------------------------------------------------- solving
    @cached_property
    def node_graph(self) -> sp.csr_matrix:
        """Scalar-DOF adjacency (two DOFs are adjacent if they share an element)."""
        ed = self.scalar_dofs.element_dofs
        nel = ed.shape[1]
        B = sp.csr_matrix(
            (np.ones(ed.size), (np.repeat(np.arange(nel), ed.shape[0]), ed.T.ravel())),
            shape=(nel, self.scalar_dofs.N),
        )
        return (B.T @ B).tocsr()

    def ordering(self, free: np.ndarray) -> np.ndarray:
        """Nested-dissection ordering of the free DOFs (``perm[new] = position in free``)."""
        pts, dofs = self.all_node_dofs()
        nodes = nested_dissection(pts, self.node_graph)
        pos = np.full(self.ndofs, -1, dtype=np.int64)
        pos[free] = np.arange(free.size)
        p = pos[dofs[nodes].ravel()]
        return p[p >= 0]

    #: factorizations computed by :meth:`factorize` (reused ones are not counted)
    factorization_count = 0
    _factor_cache: tuple | None = None

    def factorize(self, dirichlet_dofs, *, matrix=None, ordering: str = "auto", check: bool = True,
                  backend: str = "auto", reuse: bool = True, schur=None) -> Factorization:
        """Factorize the stiffness condensed on the free DOFs (one factorization, many solves).

        The last factorization is kept on the model and returned again when the same
        matrix object (by identity: the cached :meth:`stiffness` by default) is condensed
        on the same set of fixed DOFs with the same solver options: load steps of a
        frictionless run (:func:`~alcontact.contact.problem_at` keeps the model) then
        factorize once. Prescribed *values* may change; they only enter the right-hand
        side (:meth:`Factorization.rhs`).

        Parameters
        ----------
        dirichlet_dofs : array_like of int
            Fixed DOFs.
        matrix : scipy.sparse matrix, optional
            Use this matrix (same DOF numbering and sparsity within the element
            graph, e.g. stiffness plus a penalty term) instead of :meth:`stiffness`;
            the rigid-motion check is then skipped. Do not modify it in place after
            factorizing (the cache compares the object, not its values).
        ordering : {"auto", "nd", "MMD_AT_PLUS_A", "COLAMD", "MMD_ATA", "NATURAL"}
            Fill-reducing ordering of the ``"superlu"`` backend: ``"nd"`` is
            :func:`nested_dissection` on the mesh graph; ``"auto"`` uses it in 3D and
            SuperLU's ``MMD_AT_PLUS_A`` in 2D. The other solvers order the matrix themselves.
        check : bool
            Check that rigid motions are restrained and that the factor is not singular.
        backend : str
            ``"auto"`` (:func:`alcontact.linalg.choose_solver` among the direct solvers:
            MKL PARDISO when installed, else CHOLMOD, else SuperLU) or a name of
            :func:`alcontact.linalg.registered_solvers` (``"amg"`` gives an approximate
            factor whose solves run preconditioned CG).
        reuse : bool
            Return the cached factorization when it matches (see above).
        schur : array_like of int, optional
            Free DOFs (global numbering) to eliminate last: a solver with a Schur
            facility returns their Schur complement on the factor (see
            :class:`alcontact.linalg.MatrixHints`); the others ignore it.

        Returns
        -------
        Factorization
            ``.solve(r)`` solves ``K_ff x = r``; see :class:`Factorization`.
        """
        from alcontact.linalg import choose_solver, registered_solvers

        if matrix is None:
            if check:
                self.check_restrained(dirichlet_dofs)
            matrix = self.stiffness()
        known = ("auto", "nd", "MMD_AT_PLUS_A", "COLAMD", "MMD_ATA", "NATURAL")
        if ordering not in known:
            raise InputError(f"ordering={ordering!r} is not known; use one of {', '.join(known)}.")
        names = registered_solvers()
        if backend != "auto" and backend not in names:
            raise InputError(f"backend={backend!r} is not a registered linear solver; use 'auto' or one of "
                             f"{', '.join(names)} (alcontact.linalg.register_solver adds others).")
        if backend == "auto":
            backend = choose_solver(self.dim, self.ndofs, allow_iterative=False)
        fixed = np.unique(np.asarray(dirichlet_dofs, dtype=np.int64).ravel())
        if ordering == "auto":
            ordering = "nd" if self.dim == 3 else "MMD_AT_PLUS_A"
        schur = None if schur is None else np.unique(np.asarray(schur, dtype=np.int64).ravel())
        key = (backend, ordering, bool(check), fixed.tobytes(), None if schur is None else schur.tobytes())
        cached = self._factor_cache
        if reuse and cached is not None and cached[0] is matrix and cached[1] == key:
            logger.debug("reusing the factorization of %d free DOFs (%s)", cached[2].free.size, backend)
            return cached[2]
        self._factor_cache = None  # free the old factor before building the new one
        mask = np.ones(self.ndofs, dtype=bool)
        mask[fixed] = False
        free = np.flatnonzero(mask)
        # the nested dissection and the rigid modes are computed only if the solver asks for them
        nd = ordering == "nd"
        if schur is not None:  # positions in the free numbering (fixed DOFs dropped)
            schur = np.searchsorted(free, schur[~np.isin(schur, fixed)])
        hints = MatrixHints(dim=self.dim, ordering=(lambda: self.ordering(free)) if nd else None,
                            near_null=lambda: self._free_rigid_modes(free), schur=schur)
        fac = Factorization(matrix, fixed, permc_spec="MMD_AT_PLUS_A" if nd else ordering, check=check,
                            backend=backend, hints=hints)
        self.factorization_count += 1
        if reuse:
            self._factor_cache = (matrix, key, fac)
        return fac

    def clear_factorization(self) -> None:
        """Drop the cached factorization of :meth:`factorize` (frees its memory)."""
        self._factor_cache = None

    def _rigid_modes(self, pts: np.ndarray) -> tuple[np.ndarray, list[str]]:
        """:func:`rigid_body_modes` of this geometry: a body of revolution keeps the translation along the axis only."""
        modes, names = rigid_body_modes(pts)
        if self.geometry == AXISYMMETRIC:  # u_r = const or a rotation would strain the hoop direction
            return modes[..., 1:2], ["translation along the axis (y)"]
        return modes, names

    def _free_rigid_modes(self, free: np.ndarray) -> np.ndarray:
        """Rigid-body modes restricted to the DOFs ``free`` (near-null space for AMG)."""
        pts, dofs = self.all_node_dofs()
        modes, _ = self._rigid_modes(pts)
        R = np.zeros((self.ndofs, modes.shape[-1]))
        R[dofs.ravel()] = modes.reshape(-1, modes.shape[-1])
        return np.ascontiguousarray(R[free])

    def solve(self, load, dirichlet=()) -> np.ndarray:
        """Solve ``K u = load`` with Dirichlet conditions.

        Parameters
        ----------
        load : numpy.ndarray, shape (ndofs,)
        dirichlet : list of (dofs, values)
            As returned by :meth:`dirichlet`; a DOF given twice takes the last value.

        Returns
        -------
        numpy.ndarray, shape (ndofs,)

        Raises
        ------
        alcontact.errors.InputError
            If the supports leave a rigid-body motion free (message says which).
        """
        load = np.asarray(load, dtype=float)
        if load.shape != (self.ndofs,):
            raise InputError(f"load must have shape ({self.ndofs},); got {load.shape}.")
        dofs, vals = self._collect_fixed(dirichlet)
        fac = self.factorize(dofs)
        return fac.solve_full(load, vals)

    # ------------------------------------------------- Body protocol (fem._body)
    #: the internal force is linear in u: the condensed contact path applies
    linear = True

    def internal_force(self, u) -> np.ndarray:
        """Internal force :math:`K u` of the :class:`~alcontact.fem._body.Body` protocol."""
        return self.stiffness() @ np.asarray(u, dtype=float)

    def tangent(self, u=None) -> sp.csr_matrix:
        """Tangent stiffness: the constant :math:`K` (``u`` is ignored)."""
        return self.stiffness()

    def energy(self, u) -> float:
        """Stored energy :math:`\\tfrac12 u^T K u` (same as :meth:`strain_energy`)."""
        return self.strain_energy(u)

    # ----------------------------------------------------------- postprocess
    def strain_energy(self, u) -> float:
        r""":math:`\tfrac12 u^T K u`."""
        u = np.asarray(u, dtype=float)
        return 0.5 * float(u @ (self.stiffness() @ u))

    def _quadrature_stress(self, u) -> list[np.ndarray]:
        """Stress components at quadrature points, Voigt order plus zz in 2D."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.ndofs,):
            raise InputError(f"u must have shape ({self.ndofs},); got {u.shape}.")
        field = self.basis.interpolate(u)
        G = field.grad  # (dim, dim, nel, nqp)
        eps = 0.5 * (G + np.swapaxes(G, 0, 1))
        tr = np.trace(eps, axis1=0, axis2=1)
        if self.geometry == AXISYMMETRIC:  # hoop strain u_r / r; "zz" is the hoop stress
            hoop = np.asarray(field)[0] / np.asarray(self.basis.global_coordinates())[0]
            iso = self.lam * (tr + hoop)
            s = 2.0 * self.mu * eps
            for i in range(self.dim):
                s[i, i] += iso
            return [s[0, 0], s[1, 1], s[0, 1], 2.0 * self.mu * hoop + iso]
        iso = self._volumetric.isotropic_stress(self, tr, np.broadcast_to(np.asarray(self.basis.dx), tr.shape))
        s = 2.0 * self.mu * eps
        for i in range(self.dim):
            s[i, i] += iso
        if self.dim == 2:
            szz = iso if self.material.plane == "strain" else np.zeros_like(tr)
            return [s[0, 0], s[1, 1], s[0, 1], szz]
        return [s[0, 0], s[1, 1], s[2, 2], s[1, 2], s[0, 2], s[0, 1]]

    def _project(self, fields: list[np.ndarray]) -> np.ndarray:
        """L2 projection of quadrature-point fields onto the scalar space."""

        @LinearForm
        def rhs(v, w):
            return w.s * v

        M = self._mass_scalar
        d = M.diagonal()
        precond = sp.diags(1.0 / d)
        out = np.empty((self.scalar_basis.N, len(fields)))
        for j, f in enumerate(fields):
            b = asm(rhs, self.scalar_basis, s=np.ascontiguousarray(f))
            x0 = b / M.sum(axis=1).A1 if self.order == 1 else b / d
            x, info = cg(M, b, x0=x0, M=precond, rtol=1e-13, atol=0.0, maxiter=2000)
            if info != 0:
                logger.warning("stress projection: CG did not converge (info=%d)", info)
            out[:, j] = x
        return out

    def stress(self, u, *, include_zz: bool = False) -> np.ndarray:
        r"""Nodal stresses by L2 projection onto the scalar P1/P2 space.

        Parameters
        ----------
        u : numpy.ndarray, shape (ndofs,)
        include_zz : bool
            2D only: append the out-of-plane stress ``zz`` as a 4th column
            (``lambda * tr(eps)`` in plane strain, zero in plane stress; axisymmetric: the
            hoop stress :math:`\sigma_{\theta\theta}`, and ``xx, yy, xy`` are ``rr, zz, rz``).

        Returns
        -------
        numpy.ndarray, shape (n_scalar, n_voigt)
            Rows aligned with :meth:`all_node_dofs`; columns ``xx, yy, xy`` (2D,
            plus ``zz`` if requested) or ``xx, yy, zz, yz, xz, xy`` (3D).
        """
        comps = self._quadrature_stress(u)
        if self.dim == 2 and not include_zz:
            comps = comps[:3]
        return self._project(comps)

    def von_mises(self, u) -> np.ndarray:
        """Nodal von Mises stress (plane strain includes ``zz``), shape ``(n_scalar,)``."""
        s = self.stress(u, include_zz=True)
        if self.dim == 2:
            sxx, syy, sxy, szz = s.T
            syz = sxz = 0.0
        else:
            sxx, syy, szz, syz, sxz, sxy = s.T
        j2 = 0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * (sxy**2 + syz**2 + sxz**2)
        return np.sqrt(np.maximum(j2, 0.0))

    def interpolate(self, fun: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """Nodal interpolant of ``fun: x (dim, m) -> (dim, m)`` as a DOF vector."""
        pts, dofs = self.all_node_dofs()
        vals = np.asarray(fun(pts.T), dtype=float)
        u = np.zeros(self.ndofs)
        u[dofs.T.ravel()] = vals.ravel()
        return u
