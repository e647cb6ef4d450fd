"""Property-based fuzz test of the Gmsh reader through the problem loader (issue 19): it never crashes.

Gmsh 2.2 files of a small square (2 x 2 cells) with random faults, loaded by
:func:`~alcontact.io.config.load_problem_text` as a ``generator = "file"`` mesh (read,
checked, body, boundaries, obstacle, supports; nothing is solved):

* **physical tags**: names dropped, emptied, given twice, tags shared between
  dimensions, names with spaces, quotes and non-ASCII characters, the section left out;
* **element types**: blocks of lines, triangles, quads, tetrahedra, hexahedra, points,
  second-order lines and triangles added, with valid or out-of-range node numbers;
* **coordinates**: NaN, infinity, 1e200, 1e-300, z off the plane, all nodes in one point,
  nodes swapped, duplicated elements;
* **text**: lines of the file deleted, duplicated or cut.

Property: the loader returns a ``ProblemSetup`` or raises one of the project's errors
(:class:`alcontact.errors.AlcontactError`); any other exception is a bug.

``make fuzz`` runs it under the Hypothesis profile ``fuzz`` (``ALCONTACT_FUZZ=1``, see
``tests/conftest.py``: 40,000 examples); the default suite draws 1,000.
"""

from __future__ import annotations

import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from _gmsh import GMSH_TYPES, SQUARE_PROBLEM, msh_text, square
from alcontact.errors import AlcontactError
from alcontact.io.config import ProblemSetup, load_problem_text

FUZZ = bool(os.environ.get("ALCONTACT_FUZZ"))
PTS, TRI, LINES = square(2)
ORDER = ["left", "right", "bottom", "top"]
NODES_OF = {"point": 1, "line": 2, "triangle": 3, "quad": 4, "tetra": 4, "hexahedron": 8, "line3": 3,
            "triangle6": 6}
ODD_NAMES = ["", " ", "top", "body", "left", "a b", 'q"uote', "ünïcode", "x" * 300, "gmsh:bounding_entities"]
ODD_NUMBERS = [math.nan, math.inf, -math.inf, 1e200, -1e200, 1e-300, 0.0, 1e30, 1e31]


def _examples(n: int) -> int:
    return settings.default.max_examples if FUZZ else n


@st.composite
def gmsh_files(draw) -> str:
    pts = PTS.copy()
    blocks = [("line", k + 1, LINES[n]) for k, n in enumerate(ORDER)] + [("triangle", 5, TRI.copy())]
    names = [(1, k + 1, n) for k, n in enumerate(ORDER)] + [(2, 5, "body")]
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["names", "names", "types", "coords", "coords", "elements"]))
        if kind == "names":
            op = draw(st.sampled_from(["drop", "rename", "retag", "redim", "add", "none"]))
            if op == "none":
                names = None
            elif names:
                i = draw(st.integers(0, len(names) - 1))
                d, tag, name = names[i]
                if op == "drop":
                    names = names[:i] + names[i + 1:]
                elif op == "rename":
                    names[i] = (d, tag, draw(st.sampled_from(ODD_NAMES + [n for _, _, n in names])))
                elif op == "retag":
                    names[i] = (d, draw(st.sampled_from([0, -1, 1, 2, 5, 99, 2**31])), name)
                elif op == "redim":
                    names[i] = (draw(st.sampled_from([0, 1, 2, 3, 7])), tag, name)
                else:
                    names.append((draw(st.integers(0, 3)), draw(st.integers(0, 9)), draw(st.sampled_from(ODD_NAMES))))
        elif kind == "types":
            typ = draw(st.sampled_from(sorted(GMSH_TYPES)))
            count = draw(st.integers(1, 3))
            high = len(pts) + draw(st.sampled_from([0, 0, 0, 5]))  # node numbers past the last node
            conn = np.array(draw(st.lists(st.lists(st.integers(0, high - 1), min_size=NODES_OF[typ],
                                                   max_size=NODES_OF[typ]), min_size=count, max_size=count)))
            blocks.append((typ, draw(st.sampled_from([1, 4, 5, 6])), conn))
        elif kind == "coords":
            op = draw(st.sampled_from(["value", "scale", "z", "collapse", "swap"]))
            i = draw(st.integers(0, len(pts) - 1))
            if op == "value":
                pts[i, draw(st.integers(0, 2))] = draw(st.sampled_from(ODD_NUMBERS) | st.floats())
            elif op == "scale":
                with np.errstate(over="ignore", under="ignore", invalid="ignore"):
                    pts = pts * draw(st.sampled_from([1e200, 1e-300, 1e-20, 1e29, -1.0, 0.0]))
            elif op == "z":
                pts[:, 2] = draw(st.sampled_from([0.0, 5.0])) + draw(st.sampled_from([0.0, 1e-12, 0.1])) * pts[:, 0]
            elif op == "collapse":
                pts[:] = pts[i]
            else:
                j = draw(st.integers(0, len(pts) - 1))
                pts[[i, j]] = pts[[j, i]]
        else:
            typ, tag, conn = blocks[4]
            k = draw(st.integers(0, len(conn) - 1))
            op = draw(st.sampled_from(["duplicate", "flip", "drop", "repeat-node"]))
            if op == "duplicate":
                conn = np.vstack([conn, conn[k:k + 1]])
            elif op == "flip":
                conn = conn.copy()
                conn[k] = conn[k][::-1]
            elif op == "drop":
                conn = np.delete(conn, k, axis=0)
            else:
                conn = conn.copy()
                conn[k, 1] = conn[k, 0]
            blocks[4] = (typ, tag, conn)
    text = msh_text(pts, blocks, names)
    if draw(st.integers(0, 4)) == 0:  # a text fault on top
        lines = text.split("\n")
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["delete", "duplicate", "cut"]))
        if op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        else:
            lines[i] = lines[i][: draw(st.integers(0, max(len(lines[i]) - 1, 0)))]
        text = "\n".join(lines)
    return text


def _load(text: str, tmp_path):
    (tmp_path / "body.msh").write_text(text, encoding="utf-8")
    try:
        setup = load_problem_text(SQUARE_PROBLEM, base_dir=tmp_path)
    except AlcontactError:
        return None
    assert isinstance(setup, ProblemSetup)
    assert np.all(np.isfinite(setup.problem.model.mesh.p))
    return setup


FUZZ_SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                           HealthCheck.function_scoped_fixture])


def test_the_unmutated_file_loads(tmp_path):
    """The starting point of the mutations is a valid mesh (else the fuzzing would only see errors)."""
    pts, blocks = PTS, [("line", k + 1, LINES[n]) for k, n in enumerate(ORDER)] + [("triangle", 5, TRI)]
    names = [(1, k + 1, n) for k, n in enumerate(ORDER)] + [(2, 5, "body")]
    assert _load(msh_text(pts, blocks, names), tmp_path) is not None


@settings(max_examples=_examples(1000), **FUZZ_SETTINGS)
@given(text=gmsh_files())
def test_faulty_gmsh_files_never_crash(text, tmp_path):
    _load(text, tmp_path)
