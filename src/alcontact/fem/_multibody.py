r"""Several bodies as one discretized body: stacked DOFs, block-diagonal stiffness (or tangent).

Two bodies in contact share no element: without contact their equilibrium equations
are independent, so the discrete system of several bodies is block diagonal,

.. math::

    K = \operatorname{diag}(K_1, \dots, K_n), \qquad u = (u_1, \dots, u_n),

with body ``b``'s DOFs at the offset ``offsets[b]``; for hyperelastic bodies (finite
deformation) the internal force is each body's :math:`f_{int}(u_b)` stacked and the tangent
:math:`\operatorname{diag}(K_{T,1}(u_1), \dots, K_{T,n}(u_n))` on one fixed block-diagonal
pattern (:attr:`MultiBody.tangent_pattern`). :class:`MultiBody` offers what one
:class:`~alcontact.fem.LinearElasticity` offers to the contact layer (boundaries, node DOFs,
boundary weights, supports, loads, the stiffness and its factorization), so that the contact
systems see one set of free DOFs and every algorithm runs unchanged; a contact constraint
between two bodies is a row of the gap operator ``B`` with entries on both bodies' DOFs.

Boundaries are named ``"<body>/<boundary>"`` (``"base/top"``), the body names given to
:class:`MultiBody` (default ``body0``, ``body1``, ...); a boundary name that exists in one body
only may be given without its body.
"""

from __future__ import annotations

import logging
from typing import Any, Sequence

import numpy as np
import scipy.sparse as sp

from alcontact.errors import InputError, MeshError
from alcontact.fem._linalg import Factorization
from alcontact.fem.elasticity import rigid_body_modes
from alcontact.linalg import MatrixHints

logger = logging.getLogger(__name__)

#: separator of a body name and a boundary name in the boundary names of a :class:`MultiBody`
SEP = "/"


def _csr_pattern(K) -> tuple[np.ndarray, np.ndarray]:
    """``(indptr, indices)`` of a canonical (sorted, no duplicates) CSR matrix."""
    K = K.tocsr()
    K.sum_duplicates()
    K.sort_indices()
    return K.indptr, K.indices


class MultiBody:
    r"""Several bodies solved together: DOFs stacked body after body.

    Parameters
    ----------
    bodies : sequence of alcontact.fem.LinearElasticity or alcontact.fem.Hyperelastic
        The bodies (same dimension; all linear, their stiffness constant, or all hyperelastic).
    names : sequence of str, optional
        One name per body (default ``body0``, ``body1``, ...); boundaries are named
        ``"<name>/<boundary>"``.

    Attributes
    ----------
    bodies : tuple
    names : tuple of str
    offsets : ndarray of int, shape (n + 1,)
        Body ``b`` owns the DOFs ``offsets[b] : offsets[b + 1]``.
    ndofs, dim : int

    Examples
    --------
    >>> from alcontact.fem import LinearElasticity, Material, meshes
    >>> a = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1.0, nu=0.3))
    >>> b = LinearElasticity(meshes.rectangle(0, 1, 1, 2, 3, 3), Material(E=2.0, nu=0.2))
    >>> both = MultiBody([a, b], names=["base", "block"])
    >>> both.ndofs == a.ndofs + b.ndofs, both.boundary_names[:2]
    (True, ['base/bottom', 'base/left'])
    """

    #: the internal force is linear in u when every body is linear (the condensed contact path applies);
    #: ``False`` for geometrically nonlinear (hyperelastic) bodies, solved at finite deformation
    linear = True

    def __init__(self, bodies: Sequence[Any], names: Sequence[str] | None = None):
        if isinstance(bodies, (str, bytes, dict, np.ndarray)) or not np.iterable(bodies):
            raise InputError(f"MultiBody: bodies = {type(bodies).__name__}: expected a list of bodies "
                             "(alcontact.fem.LinearElasticity).")
        bodies = tuple(bodies)
        if len(bodies) < 1:
            raise InputError("MultiBody: bodies = []: give at least one body.")
        for i, b in enumerate(bodies):
            if getattr(b, "linear", None) not in (True, False) or not hasattr(b, "stiffness") or not hasattr(b, "dim") \
                    or hasattr(b, "npressure") or not hasattr(b, "internal_force"):
                raise InputError(f"MultiBody: bodies[{i}] is a {type(b).__name__}: several bodies are solved "
                                 "together with linear elastic bodies (alcontact.fem.LinearElasticity, small "
                                 "deformation) or displacement-based hyperelastic ones (alcontact.fem.Hyperelastic, "
                                 "finite deformation).")
        kinds = {bool(b.linear) for b in bodies}
        if len(kinds) != 1:
            raise InputError("MultiBody: some bodies are linear (linear elastic or rigid) and others hyperelastic: "
                             "give bodies of one kind (LinearElasticity and rigid bodies for kinematics='small', "
                             "all Hyperelastic for kinematics='finite').")
        self.linear = kinds.pop()
        dims = {int(b.dim) for b in bodies}
        if len(dims) != 1:
            raise InputError(f"MultiBody: the bodies have different dimensions {sorted(dims)}: give bodies of "
                             "one dimension (all 2D or all 3D).")
        axi = {bool(getattr(b, "axisymmetric", False)) for b in bodies}
        if len(axi) != 1:
            raise InputError("MultiBody: some bodies are axisymmetric and others Cartesian: give bodies of one "
                             "geometry.")
        self.axisymmetric = axi.pop()
        if names is None:
            names = [f"body{i}" for i in range(len(bodies))]
        if isinstance(names, (str, bytes, dict)) or not np.iterable(names):
            raise InputError(f"MultiBody: names = {type(names).__name__}: expected a list of names, one per body.")
        names = tuple(names)
        if len(names) != len(bodies) or not all(isinstance(n, str) and n and SEP not in n for n in names):
            raise InputError(f"MultiBody: names = {list(names)!r:.80}: expected one non-empty name per body, "
                             f"without {SEP!r}.")
        if len(set(names)) != len(names):
            raise InputError(f"MultiBody: names = {list(names)!r}: two bodies have the same name; give each its "
                             "own.")
        self.bodies = bodies
        self.names = names
        self.dim = dims.pop()
        self.offsets = np.concatenate([[0], np.cumsum([b.ndofs for b in bodies])]).astype(np.int64)
        self.ndofs = int(self.offsets[-1])
        self._stiffness: sp.csr_matrix | None = None
        self._factor_cache: tuple | None = None
        self.factorization_count = 0

    # ------------------------------------------------------------ names and DOFs
    @property
    def material(self):
        """The material of the stiffest body (largest plane-strain modulus): the scale of penalty stiffnesses.

        Bodies without a material (a rigid body, :class:`alcontact.contact.RigidBody`) do not count."""
        return max((b.material for b in self.bodies if b.material is not None), key=lambda m: m.plane_strain_modulus)

    @property
    def boundary_names(self) -> list[str]:
        """``"<body>/<boundary>"`` for every boundary of every body."""
        return [f"{n}{SEP}{b}" for n, body in zip(self.names, self.bodies) for b in body.boundary_names]

    def qualify(self, body: Any, name: str) -> str:
        """The name of boundary ``name`` of ``body`` (one of :attr:`bodies`, by identity) here."""
        for n, b in zip(self.names, self.bodies):
            if b is body:
                return f"{n}{SEP}{name}"
        raise InputError(f"MultiBody: the body of boundary {name!r} is not one of the bodies {list(self.names)}.")

    def locate(self, name: str) -> tuple[int, str]:
        """``(body index, boundary name of that body)`` of a boundary name of this assembly.

        Raises
        ------
        alcontact.errors.MeshError
            No body has that boundary, or several have it and ``name`` does not say which.
        """
        if not isinstance(name, str):
            raise MeshError(f"boundary {name!r} is not a name; known: {', '.join(self.boundary_names)}.")
        if name in self.names and len(self.bodies[self.names.index(name)].boundary_names) == 1:
            i = self.names.index(name)  # a body of one boundary (a rigid body's reference point) by its name
            return i, self.bodies[i].boundary_names[0]
        if SEP in name:
            head, tail = name.split(SEP, 1)
            if head in self.names:
                i = self.names.index(head)
                if tail in self.bodies[i].boundary_names:
                    return i, tail
        owners = [i for i, b in enumerate(self.bodies) if name in b.boundary_names]
        if len(owners) == 1:
            return owners[0], name
        if len(owners) > 1:
            raise MeshError(f"boundary {name!r} exists in several bodies ({', '.join(self.names[i] for i in owners)}); "
                            f"name it with its body, e.g. {self.names[owners[0]]}{SEP}{name}.")
        raise MeshError(f"boundary {name!r} not found; known: {', '.join(self.boundary_names)}.")

    def facets(self, name: str) -> np.ndarray:
        """Facet indices (in its body's mesh) of boundary ``name``; a :class:`MeshError` naming the known ones."""
        i, local = self.locate(name)
        return self.bodies[i].facets(local)

    def node_dofs(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """DOF locations on boundary ``name`` and their DOFs in the stacked numbering."""
        i, local = self.locate(name)
        pts, dofs = self.bodies[i].node_dofs(local)
        return pts, dofs + self.offsets[i]

    def all_node_dofs(self) -> tuple[np.ndarray, np.ndarray]:
        """All DOF locations and vector DOFs (stacked numbering), body after body."""
        pts, dofs = zip(*(b.all_node_dofs() for b in self.bodies))
        return np.vstack(pts), np.vstack([d + o for d, o in zip(dofs, self.offsets[:-1])])

    def body_of_dofs(self) -> np.ndarray:
        """``(ndofs,)`` index of the body of every DOF."""
        return np.repeat(np.arange(len(self.bodies)), np.diff(self.offsets))

    def split(self, u: np.ndarray) -> list[np.ndarray]:
        """The displacement of each body from a stacked vector ``u`` (views)."""
        u = np.asarray(u)
        return [u[a:b] for a, b in zip(self.offsets[:-1], self.offsets[1:])]

    @property
    def axis_dofs(self) -> np.ndarray:
        """Radial DOFs on the axis of the bodies of revolution (stacked numbering)."""
        return np.concatenate([np.asarray(b.axis_dofs, dtype=np.int64) + o
                               for b, o in zip(self.bodies, self.offsets[:-1])])

    def boundary_weights(self, name: str) -> np.ndarray:
        """Tributary length/area of each DOF location of boundary ``name`` (its body's)."""
        i, local = self.locate(name)
        return self.bodies[i].boundary_weights(local)

    def boundary_pressure(self, name: str, forces) -> np.ndarray:
        """Pressure at the DOF locations of boundary ``name`` from nodal normal forces (its body's)."""
        i, local = self.locate(name)
        return self.bodies[i].boundary_pressure(local, forces)

    def boundary_field_at_quadrature(self, name: str, values, **kw):
        """A scalar boundary field at the quadrature points of boundary ``name`` (its body's
        ``boundary_field_at_quadrature``: the Hertz fits of the contact pressure use it)."""
        i, local = self.locate(name)
        return self.bodies[i].boundary_field_at_quadrature(local, values, **kw)

    # ------------------------------------------------------------ supports and loads
    def _pad(self, i: int, vec: np.ndarray) -> np.ndarray:
        out = np.zeros(self.ndofs)
        out[self.offsets[i]: self.offsets[i + 1]] = vec
        return out

    def dirichlet(self, name: str, components: Sequence[int] | None = None, value: Any = 0.0):
        """Prescribed DOFs (stacked numbering) and values on boundary ``name`` (see ``LinearElasticity.dirichlet``)."""
        i, local = self.locate(name)
        dofs, vals = self.bodies[i].dirichlet(local, components, value)
        return dofs + self.offsets[i], vals

    def traction_load(self, name: str, traction) -> np.ndarray:
        """Load vector of a traction on boundary ``name``."""
        i, local = self.locate(name)
        return self._pad(i, self.bodies[i].traction_load(local, traction))

    def pressure_load(self, name: str, p) -> np.ndarray:
        """Load vector of a pressure on boundary ``name`` (positive pushes into its body)."""
        i, local = self.locate(name)
        return self._pad(i, self.bodies[i].pressure_load(local, p))

    def body_load(self, f) -> np.ndarray:
        """Load vector of a body force density acting on every body."""
        return np.concatenate([b.body_load(f) for b in self.bodies])

    # ------------------------------------------------------------ matrices and solving
    def stiffness(self) -> sp.csr_matrix:
        r"""Block-diagonal stiffness :math:`\operatorname{diag}(K_1, \dots, K_n)` (cached)."""
        if self._stiffness is None:
            self._stiffness = sp.block_diag([b.stiffness() for b in self.bodies], format="csr")
        return self._stiffness

    def clear_stiffness(self) -> None:
        """Drop the cached stiffness (and the bodies' own), and a factorization of it."""
        if self._factor_cache is not None and self._factor_cache[0] is self._stiffness:
            self._factor_cache = None
        self._stiffness = None
        for b in self.bodies:
            b.clear_stiffness()

    def internal_force(self, u) -> np.ndarray:
        r"""Internal force: :math:`K u` (linear bodies), else every body's :math:`f_{int}(u_b)` stacked."""
        u = np.asarray(u, dtype=float)
        if self.linear:
            return self.stiffness() @ u
        return np.concatenate([np.asarray(b.internal_force(ub), dtype=float)
                               for b, ub in zip(self.bodies, self.split(u))])

    def tangent(self, u=None) -> sp.csr_matrix:
        r"""The (constant) stiffness of linear bodies, else :math:`\operatorname{diag}(K_{T,b}(u_b))`."""
        if self.linear:
            return self.stiffness()
        indptr, indices = self.tangent_pattern
        K = sp.csr_matrix((self.tangent_data(u), indices.copy(), indptr.copy()), shape=(self.ndofs, self.ndofs))
        K.has_sorted_indices = True
        return K

    @property
    def tangent_pattern(self) -> tuple[np.ndarray, np.ndarray]:
        """``(indptr, indices)`` of the block-diagonal CSR pattern of every :meth:`tangent` (the bodies' own, stacked)."""
        cached = getattr(self, "_pattern", None)
        if cached is None:
            indptr, indices, nnz = [np.zeros(1, dtype=np.int64)], [], 0
            for b, off in zip(self.bodies, self.offsets[:-1]):
                bp, bi = b.tangent_pattern if hasattr(b, "tangent_pattern") else _csr_pattern(b.stiffness())
                indptr.append(np.asarray(bp[1:], dtype=np.int64) + nnz)
                indices.append(np.asarray(bi, dtype=np.int64) + off)
                nnz += int(bp[-1])
            cached = self._pattern = (np.concatenate(indptr), np.concatenate(indices))
            for a in cached:
                a.flags.writeable = False
        return cached

    def tangent_data(self, u) -> np.ndarray:
        """Values of :meth:`tangent` at ``u`` in the order of :attr:`tangent_pattern`."""
        return np.concatenate([np.asarray(b.tangent_data(ub), dtype=float) if hasattr(b, "tangent_data")
                               else b.stiffness().data for b, ub in zip(self.bodies, self.split(u))])

    def energy(self, u) -> float:
        r"""Strain energy of all bodies (:math:`\tfrac12 u^T K u` for linear ones)."""
        u = np.asarray(u, dtype=float)
        if self.linear:
            return 0.5 * float(u @ (self.stiffness() @ u))
        return float(sum(b.energy(ub) for b, ub in zip(self.bodies, self.split(u))))

    strain_energy = energy

    def check_restrained(self, dirichlet_dofs, **kw) -> None:
        """Each body's supports must stop its rigid motions; the error names the body.

        Raises
        ------
        alcontact.errors.InputError
            From the body's own check, prefixed with its name.
        """
        fixed = np.asarray(dirichlet_dofs, dtype=np.int64).ravel()
        for i, b in enumerate(self.bodies):
            lo, hi = self.offsets[i], self.offsets[i + 1]
            local = fixed[(fixed >= lo) & (fixed < hi)] - lo
            try:
                b.check_restrained(local, **kw)
            except InputError as exc:
                raise InputError(f"body {self.names[i]!r}: {exc}") from None

    def rigid_modes(self) -> np.ndarray:
        """``(ndofs, k)`` rigid-body modes of every body, each zero on the other bodies (block by block).

        A body that gives its own modes (``rigid_modes()``: a rigid body's DOFs are all rigid motions) gives them."""
        blocks = []
        for b, off in zip(self.bodies, self.offsets[:-1]):
            if hasattr(b, "rigid_modes"):
                R = np.zeros((self.ndofs, b.ndofs))
                R[off: off + b.ndofs] = b.rigid_modes()
                blocks.append(R)
                continue
            pts, dofs = b.all_node_dofs()
            modes, _ = b._rigid_modes(pts) if hasattr(b, "_rigid_modes") else rigid_body_modes(pts)
            R = np.zeros((self.ndofs, modes.shape[-1]))
            R[dofs.ravel() + off] = modes.reshape(-1, modes.shape[-1])
            blocks.append(R)
        return np.hstack(blocks)

    def factorize(self, dirichlet_dofs, *, matrix=None, check: bool = True, backend: str = "auto",
                  reuse: bool = True, schur=None):
        """Factorize the (block-diagonal) matrix condensed on the free DOFs; see ``LinearElasticity.factorize``.

        One factorization of the whole block-diagonal matrix (a direct solver treats the
        independent blocks at no extra cost); the last one is kept for the same matrix object
        and the same fixed DOFs. ``schur``: free DOFs (stacked numbering) to eliminate last, for
        a solver with a Schur facility (:class:`alcontact.linalg.MatrixHints`).
        """
        from alcontact.linalg import choose_solver, registered_solvers

        if matrix is None:
            if check:
                self.check_restrained(dirichlet_dofs)
            matrix = self.stiffness()
        names = registered_solvers()
        if backend != "auto" and backend not in names:
            raise InputError(f"backend={backend!r} is not a registered linear solver; use 'auto' or one of "
                             f"{', '.join(names)} (alcontact.linalg.register_solver adds others).")
        if backend == "auto":
            backend = choose_solver(self.dim, self.ndofs, allow_iterative=False)
        fixed = np.unique(np.asarray(dirichlet_dofs, dtype=np.int64).ravel())
        schur = None if schur is None else np.unique(np.asarray(schur, dtype=np.int64).ravel())
        key = (backend, bool(check), fixed.tobytes(), None if schur is None else schur.tobytes())
        cached = self._factor_cache
        if reuse and cached is not None and cached[0] is matrix and cached[1] == key:
            return cached[2]
        self._factor_cache = None
        mask = np.ones(self.ndofs, dtype=bool)
        mask[fixed] = False
        free = np.flatnonzero(mask)
        if schur is not None:  # positions in the free numbering (fixed DOFs dropped)
            schur = np.searchsorted(free, schur[~np.isin(schur, fixed)])
        hints = MatrixHints(dim=self.dim, near_null=lambda: np.ascontiguousarray(self.rigid_modes()[free]),
                            schur=schur)
        fac = Factorization(matrix, fixed, check=check, backend=backend, hints=hints)
        self.factorization_count += 1
        if reuse:
            self._factor_cache = (matrix, key, fac)
        return fac

    def clear_factorization(self) -> None:
        """Drop the cached factorization."""
        self._factor_cache = None

    def solve(self, load, dirichlet=()) -> np.ndarray:
        """Solve ``K u = load`` with Dirichlet conditions ``[(dofs, values), ...]`` (stacked numbering)."""
        load = np.asarray(load, dtype=float)
        if load.shape != (self.ndofs,):
            raise InputError(f"load must have shape ({self.ndofs},); got {load.shape}.")
        pairs = list(dirichlet)
        dofs = np.concatenate([np.asarray(d, dtype=np.int64).ravel() for d, _ in pairs]) if pairs else \
            np.empty(0, dtype=np.int64)
        vals = np.concatenate([np.broadcast_to(np.asarray(v, dtype=float), np.shape(d)).ravel()
                               for d, v in pairs]) if pairs else np.empty(0)
        uniq, idx = np.unique(dofs[::-1], return_index=True)
        return self.factorize(uniq).solve_full(load, vals[::-1][idx])
