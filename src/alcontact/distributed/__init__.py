"""Distributed bodies on PETSc (petsc4py) and MPI (mpi4py): the foundation of ``mpirun -n N``.

Nothing is imported from MPI or PETSc until a distributed object is built, so
``import alcontact.distributed`` is as light as the serial path. Install the MPI
environment with ``make mpi`` (see the README) and run scripts with
``mpirun -n N .venv-mpi/bin/python script.py``.

What is here: the mesh partition (METIS through pymetis,
:func:`partition_elements`), linear elasticity assembled per rank with scikit-fem into
a PETSc ``MPIAIJ`` matrix with COO preallocation and solved with KSP
(:class:`DistributedElasticity`), and the collective error rule (:func:`collective`,
:class:`DistributedError`): a phase that fails on one rank raises on every rank; and
:func:`check_launch`, the clear refusal of a serial command started as several MPI ranks.
The distributed contact solve built on these pieces is :func:`alcontact.contact.solve_distributed`
(``mpirun -n N alcontact run problem.toml``).
"""

from ._comm import DistributedError, collective, release_memory, run_ranks, world
from ._elasticity import DistributedElasticity, DistributedSolution, LocalPiece
from ._launch import check_launch, launch_rank, launch_size, mpi_extras_missing
from ._partition import dual_graph, owner_numbering, partition_elements

__all__ = [
    "DistributedElasticity",
    "DistributedError",
    "DistributedSolution",
    "LocalPiece",
    "check_launch",
    "collective",
    "dual_graph",
    "launch_rank",
    "launch_size",
    "mpi_extras_missing",
    "owner_numbering",
    "partition_elements",
    "release_memory",
    "run_ranks",
    "world",
]
