"""Without petsc4py the PETSc solvers stay registered and naming one says how to install them."""

from __future__ import annotations

import sys

import pytest

from alcontact import linalg
from alcontact.errors import InputError


@pytest.fixture
def no_petsc(monkeypatch):
    monkeypatch.setitem(sys.modules, "petsc4py", None)  # import petsc4py -> ImportError
    linalg.is_installed.cache_clear()
    yield
    linalg.is_installed.cache_clear()


@pytest.mark.parametrize("name", ["petsc", "petsc-direct"])
def test_naming_a_petsc_solver_without_petsc4py_gives_the_make_mpi_command(no_petsc, name):
    assert name in linalg.registered_solvers() and name not in linalg.available_solvers()
    with pytest.raises(InputError, match="make mpi"):
        linalg.make_solver(name)


def test_the_solver_class_itself_gives_the_make_mpi_command(no_petsc):
    with pytest.raises(InputError, match="make mpi"):
        linalg.PetscKrylovSolver()


def test_auto_never_chooses_petsc():
    installed = linalg.registered_solvers()
    for dim, n in [(2, 10), (3, 10**7)]:
        assert not linalg.choose_solver(dim, n, installed=installed).startswith("petsc")
