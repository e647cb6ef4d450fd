"""Property-based fuzz test of the problem-file loader (issue 8): it never crashes.

Three generators of problem files, each loaded with :func:`load_problem_text` (parse,
validate against the schema, build mesh, material, obstacle, supports, loads, load
history, solver options and the ``ContactProblem``; nothing is solved):

* mutations of the files in ``examples/`` (values replaced by other types, edge
  numbers such as ``10**400``, ``5e-324``, ``2**63 - 1``, ``nan``, ``inf``; keys
  deleted or added; entries of lists added and removed),
* random TOML documents (tables, arrays of tables, deeply nested arrays),
* text mutations of the example files (characters inserted, deleted, replaced).

Property: the loader returns a ``ProblemSetup`` or raises one of the project's
errors (``alcontact.errors.AlcontactError``); any other exception is a bug.

Sizes: the examples are shrunk to a few cells first, and ``meshes.MAX_VERTICES``
is lowered for the test, so a mutation asking for a big mesh is rejected by the
same validated limit that rejects absurd meshes in production, without building it.

``make fuzz`` runs these tests under the Hypothesis profile ``fuzz`` (selected by
``ALCONTACT_FUZZ=1``, see ``tests/conftest.py``): 40,000 examples per test.
"""

from __future__ import annotations

import copy
import datetime as dt
import json
import math
import os
import re
import shutil
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from alcontact.errors import AlcontactError
from alcontact.fem import meshes
from alcontact.io import schema
from alcontact.io.config import ProblemSetup, load_problem_text

ROOT = Path(__file__).resolve().parents[2]
FUZZ = bool(os.environ.get("ALCONTACT_FUZZ"))


def _examples(n: int) -> int:
    """``n`` examples in the test suite; the profile's count (``make fuzz``) when fuzzing."""
    return settings.default.max_examples if FUZZ else n


def _shrink(text: str) -> str:
    """An example with a mesh of a few cells (the mutations decide the rest)."""
    text = re.sub(r"(?m)^cells\s*=\s*\[([^\]]*)\]", lambda m: "cells = [" + ", ".join(
        "2" for _ in m.group(1).split(",")) + "]", text)
    text = re.sub(r"(?m)^h_min\s*=\s*[0-9.eE+-]+", "h_min = 4.0", text)
    return text


EXAMPLE_TEXTS = {p.name: _shrink(p.read_text(encoding="utf-8")) for p in sorted((ROOT / "examples").glob("*.toml"))}
EXAMPLE_DATA = {name: tomllib.loads(text) for name, text in EXAMPLE_TEXTS.items()}

KEYS = sorted({o.name for t in schema.schema() for o in t.options} | {t.path.split(".")[-1] for t in schema.schema()}
              | {"center", "radius", "point", "normal", "vertices", "axis", "height", "half_width"})
NAMES = sorted({c for t in schema.schema() for o in t.options for c in (o.allowed or ())}
               | {"top", "bottom", "left", "right", "front", "back", "circle", "sphere", "half-space",
                  "convex-polygon", "user", "body.msh", "traction", "pressure", "body-force", ""})
EDGE_INTS = [0, 1, -1, 2, 3, 7, 2**31, 2**53 + 1, 2**63 - 1, -(2**63), 10**400, 1_000_000_000, 100_000, 100_001]
EDGE_FLOATS = [0.0, -0.0, 0.5, 1.0, -1.0, 1e-300, 5e-324, 4e-324, 1e308, -1e308, 1.7976931348623157e308, math.inf,
               -math.inf, math.nan, 1e16, 1e-16, 0.49999999999999994]


@pytest.fixture(autouse=True)
def _small_meshes(monkeypatch):
    """Meshes above 2,000 vertices are rejected by the validated limit instead of being built."""
    monkeypatch.setattr(meshes, "MAX_VERTICES", 2_000)


# --------------------------------------------------------------------------- TOML writer
def _string(text: str) -> str:
    """A TOML basic string (json.dumps would write non-BMP characters as surrogate pairs, invalid in TOML)."""
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _string(k)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (dt.datetime, dt.date, dt.time)):
        return v.isoformat()
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def dumps(data: dict) -> str:
    """TOML text of ``data``: one line per root key, tables written inline."""
    return "\n".join(f"{_key(k)} = {_value(v)}" for k, v in data.items()) + "\n"


# --------------------------------------------------------------------------- strategies
scalars = st.one_of(
    st.sampled_from(EDGE_INTS), st.integers(), st.sampled_from(EDGE_FLOATS), st.floats(),
    st.booleans(), st.sampled_from(NAMES), st.text(max_size=8),
    st.datetimes(max_value=dt.datetime(9999, 1, 1), min_value=dt.datetime(1, 1, 2)),
)
toml_values = st.recursive(
    scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=5),
                            st.dictionaries(st.sampled_from(KEYS) | st.text(max_size=6), inner, max_size=4)),
    max_leaves=6,
)


def _deep(depth: int) -> str:
    return "[" * depth + "]" * depth


def _paths(node, prefix=()):
    """Every ``(container, key)`` inside a parsed document (dict keys and list indices)."""
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for k, v in list(items):
        yield node, k
        if isinstance(v, (dict, list)) and v:
            yield from _paths(v, prefix + (k,))


def _related(draw, old):
    """A value close to ``old``: scaled, negated, off by one, resized list, or another type."""
    if isinstance(old, bool):
        return draw(st.sampled_from([not old, int(old), str(old).lower()]))
    if isinstance(old, (int, float)):
        k = draw(st.sampled_from([-400, -320, -20, -1, 1, 3, 10, 20, 308, 400]))
        if isinstance(old, int):
            scaled = old * 10**k if k > 0 else old // 10**-k
        else:
            scaled = old * 10.0**k if abs(k) < 308 else old * 1e300 * 10.0 ** (k - 300 if k > 0 else k + 300)
        finite = not isinstance(old, float) or math.isfinite(old)
        other = (float(old) if abs(old) < 1e300 else math.inf) if isinstance(old, int) else (
            int(old) if finite else 0)
        return draw(st.sampled_from([scaled, -old, old + 1, old - 1, 0, other, str(old)]))
    if isinstance(old, list):
        choice = draw(st.integers(0, 3))
        if choice == 0 and old:
            return old[:-1]
        if choice == 1:
            return old + [old[-1] if old else 0]
        if choice == 2:
            return [old]
        return old * 3
    if isinstance(old, str):
        return draw(st.sampled_from([old + "x", old[:-1], old.upper(), "", "x" * 200]) | st.sampled_from(NAMES))
    return draw(toml_values)


@st.composite
def mutated_examples(draw):
    name = draw(st.sampled_from(sorted(EXAMPLE_DATA)))
    data = copy.deepcopy(EXAMPLE_DATA[name])
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 3]))):
        paths = list(_paths(data))
        if not paths:
            break
        node, key = draw(st.sampled_from(paths))
        op = draw(st.sampled_from(["related"] * 4 + ["replace", "delete", "add", "deep"]))
        if op == "related":
            node[key] = _related(draw, node[key])
        elif op == "replace":
            node[key] = draw(toml_values)
        elif op == "delete":
            del node[key]
        elif op == "add" and isinstance(node, dict):
            node[draw(st.sampled_from(KEYS) | st.text(min_size=1, max_size=6))] = draw(toml_values)
        elif op == "deep":
            node[key] = json.loads(_deep(draw(st.integers(1, 40))))
    return name, dumps(data)


@st.composite
def random_documents(draw):
    tables = draw(st.dictionaries(st.sampled_from(sorted({t.path.split(".")[0] for t in schema.schema()}))
                                  | st.text(min_size=1, max_size=5),
                                  st.dictionaries(st.sampled_from(KEYS), toml_values, max_size=5)
                                  | st.lists(st.dictionaries(st.sampled_from(KEYS), toml_values, max_size=3),
                                             max_size=2) | toml_values,
                                  max_size=6))
    text = dumps(tables)
    if draw(st.booleans()):
        text += f"deep = {_deep(draw(st.sampled_from([50, 500, 999, 1000, 5000, 20000])))}\n"
    return text


MUTATION_ALPHABET = "[]{}=\"'.,#\n \t0123456789eE+-_xyzinfa."


@st.composite
def text_mutations(draw):
    name = draw(st.sampled_from(sorted(EXAMPLE_TEXTS)))
    text = EXAMPLE_TEXTS[name]
    for _ in range(draw(st.integers(1, 6))):
        i = draw(st.integers(0, len(text)))
        op = draw(st.sampled_from(["insert", "delete", "replace", "duplicate-line"]))
        piece = draw(st.text(alphabet=MUTATION_ALPHABET, min_size=1, max_size=4))
        if op == "insert":
            text = text[:i] + piece + text[i:]
        elif op == "delete":
            text = text[:i] + text[i + len(piece):]
        elif op == "replace":
            text = text[:i] + piece + text[i + len(piece):]
        else:
            start = text.rfind("\n", 0, i) + 1
            end = text.find("\n", i)
            end = len(text) if end < 0 else end
            text = text[:end] + "\n" + text[start:end] + text[end:]
    return text


def _load(text: str, tmp: Path):
    for msh in (ROOT / "examples").glob("*.msh"):  # mesh files of the examples, relative to the problem file
        if not (tmp / msh.name).exists():
            shutil.copy(msh, tmp / msh.name)
    try:
        setup = load_problem_text(text, base_dir=tmp)
    except AlcontactError:
        return None
    assert isinstance(setup, ProblemSetup)
    model = setup.problem.model  # several bodies (a rigid body has no mesh): each mesh within the bound
    assert all(b.mesh.nvertices <= meshes.MAX_VERTICES for b in getattr(model, "bodies", [model])
               if b.mesh is not None)
    return setup


FUZZ_SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                           HealthCheck.function_scoped_fixture])


def test_shrunk_examples_still_build(tmp_path):
    """The starting points of the mutations are valid problem files (else the fuzzing would only see errors)."""
    for name, text in EXAMPLE_TEXTS.items():
        assert _load(text, tmp_path) is not None, name


@settings(max_examples=_examples(1000), **FUZZ_SETTINGS)
@given(case=mutated_examples())
def test_mutated_examples_never_crash(case, tmp_path):
    _load(case[1], tmp_path)


@settings(max_examples=_examples(500), **FUZZ_SETTINGS)
@given(text=random_documents())
def test_random_toml_never_crashes(text, tmp_path):
    _load(text, tmp_path)


@settings(max_examples=_examples(1000), **FUZZ_SETTINGS)
@given(text=text_mutations())
def test_text_mutations_never_crash(text, tmp_path):
    _load(text, tmp_path)


@pytest.mark.parametrize("edit,key", [
    (lambda t: t + "\nx = " + _deep(100_000) + "\n", "nested too deeply"),
    (lambda t: t.replace("E = ", "E = 1" + "0" * 400 + " #", 1), "material.E"),
    (lambda t: t.replace("E = ", "E = 1" + "0" * 5000 + " #", 1), "1.8e308"),
    (lambda t: re.sub(r"(?m)^radius = .*$", "radius = 1" + "0" * 400, t, count=1), "obstacle"),
    (lambda t: re.sub(r"(?m)^depth = .*$", "depth = 4e-324", t), None),
    (lambda t: re.sub(r"(?m)^h_min = .*$", "h_min = 5e-324", t), "h_min"),
    (lambda t: re.sub(r"(?m)^cells = .*$", "cells = [9223372036854775807, 4]", t), "mesh.cells[0]"),
    (lambda t: t + "\n[loading]\nsteps = 1000000000\n", "loading.steps"),
    (lambda t: re.sub(r"(?m)^bounds = .*$", "bounds = [-1e308, 1e308, 0, 1]", t), "mesh"),
    (lambda t: re.sub(r"(?m)^cells = .*$", "cells = [1000, 1000]", re.sub(r"(?ms)^\[mesh\.refine\].*?(?=^\[)", "", t)),
     "vertices"),
])
def test_issue_8_inputs_are_config_errors(edit, key, tmp_path):
    """The crashes reported in issue 8 are ConfigErrors naming the key (depth = 4e-324 acts as depth 0)."""
    from alcontact.errors import ConfigError

    text = edit(EXAMPLE_TEXTS["hertz_2d.toml"])
    if key is None:
        assert _load(text, tmp_path) is not None
        return
    with pytest.raises(ConfigError) as info:
        load_problem_text(text, base_dir=tmp_path)
    assert key in str(info.value)
