r"""Linear elasticity assembled and solved over MPI ranks on a PETSc ``MPIAIJ`` matrix.

Rank 0 holds the mesh (as the serial path reads it), partitions its elements
(:func:`~alcontact.distributed._partition.partition_elements`) and sends each rank only
its elements and their nodes. Each rank assembles the stiffness of its own elements with
scikit-fem (:class:`alcontact.fem.LinearElasticity` on the local piece of the mesh,
the bilinear form of the equilibrium (6.18)-(6.20) without contact, :math:`a(u, v) = \int_\Omega \sigma(u):\varepsilon(v)\,dx`)
into its local CSR matrix (rows and columns of its own nodes), and inserts it in one
``MatSetValuesIJV`` call with the global row of each local row: rows owned by another rank
(nodes on the interface) travel through PETSc's stash to their owner at assembly. The
preallocation is exact on the rows only this rank assembles and an upper bound (the sum of
the ranks' counts) on interface rows (:meth:`DistributedElasticity._preallocation`); a
preallocation with COO triplets (``MatSetPreallocationCOO``) kept about 30 bytes per stored
entry beyond the matrix (its maps and the triplets) and held the rank's block at block size 1.
No rank but rank 0 (while it scatters the mesh) holds an array of the global size.

Numbering: a node belongs to the lowest rank among its elements; each rank owns a
contiguous range of nodes, and DOF ``dim * node + c`` (block size ``dim``, what GAMG
wants for its aggregates). Dirichlet rows and columns are eliminated with
``MatZeroRowsColumns`` (diagonal 1, prescribed value in the right-hand side).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ._comm import collective, world
from ._partition import owner_numbering, partition_elements

__all__ = ["DistributedElasticity", "LocalPiece", "DistributedSolution"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class LocalPiece:
    """What one rank holds of the mesh.

    Attributes
    ----------
    points : numpy.ndarray, shape (dim, n_local_nodes)
        Coordinates of the nodes of this rank's elements.
    elements : numpy.ndarray, shape (nodes_per_element, n_local_elements)
        Connectivity in local node numbers.
    global_nodes : numpy.ndarray of int, shape (n_local_nodes,)
        Distributed (owner-contiguous) number of each local node.
    node_range : tuple of int
        ``[start, stop)`` of the distributed node numbers this rank owns.
    n_nodes : int
        Number of nodes of the whole mesh.
    mesh_nodes : numpy.ndarray of int, shape (n_local_nodes,), optional
        Number of each local node in the numbering of rank 0's model (P1: ``mesh.p`` columns; P2:
        its scalar DOFs, vertices then edge nodes), for output.
    order : int
        1 (the nodes are the vertices) or 2 (the nodes are the scalar P2 DOFs of the local mesh:
        its vertices, then its edge nodes, in scikit-fem's numbering).
    node_points : numpy.ndarray, shape (dim, n_local_nodes), optional
        Coordinates of the local nodes (P2: with the edge nodes; ``None`` for P1: ``points``).
    elem_nodes, elem_mesh_nodes : numpy.ndarray, optional
        P2 in transit: the distributed and the model's number of every node of every element (the
        receiving rank turns them into ``global_nodes`` and ``mesh_nodes`` of its own numbering).
    """

    points: np.ndarray
    elements: np.ndarray
    global_nodes: np.ndarray | None
    node_range: tuple[int, int]
    n_nodes: int
    mesh_nodes: np.ndarray | None = None
    order: int = 1
    node_points: np.ndarray | None = None
    elem_nodes: np.ndarray | None = None
    elem_mesh_nodes: np.ndarray | None = None


@dataclass
class DistributedSolution:
    """The displacement this rank owns and how the solve went.

    Attributes
    ----------
    u : numpy.ndarray, shape (n_owned_nodes * dim,)
        Displacement of the owned nodes, node-major (``u[dim * i + c]``).
    points : numpy.ndarray, shape (n_owned_nodes, dim)
        Coordinates of the owned nodes.
    iterations : int
        Krylov iterations.
    reason : int
        PETSc's converged reason (positive: converged).
    residual_norm : float
        Final (preconditioned) residual norm PETSc reports.
    seconds : dict
        Wall time of ``distribute``, ``assemble``, ``setup`` and ``solve`` on this rank.
    """

    u: np.ndarray
    points: np.ndarray
    iterations: int
    reason: int
    residual_norm: float
    seconds: dict = field(default_factory=dict)


class DistributedElasticity:
    """Small-strain linear elasticity on P1 triangles/tetrahedra, distributed over the ranks of ``comm``.

    Parameters
    ----------
    mesh : skfem.MeshTri or skfem.MeshTet or None
        The whole mesh on rank 0; ignored on the other ranks (pass None there).
    material : alcontact.fem.Material
    comm : mpi4py communicator, optional
        Default ``MPI.COMM_WORLD``.
    parts : numpy.ndarray of int, optional
        Rank of each element (on rank 0), instead of METIS (e.g. to force a cut).
    checked_mesh : bool
        The whole mesh's element quality was checked already (the contact path's model on rank 0
        did it): each rank's piece is not checked again. Default False: every rank checks its
        piece.

    Examples
    --------
    Run with ``mpirun -n 2 .venv-mpi/bin/python script.py``::

        model = DistributedElasticity(mesh if rank == 0 else None, Material(E=1e3, nu=0.3))
        sol = model.solve(body_force=[0, 0, -1], clamped=lambda x: x[0] < 1e-12)
    """

    def __init__(self, mesh, material, *, comm=None, parts: np.ndarray | None = None, order: int = 1,
                 element_nodes: np.ndarray | None = None, checked_mesh: bool = False):
        from ..fem import Material

        self.comm = comm if comm is not None else world()
        if not isinstance(material, Material):
            raise InputError(f"material must be an alcontact.fem.Material; got {type(material).__name__}.")
        if order not in (1, 2):
            raise InputError(f"order = {order!r}: the distributed elasticity has P1 and P2 elements (1 or 2).")
        self.material = material
        self.order = int(order)
        self.checked_mesh = bool(checked_mesh)
        t0 = time.perf_counter()
        #: on rank 0: ``numbering[old]`` is the distributed number of the model's node ``old`` (None elsewhere)
        self.numbering: np.ndarray | None = None
        self._element_nodes = element_nodes
        self.piece, self._mesh_type = self._distribute(mesh, parts)
        self._element_nodes = None
        self.dim = int(self.piece.points.shape[0])
        self._local = None
        if self.order == 2:  # the P2 nodes of the piece in the local model's numbering
            self._local = self._local_model()
            led = np.asarray(self._local.scalar_dofs.element_dofs)
            n = int(self._local.scalar_dofs.N)
            g, mn = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
            g[led] = self.piece.elem_nodes
            mn[led] = self.piece.elem_mesh_nodes
            self.piece = dataclasses.replace(self.piece, global_nodes=g, mesh_nodes=mn, elem_nodes=None,
                                             elem_mesh_nodes=None,
                                             node_points=np.asarray(self._local.scalar_doflocs, dtype=float))
        self.seconds = {"distribute": time.perf_counter() - t0}

    def _local_model(self):
        """The piece as an :class:`alcontact.fem.LinearElasticity` of this rank (P1 or P2)."""
        from ..fem import LinearElasticity

        piece = self.piece
        return LinearElasticity(self._mesh_type(piece.points, piece.elements), self.material, order=self.order,
                                checked_mesh=self.checked_mesh)

    @property
    def node_points(self) -> np.ndarray:
        """``(dim, n_local_nodes)`` coordinates of the local nodes (P2: the edge nodes too)."""
        return self.piece.points if self.piece.node_points is None else self.piece.node_points

    # ---------------------------------------------------------------- mesh
    def _distribute(self, mesh, parts):
        comm = self.comm
        size, rank = comm.size, comm.rank
        plan = mesh_type = None
        with collective(comm, "partitioning the mesh"):
            if rank == 0:
                plan, mesh_type, self.numbering = self._split(mesh, parts, size, self.order, self._element_nodes,
                                                              self.material)
        mesh_type = comm.bcast(mesh_type, root=0)
        # rank 0 builds and sends one piece at a time (never every piece at once: a second copy of the mesh)
        if rank == 0:
            for r in range(1, size):
                comm.send(self._piece_of(plan, r), dest=r, tag=71)
            return self._piece_of(plan, 0), mesh_type
        return comm.recv(source=0, tag=71), mesh_type

    @staticmethod
    def _piece_of(plan, r: int) -> LocalPiece:
        """Rank ``r``'s elements and their nodes from the partition ``plan`` of :meth:`_split`."""
        p, t, parts, new, starts, T = plan
        sel = parts == r
        tr = t[:, sel]
        nodes = np.unique(tr)
        local = np.searchsorted(nodes, tr)  # monotonic: each element keeps its vertex order
        rng = (int(starts[r]), int(starts[r + 1]))
        if T is None:
            return LocalPiece(np.ascontiguousarray(p[:, nodes]), np.ascontiguousarray(local), new[nodes], rng,
                              int(new.size), mesh_nodes=nodes)
        Tr = T[:, sel]
        return LocalPiece(np.ascontiguousarray(p[:, nodes]), np.ascontiguousarray(local), None, rng, int(new.size),
                          order=2, elem_nodes=np.ascontiguousarray(new[Tr]), elem_mesh_nodes=np.ascontiguousarray(Tr))

    @staticmethod
    def _split(mesh, parts, size, order: int = 1, element_nodes=None, material=None):
        import skfem

        if not isinstance(mesh, (skfem.MeshTri1, skfem.MeshTet1)):
            raise InputError(f"the distributed elasticity needs a linear triangle (MeshTri) or tetrahedron (MeshTet) "
                             f"mesh on rank 0; got {type(mesh).__name__}.")
        p, t = np.asarray(mesh.p), np.asarray(mesh.t)
        if parts is None:
            parts = partition_elements(t, size)
        else:
            parts = np.asarray(parts, dtype=np.int64)
            if parts.shape != (t.shape[1],) or parts.min() < 0 or parts.max() >= size:
                raise InputError(f"parts must give each of the {t.shape[1]} elements a rank in 0..{size - 1}; got "
                                 f"shape {parts.shape} with values {parts.min()}..{parts.max()}.")
            if np.unique(parts).size != size:
                raise InputError(f"parts leaves a rank without elements ({np.unique(parts).size} of {size} used).")
        T = None  # P2: the scalar DOFs of every element (vertices, then edge nodes), the nodes that are distributed
        if order == 2:
            if element_nodes is None:
                from ..fem import LinearElasticity

                element_nodes = LinearElasticity(mesh, material, order=2).scalar_dofs.element_dofs
            T = np.asarray(element_nodes, dtype=np.int64)
        nodes_of, n_nodes = (t, p.shape[1]) if T is None else (T, int(T.max()) + 1)
        owner, new = owner_numbering(nodes_of, parts, n_nodes)
        counts = np.bincount(owner, minlength=size)
        starts = np.concatenate([[0], np.cumsum(counts)])
        return (p, t, parts, new, starts, T), type(mesh), new

    # ------------------------------------------------------------ assembly
    def assemble(self, body_force, *, node_blocks: np.ndarray | None = None):
        """Global stiffness (``MPIAIJ``, block size ``dim``) and body-load vector.

        Parameters
        ----------
        body_force : array_like, shape (dim,)
            Constant force per unit volume.
        node_blocks : numpy.ndarray of int, optional
            Owned nodes (numbered from this rank's first node) whose whole ``dim x dim``
            diagonal block must be in the pattern, explicit zeros where the stiffness cancels
            (e.g. the x-y coupling of a node of a structured tetrahedral mesh): the contact
            points, whose Newton matrices write their springs there. Preallocated and inserted
            before the first assembly (an entry added to an assembled matrix reallocates its
            rows: 2,209 contact blocks took 2.0 s at 250k DOFs that way).

        Returns
        -------
        K : petsc4py.PETSc.Mat
        f : petsc4py.PETSc.Vec
        """
        from ..linalg import petsc

        PETSc = petsc()
        comm, dim, piece = self.comm, self.dim, self.piece
        t0 = time.perf_counter()
        with collective(comm, "assembling the local stiffness"):
            local = self._local if self._local is not None else self._local_model()
            self._local = None
            K = local.stiffness().tocsr()
            force = np.asarray(body_force, dtype=float)
            # no body force: no load assembly (it builds the vector basis at every quadrature point of the piece)
            f_loc = local.body_load(force) if np.any(force != 0.0) else np.zeros(local.ndofs)
            _, dmap = local.all_node_dofs()  # (n_local_nodes, dim) local vector DOFs
            gdof = np.empty(local.ndofs, dtype=PETSc.IntType)
            for c in range(dim):
                gdof[dmap[:, c]] = dim * piece.global_nodes + c
            del local
            cols = gdof[K.indices].astype(PETSc.IntType)  # global column of every stored entry
        n_own = dim * (piece.node_range[1] - piece.node_range[0])
        N = dim * piece.n_nodes
        d_nnz, o_nnz = self._preallocation(K, gdof, cols, n_own)
        if node_blocks is not None:
            block_rows = (dim * np.asarray(node_blocks, dtype=np.int64)[:, None] + np.arange(dim)).ravel()
            d_nnz[block_rows] = np.minimum(d_nnz[block_rows] + dim, n_own)  # room for the block, an upper bound
        A = PETSc.Mat().create(comm=comm)
        A.setSizes(((n_own, N), (n_own, N)), bsize=dim)
        A.setType(PETSc.Mat.Type.AIJ)
        A.setPreallocationNNZ((d_nnz, o_nnz))
        del d_nnz, o_nnz
        # every local row at once, rows owned by another rank through PETSc's stash to their owner
        A.setValuesIJV(K.indptr.astype(PETSc.IntType), cols, K.data, addv=PETSc.InsertMode.ADD_VALUES, rowmap=gdof)
        del K, cols
        if node_blocks is not None and block_rows.size:
            grows = (dim * piece.node_range[0] + block_rows).astype(PETSc.IntType)
            bcols = np.repeat(grows.reshape(-1, dim), dim, axis=0).ravel().astype(PETSc.IntType)
            A.setValuesIJV(np.arange(0, bcols.size + 1, dim, dtype=PETSc.IntType), bcols, np.zeros(bcols.size),
                           addv=PETSc.InsertMode.ADD_VALUES, rowmap=grows)
        A.assemble()
        if comm.size > 1 and A.getDiagonalBlock().getBlockSize() != dim:
            # point-block Jacobi (MatInvertBlockDiagonal of the rank's diagonal block) needs the node blocks there
            A.getDiagonalBlock().setBlockSize(dim)
        A.setOption(PETSc.Mat.Option.SPD, True)
        f = A.createVecRight()
        f.setValues(gdof, f_loc, addv=PETSc.InsertMode.ADD_VALUES)
        f.assemblyBegin()
        f.assemblyEnd()
        self.seconds["assemble"] = time.perf_counter() - t0
        return A, f

    def _preallocation(self, K, gdof: np.ndarray, cols: np.ndarray, n_own: int) -> tuple[np.ndarray, np.ndarray]:
        """Entries per owned row in the diagonal and off-diagonal blocks (``MatMPIAIJSetPreallocation``).

        The rows of this rank's elements count their own entries; a row owned by another rank
        (a node on the interface, in this rank's elements) is counted by the rank that
        assembles it and the counts are sent to its owner, which adds them. Entries two
        ranks both add are counted twice: an upper bound on the interface rows only.
        """
        comm, dim = self.comm, self.dim
        ranges = np.array(comm.allgather(self.piece.node_range), dtype=np.int64) * dim  # DOF range of each rank
        lo, hi = ranges[comm.rank]
        grow = gdof.astype(np.int64)
        owner = np.searchsorted(ranges[:, 1], grow, side="right")  # rank owning each local row
        # entries of each local row in this rank's column range (right for the rows it owns) ...
        d_row = np.add.reduceat((cols >= lo) & (cols < hi), K.indptr[:-1], dtype=np.int64)
        ghost = np.flatnonzero(owner != comm.rank)
        if ghost.size:  # ... and, for the rows of other ranks, in the column range of their owner
            G = K[ghost]
            gcols = gdof[G.indices].astype(np.int64)
            r_of = np.repeat(owner[ghost], np.diff(G.indptr))
            d_row[ghost] = np.add.reduceat((gcols >= ranges[r_of, 0]) & (gcols < ranges[r_of, 1]), G.indptr[:-1],
                                           dtype=np.int64)
        o_row = np.diff(K.indptr) - d_row
        d_nnz = np.zeros(n_own, dtype=np.int64)
        o_nnz = np.zeros(n_own, dtype=np.int64)
        mine = owner == comm.rank
        d_nnz[grow[mine] - lo] += d_row[mine]
        o_nnz[grow[mine] - lo] += o_row[mine]
        send = [None] * comm.size
        for r in range(comm.size):
            sel = owner == r
            if r != comm.rank and np.any(sel):
                send[r] = (grow[sel], d_row[sel], o_row[sel])
        for got in comm.alltoall(send):
            if got is not None:
                rows, d, o = got
                np.add.at(d_nnz, rows - lo, d)
                np.add.at(o_nnz, rows - lo, o)
        N = int(ranges[-1, 1])
        PETSc_int = gdof.dtype
        return np.minimum(d_nnz, hi - lo).astype(PETSc_int), np.minimum(o_nnz, N - (hi - lo)).astype(PETSc_int)

    def forget_numbering(self) -> None:
        """Drop rank 0's ``numbering`` (an array over the whole mesh) once nothing needs it (the pieces carry
        their mesh node numbers, :attr:`LocalPiece.mesh_nodes`)."""
        self.numbering = None

    def owned_mesh_nodes(self) -> np.ndarray:
        """Mesh node number (rank 0's numbering) of each owned node, in distributed order (no communication)."""
        piece = self.piece
        i = piece.global_nodes - piece.node_range[0]
        mine = (i >= 0) & (i < piece.node_range[1] - piece.node_range[0])
        out = np.empty(piece.node_range[1] - piece.node_range[0], dtype=np.int64)
        out[i[mine]] = piece.mesh_nodes[mine]
        return out

    def owned_points(self) -> np.ndarray:
        """``(n_owned_nodes, dim)`` coordinates of the nodes this rank owns, in distributed order."""
        piece = self.piece
        i = piece.global_nodes - piece.node_range[0]
        mine = (i >= 0) & (i < piece.node_range[1] - piece.node_range[0])
        out = np.empty((piece.node_range[1] - piece.node_range[0], self.dim))
        out[i[mine]] = self.node_points[:, mine].T
        return out

    def rigid_modes(self) -> np.ndarray:
        """Rigid-body modes at the owned nodes, ``(n_owned * dim, 3 or 6)``, about the global centroid."""
        from mpi4py import MPI

        x = self.owned_points()
        c = self.comm.allreduce(x.sum(axis=0), op=MPI.SUM) / self.piece.n_nodes
        scale = self.comm.allreduce(float(np.max(np.abs(x - c))) if x.size else 0.0, op=MPI.MAX) or 1.0
        y = (x - c) / scale
        cols = []
        for i in range(self.dim):
            e = np.zeros_like(y)
            e[:, i] = 1.0
            cols.append(e)
        if self.dim == 2:
            cols.append(np.column_stack([-y[:, 1], y[:, 0]]))
        else:
            for ax in range(3):
                omega = np.zeros(3)
                omega[ax] = 1.0
                cols.append(np.cross(omega, y))
        return np.stack([m.ravel() for m in cols], axis=1)

    # --------------------------------------------------------------- solve
    def solve(self, body_force, clamped: Callable[[np.ndarray], np.ndarray], *, solver: str = "gamg",
              rtol: float = 1e-10, options: dict | None = None) -> DistributedSolution:
        """Assemble, clamp the nodes where ``clamped(x)`` holds, and solve ``K u = f``.

        Parameters
        ----------
        body_force : array_like, shape (dim,)
        clamped : callable
            ``clamped(x) -> bool array`` for node coordinates ``x`` of shape ``(dim, m)``:
            all components of these nodes are fixed to zero.
        solver : {"gamg", "direct"}
            CG + GAMG with the rigid-body near-null space, or MUMPS (else SuperLU_dist).
        rtol : float
            Relative residual of CG.
        options : dict, optional
            PETSc options passed through (names without the dash); the ones PETSc did not use
            are logged as a warning by rank 0 after the solve (:func:`alcontact.linalg.report_unused_options`).
        """
        from ..linalg import configure_ksp, direct_package, near_null_space, petsc, report_unused_options

        PETSc = petsc()
        if solver not in ("gamg", "direct"):
            raise InputError(f"solver={solver!r}; allowed: 'gamg', 'direct'.")
        A, f = self.assemble(body_force)
        t0 = time.perf_counter()
        with collective(self.comm, "finding the clamped nodes"):
            x = self.owned_points()
            fixed = np.asarray(clamped(x.T), dtype=bool)
            if fixed.shape != (x.shape[0],):
                raise InputError(f"clamped(x) must return one bool per node, shape ({x.shape[0]},); got {fixed.shape}.")
            start = self.dim * self.piece.node_range[0]
            rows = (start + self.dim * np.flatnonzero(fixed)[:, None] + np.arange(self.dim)).ravel()
        from mpi4py import MPI

        if self.comm.allreduce(int(rows.size), op=MPI.SUM) == 0:
            raise InputError("clamped(x) holds at no node: the body would move freely; clamp a boundary.")
        u = A.createVecRight()
        A.zeroRowsColumns(rows.astype(PETSc.IntType), diag=1.0, x=u, b=f)
        if solver == "gamg":
            null = near_null_space(self.rigid_modes(), comm=A.getComm())
            ksp = configure_ksp(A, ksp_type="cg", pc_type="gamg", rtol=rtol, options=options, near_null=null,
                                defer_check=True)
        else:
            pkg = direct_package()
            ksp = configure_ksp(A, ksp_type="preonly", pc_type="cholesky" if pkg == "mumps" else "lu", rtol=rtol,
                                options=options, factor_solver=pkg, defer_check=True)
        t1 = time.perf_counter()
        self.seconds["setup"] = t1 - t0
        ksp.solve(f, u)
        self.seconds["solve"] = time.perf_counter() - t1
        # every rank clears its options database; rank 0 alone reports (the ranks read the same options)
        report_unused_options(ksp.getOptionsPrefix() or "", options,
                              reported=None if self.comm.rank == 0 else set(options or {}))
        reason = int(ksp.getConvergedReason())
        its = int(ksp.getIterationNumber())
        if reason < 0:
            raise InputError(f"PETSc KSP {ksp.getType()} / PC {ksp.getPC().getType()} did not converge (reason "
                             f"{reason}, {its} iterations); pass options (ksp_max_it, pc_gamg_threshold) or "
                             "solver='direct'.")
        return DistributedSolution(u.getArray().copy(), x, its, reason, float(ksp.getResidualNorm()),
                                   dict(self.seconds))

    def gather(self, sol: DistributedSolution):
        """The whole displacement on rank 0 as ``(n_nodes, dim)`` in the distributed node order, with the points.

        For checks and small output only: it is the one place that builds a global array
        (on rank 0); the other ranks get ``(None, None)``.
        """
        us = self.comm.gather(sol.u.reshape(-1, self.dim), root=0)
        xs = self.comm.gather(sol.points, root=0)
        if self.comm.rank != 0:
            return None, None
        return np.concatenate(us), np.concatenate(xs)
