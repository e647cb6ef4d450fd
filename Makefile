# Two entry points (see README): `make run` and `make test`.
# Both create .venv on first use and install the package into it.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= results

.PHONY: run test test-slow install bench fuzz clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# Gmsh's wheel links the X11/OpenGL client libraries (it never opens a display); a bare
# Debian 12 lacks some of them, so they come from Debian's packages when `import gmsh` fails.
GMSH_DEBS := libglu1-mesa libgl1 libopengl0 libx11-6 libxext6 libxfixes3 libxrender1 \
             libxcursor1 libxft2 libxinerama1 libfontconfig1 libgomp1

$(VENV)/.installed: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test]'
	$(BIN)/python -c 'import gmsh' 2>/dev/null || { apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $(GMSH_DEBS); }
	$(BIN)/python -c 'import gmsh'
	touch $@

install: $(VENV)/.installed

run: $(VENV)/.installed
	$(BIN)/alcontact run --out $(OUT) --force

# one BLAS/OpenMP thread per pytest worker: 2 workers on 2 cores, no oversubscription
# (CHOLMOD through cholespy uses a reference BLAS, single-threaded; tests/conftest.py sets the same defaults)
TEST_ENV := OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 VECLIB_MAXIMUM_THREADS=1 NUMEXPR_NUM_THREADS=1

# `make test`: everything but the tests marked slow (each > ~10 s); CI (.ci/run) runs both targets
test: $(VENV)/.installed
	$(TEST_ENV) $(BIN)/python -m pytest -q -n 2 --dist loadfile -m "not slow"

test-slow: $(VENV)/.installed
	$(TEST_ENV) $(BIN)/python -m pytest -q -n 2 --dist loadfile -m slow

# Fuzzing (profile "fuzz" in tests/conftest.py): problem files 3 x 40,000 Hypothesis examples, Gmsh files
# 40,000, Python-API calls 40,000; the algorithm differential test 200 random problems.
FUZZ_TESTS := tests/unit/test_config_fuzz.py tests/unit/test_gmsh_fuzz.py tests/unit/test_api_fuzz.py \
	tests/property/test_algorithms_differential.py
fuzz: $(VENV)/.installed
	ALCONTACT_FUZZ=1 $(BIN)/python -m pytest -q -n 2 $(FUZZ_TESTS)

bench: $(VENV)/.installed
	$(BIN)/alcontact bench

clean:
	rm -rf $(VENV) $(OUT) build *.egg-info src/*.egg-info
