"""``alcontact check`` (and ``run``, which checks first): exit code 2 and the message for each rejected input."""

from __future__ import annotations

import numpy as np
import pytest

from _helpers import assert_check_rejects, flat, runner
from alcontact.cli import app
from alcontact.fem import meshes

from test_mesh_quality import _FILE_PROBLEM, _moved, _write_msh
from test_preflight import BLOCK


def _tangled(tmp_path):
    good = meshes.rectangle(0, 1, 0, 1, 6, 6)
    bad, _ = _moved(good, (0.5, 0.5), np.array([0.22, 0.1]))
    _write_msh(tmp_path / "tangled.msh", bad, good.boundaries)
    return _FILE_PROBLEM.format(name="tangled.msh")


def _lines(tmp_path):
    good = meshes.rectangle(0, 1, 0, 1, 4, 4)
    _write_msh(tmp_path / "lines.msh", good, good.boundaries, body=False)
    return _FILE_PROBLEM.format(name="lines.msh")


CASES = {
    "h_min": (lambda tmp: BLOCK + "[mesh.refine]\ncenter = [0.0, 0.5]\nh_min = 1e-5\nwidth = 0.5\ndepth = 0.3\n",
              ["mesh.refine.h_min = 1e-05", "coarser mesh"]),
    "cells": (lambda tmp: BLOCK.replace("cells = [8, 2]", "cells = [3000, 3000]"),
              ["mesh.cells = [3000, 3000]", "DOFs"]),
    "friction": (lambda tmp: BLOCK.replace('boundary = "bottom"', 'boundary = "bottom"\nfriction = 0.3').replace(
                     "point = [0.0, 0.0]", "point = [0.0, -1.0]"),
                 ["support:", "translation y", "nothing holds the body", "[[support]]"]),
    # the AMG path lets the touching obstacle hold the body (issue 9), not one out of reach
    "amg": (lambda tmp: (BLOCK + '[solver]\nlinear_solver = "amg"\n').replace("point = [0.0, 0.0]",
                                                                             "point = [0.0, -1.0]"),
            ["support:", "translation y", "nothing holds the body", "[[support]]"]),
    "free": (lambda tmp: BLOCK.replace("components = [0]", "components = [1]"),
             ["support:", "translation x", "nothing holds the body"]),
    "conflict": (lambda tmp: BLOCK + '[[support]]\nboundary = "bottom"\ncomponents = [0]\nvalue = 0.1\n',
                 ["'left'", "'bottom'", "component 0 (x)", "0 on 'left' and 0.1 on 'bottom'"]),
    "E": (lambda tmp: BLOCK.replace("E = 1000.0", "E = 1e308"), ["material.E = 1e+308", "units"]),
    "tangled": (_tangled, ["mesh.file = 'tangled.msh'", "1 inverted element(s)", "element 57 at [0.684444, 0.588889]"]),
    "lines": (_lines, ["mesh.file = 'lines.msh'", "'bottom', 'left', 'right', 'top'", "Physical Surface"]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_check_rejects_with_the_key_and_the_way_out(tmp_path, case):
    make, expected = CASES[case]
    p = tmp_path / "p.toml"
    p.write_text(make(tmp_path))
    result = runner.invoke(app, ["check", str(p)])
    assert_check_rejects(result, expected)


@pytest.mark.parametrize("case", ["h_min", "amg", "tangled"])
def test_run_checks_first(tmp_path, case):
    make, expected = CASES[case]
    p = tmp_path / "p.toml"
    p.write_text(make(tmp_path))
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    msg = flat(result.stderr)
    assert result.exit_code == 2 and expected[0] in msg, result.output
    assert not out.exists()


def test_check_ok_prints_the_size(tmp_path):
    p = tmp_path / "p.toml"
    p.write_text(BLOCK)
    result = runner.invoke(app, ["check", str(p)])
    assert result.exit_code == 0, result.output
    out = flat(result.stdout)
    assert out.startswith("OK held: 2D P1, 54 DOFs") and "size: 54 DOFs, 32 elements, direct linear solver" in out
