# Two entry points (see README): `make run` and `make test`.
# Both create .venv on first use and install the package into it.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= results

.PHONY: run test test-serial test-mpi test-slow install mpi bench study fuzz clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# ---- the MPI / PETSc environment (`make mpi`), Debian 12 (bookworm) + Python 3.11:
# Debian's petsc4py 3.18 (OpenMPI; MUMPS, SuperLU_dist, hypre), mpi4py and OpenMPI from apt, and a
# venv over the system site-packages (NumPy 1.x, which that petsc4py needs: the `mpi` extra pins it).
# No source build: PyPI has no petsc4py wheel for this platform and building PETSc takes far longer
# than the apt packages (measured with `make mpi` on a fresh machine: see the README).
MPI_VENV      := .venv-mpi
MPI_APT       := python3-petsc4py python3-mpi4py openmpi-bin python3-venv
DEBIAN_PETSC  := /usr/lib/petscdir/petsc3.18/x86_64-linux-gnu-real
SUDO          := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
MPI_RUN_ENV   := OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

$(MPI_VENV)/.installed: pyproject.toml
	@command -v apt-get >/dev/null || { echo "make mpi: needs Debian/Ubuntu apt-get (python3-petsc4py); see README"; exit 1; }
	dpkg -s $(MPI_APT) >/dev/null 2>&1 || { $(SUDO) apt-get update -q && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -q --no-install-recommends $(MPI_APT); }
	test -x $(MPI_VENV)/bin/python || /usr/bin/python3 -m venv --system-site-packages $(MPI_VENV)
	# Debian's petsc4py.pth looks for it under $$PETSC_DIR (or petsc-dev's /usr/lib/petsc): point at it once
	echo $(DEBIAN_PETSC)/lib/python3/dist-packages > \
		$$($(MPI_VENV)/bin/python -c "import sysconfig; print(sysconfig.get_paths()['purelib'])")/zz-petsc-debian.pth
	$(MPI_VENV)/bin/python -m pip install --quiet -e '.[test,mpi]'
	$(MPI_VENV)/bin/python -c "import alcontact.linalg as L; L.petsc(); import mpi4py, pymetis"
	touch $@

mpi: $(MPI_VENV)/.installed

# Gmsh's wheel links the X11/OpenGL client libraries (it never opens a display); a bare
# Debian 12 lacks some of them, so they come from Debian's packages when `import gmsh` fails.
GMSH_DEBS := libglu1-mesa libgl1 libopengl0 libx11-6 libxext6 libxfixes3 libxrender1 \
             libxcursor1 libxft2 libxinerama1 libfontconfig1 libgomp1

$(VENV)/.installed: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test]'
	$(BIN)/python -c 'import gmsh' 2>/dev/null || { $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $(GMSH_DEBS); }
	$(BIN)/python -c 'import gmsh'
	touch $@

install: $(VENV)/.installed

run: $(VENV)/.installed
	$(BIN)/alcontact run --out $(OUT) --force

# one BLAS/OpenMP thread per pytest worker: 2 workers on 2 cores, no oversubscription
# (CHOLMOD through cholespy uses a reference BLAS, single-threaded; tests/conftest.py sets the same defaults)
TEST_ENV := OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 VECLIB_MAXIMUM_THREADS=1 NUMEXPR_NUM_THREADS=1

# `make test`: everything but the tests marked slow (each > ~10 s); CI (.ci/run) runs both targets.
# It includes the PETSc/MPI tests (tests/mpi, run in .venv-mpi, some through `mpirun -n 2` and
# `-n 3`), so it depends on `make mpi`; they are never skipped (tests/mpi/conftest.py).
test: test-serial test-mpi

test-serial: $(VENV)/.installed
	$(TEST_ENV) $(BIN)/python -m pytest -q -n 2 --dist loadfile -m "not slow" --ignore=tests/mpi

test-mpi: $(MPI_VENV)/.installed
	$(TEST_ENV) $(MPI_RUN_ENV) $(MPI_VENV)/bin/python -m pytest -q -p no:cacheprovider -m "not slow" tests/mpi \
		tests/unit/test_linalg.py tests/unit/test_linalg_petsc_missing.py

# the slow tests of both environments (the MPI ones: 3-rank and 3D P2 runs of the distributed path)
test-slow: $(VENV)/.installed $(MPI_VENV)/.installed
	$(TEST_ENV) $(BIN)/python -m pytest -q -n 2 --dist loadfile -m slow --ignore=tests/mpi
	$(TEST_ENV) $(MPI_RUN_ENV) $(MPI_VENV)/bin/python -m pytest -q -p no:cacheprovider -m slow tests/mpi

# Fuzzing (profile "fuzz" in tests/conftest.py): problem files 3 x 40,000 Hypothesis examples, Gmsh files
# 40,000, Python-API calls 40,000; the algorithm differential test 200 random problems.
FUZZ_TESTS := tests/unit/test_config_fuzz.py tests/unit/test_gmsh_fuzz.py tests/unit/test_api_fuzz.py \
	tests/property/test_algorithms_differential.py
fuzz: $(VENV)/.installed
	ALCONTACT_FUZZ=1 $(BIN)/python -m pytest -q -n 2 $(FUZZ_TESTS)

bench: $(VENV)/.installed
	$(BIN)/alcontact bench

# `make study`: the full study (resumable: a re-run skips finished cells); STUDY_ARGS=--quick for the short one
STUDY_OUT  ?= study
STUDY_JOBS ?= 2
study: $(VENV)/.installed
	$(TEST_ENV) $(BIN)/alcontact study --out $(STUDY_OUT) --jobs $(STUDY_JOBS) $(STUDY_ARGS)

clean:
	rm -rf $(VENV) $(MPI_VENV) $(OUT) build *.egg-info src/*.egg-info
