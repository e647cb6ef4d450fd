# Two entry points (see README): `make run` and `make test`.
# Both create .venv on first use and install the package into it.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= results

.PHONY: run test install bench fuzz clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

install: $(VENV)/.installed

run: $(VENV)/.installed
	$(BIN)/alcontact run --out $(OUT) --force

test: $(VENV)/.installed
	$(BIN)/python -m pytest -q -n 2 --dist loadfile

# Problem-file fuzzing: 3 x 40,000 Hypothesis examples (profile "fuzz" in tests/conftest.py).
fuzz: $(VENV)/.installed
	ALCONTACT_FUZZ=1 $(BIN)/python -m pytest -q -n 2 tests/unit/test_config_fuzz.py

bench: $(VENV)/.installed
	$(BIN)/alcontact bench

clean:
	rm -rf $(VENV) $(OUT) build *.egg-info src/*.egg-info
