"""Issue 19: every bad input and fault gets a clean answer (round 3), one test per numbered case.

Each test is the reproducer of the issue in a few lines and checks the clean answer:
``alcontact check`` / ``run`` exit 2 with an ``error:`` naming the key, value or file and
the way out, no traceback, nothing solved; for faults a clean message and an intact
results folder.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from _gmsh import SQUARE_PROBLEM, square, square_msh
from _helpers import flat, runner
from alcontact.cli import app

ROOT = Path(__file__).resolve().parents[2]
#: the 2D Hertz example on a coarse mesh (about 100 DOFs)
HERTZ = re.sub(r"h_min = [0-9.]+", "h_min = 0.5", (ROOT / "examples" / "hertz_2d.toml").read_text()).replace(
    "cells = [8, 8]", "cells = [4, 4]")


def _write(tmp_path: Path, text: str, name: str = "p.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _refused(result, *texts: str) -> str:
    """Exit 2, an ``error:`` line, no traceback, and every text of ``texts`` in the message."""
    msg = flat(result.stderr)
    assert result.exit_code == 2, result.output
    assert "error:" in msg and "Traceback" not in result.output, result.output
    for t in texts:
        assert t in msg, (t, msg)
    return msg


def _check_and_run_refuse(tmp_path: Path, p: Path, *texts: str) -> None:
    """``check`` refuses ``p`` naming ``texts``, and ``run`` refuses it the same way before solving."""
    msg = _refused(runner.invoke(app, ["check", str(p)]), *texts)
    assert "nothing was solved" in msg
    out = tmp_path / "out"
    _refused(runner.invoke(app, ["run", str(p), "--out", str(out), "-q"]), *texts)
    assert not out.exists()


# ---------------------------------------------------------------------------------------------- case 1
@pytest.mark.parametrize("deep", ["x = " + "[" * 600 + "]" * 600, "x = " + "{a = " * 600 + "1" + "}" * 600])
def test_case_1_deeply_nested_toml_is_a_clean_error(tmp_path, deep):
    """Arrays or inline tables nested 600 levels: ``check_problem``'s own parse gave a RecursionError."""
    p = _write(tmp_path, deep + "\n" + HERTZ)
    _check_and_run_refuse(tmp_path, p, "nested too deeply", "Check the brackets")


# ---------------------------------------------------------------------------------------------- case 2
@pytest.mark.parametrize("names, texts", [
    ([(1, 2, "right"), (1, 3, "bottom"), (1, 4, "top"), (2, 5, "body")], ["tag 1", "no name", "Physical Curve"]),
    ([(1, 1, "left"), (1, 2, "left"), (1, 3, "bottom"), (1, 4, "top"), (2, 5, "body")],
     ["'left'", "2 groups", "tag 1 (dimension 1) and tag 2 (dimension 1)"]),
    ([(1, 1, "left"), (1, 2, "right"), (1, 3, "bottom"), (1, 4, "top"), (2, 4, "body")],
     ["tag 4", "'body', 'top'", "different tags"]),
], ids=["unnamed", "same-name", "same-tag"])
def test_case_2_gmsh_physical_groups_without_one_name_each(tmp_path, names, texts):
    """A physical tag without a name, or two groups with one name: a TypeError in fem/meshes.py before."""
    text = square_msh(names=names)
    if names[-1] == (2, 4, "body"):
        text = text.replace(" 2 5 5 ", " 2 4 4 ")  # the triangles in the group of tag 4
    (tmp_path / "body.msh").write_text(text)
    _check_and_run_refuse(tmp_path, _write(tmp_path, SQUARE_PROBLEM), "mesh.file = 'body.msh'", *texts)


# ---------------------------------------------------------------------------------------------- case 4
def test_case_4_reference_radius_5e_324_is_refused_by_check(tmp_path):
    """``reference.radius = 5e-324`` passed ``check``; ``run`` divided by zero in problems/hertz.py."""
    head, ref = HERTZ.split("[reference]")
    p = _write(tmp_path, head + "[reference]" + ref.replace("radius = 10.0", "radius = 5e-324"))
    _check_and_run_refuse(tmp_path, p, "reference.radius = 5e-324", "[1e-100, 1e+100]")


# ---------------------------------------------------------------------------------------------- case 5
def test_case_5_svk_ironing_in_4_steps_has_no_overflow(tmp_path):
    """Saint Venant-Kirchhoff ironing in 4 steps: ``dlam**2`` overflowed (OverflowError) in the multiplier update.

    Reference: the run ends; it converges (every step) with the equilibrium residual the
    summary reports below 1e-8 (relative).
    """
    import json

    text = (ROOT / "examples" / "finite_ironing.toml").read_text()
    text = text.replace('"neo-hookean"', '"saint-venant-kirchhoff"').replace("steps = 8", "steps = 4")
    p = _write(tmp_path, text)
    result = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "out"), "-q"])
    assert "Traceback" not in result.output and result.exception is None or isinstance(result.exception,
                                                                                        SystemExit), result.output
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["status"] == "converged", s["message"]
    assert s["equilibrium_residual"] < 1e-8


# ---------------------------------------------------------------------------------------------- case 9
def test_case_9_coordinates_near_1e200_are_refused_by_check(tmp_path):
    pts, _, _ = square()
    (tmp_path / "body.msh").write_text(square_msh(points=pts * 1e200))
    _check_and_run_refuse(tmp_path, _write(tmp_path, SQUARE_PROBLEM), "mesh.file = 'body.msh'", "1e+200",
                          "other units")


# ---------------------------------------------------------------------------------------------- case 10
def test_case_10_a_2d_mesh_off_the_plane_is_refused(tmp_path):
    """z != 0 varying over a triangle mesh was silently dropped."""
    pts, _, _ = square()
    pts[:, 2] = 0.3 * pts[:, 0]  # a tilted plane
    (tmp_path / "body.msh").write_text(square_msh(points=pts))
    _check_and_run_refuse(tmp_path, _write(tmp_path, SQUARE_PROBLEM), "mesh.file = 'body.msh'",
                          "not in one plane z = const", "z = 0")


def test_case_10_a_2d_mesh_in_a_plane_z_const_is_flattened_with_a_warning(tmp_path, caplog):
    from alcontact.fem import meshes

    pts, _, _ = square()
    pts[:, 2] = 5.0
    (tmp_path / "body.msh").write_text(square_msh(points=pts))
    with caplog.at_level("WARNING", logger="alcontact"):
        m = meshes.read(tmp_path / "body.msh")
    assert m.p.shape == (2, 25) and "plane z = 5" in caplog.text


# ---------------------------------------------------------------------------------------------- case 12
def test_case_12_nan_coordinates_are_named_as_such(tmp_path):
    """NaN node coordinates were blamed on ``mesh.order``."""
    pts, _, _ = square()
    pts[7, 1] = np.nan
    (tmp_path / "body.msh").write_text(square_msh(points=pts))
    msg = _refused(runner.invoke(app, ["check", str(_write(tmp_path, SQUARE_PROBLEM))]), "mesh.file = 'body.msh'",
                   "not finite numbers", "nan")
    assert "mesh.order" not in msg


def test_case_12_duplicate_elements_are_not_called_inverted(tmp_path):
    _, tri, _ = square()
    (tmp_path / "body.msh").write_text(square_msh(triangles=np.vstack([tri, tri[3:5][:, ::-1]])))
    msg = _refused(runner.invoke(app, ["check", str(_write(tmp_path, SQUARE_PROBLEM))]), "mesh.file = 'body.msh'",
                   "2 duplicate triangle element(s)", "remove the duplicates")
    assert "inverted" not in msg


# ---------------------------------------------------------------------------------------------- case 3
def test_case_3_an_output_folder_name_over_255_bytes_is_refused_by_check(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    p = _write(tmp_path, HERTZ.replace('folder = "results-hertz-2d"', f'folder = "{"a" * 300}"'))
    _check_and_run_refuse(tmp_path, p, "output.folder", "300 bytes long", "choose a shorter name")
    _refused(runner.invoke(app, ["run", "--out", str(tmp_path / ("b" * 300)), "-q", "--level", "0"]),
             "300 bytes long", "choose a shorter name")
    assert sorted(q.name for q in tmp_path.iterdir()) == ["p.toml"]


# ---------------------------------------------------------------------------------------------- case 6
def _cli(*args: str, cwd: Path):
    import os
    import subprocess
    import sys

    env = {**os.environ, "COLUMNS": "400", "NO_COLOR": "1"}
    return subprocess.Popen([sys.executable, "-c", "from alcontact.cli import main; main()", *args], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)


def test_case_6_a_second_run_into_a_folder_in_use_is_refused(tmp_path):
    """While a run holds the results folder (its lock), another ``run --force`` into it exits 2 "in use"."""
    from alcontact.io.results import output_lock

    p = _write(tmp_path, HERTZ)
    first = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "out"), "-q"])
    assert first.exit_code == 0, first.output
    before = {q.name: q.read_bytes() for q in (tmp_path / "out").iterdir()}
    with output_lock(tmp_path / "out") as lock:
        assert lock is not None and lock.exists()
        proc = _cli("run", str(p), "--out", "out", "--force", "-q", cwd=tmp_path)
        _, err = proc.communicate(timeout=120)
    msg = flat(err)
    assert proc.returncode == 2 and "Traceback" not in err, err
    assert "results folder 'out' is in use" in msg and "choose another --out" in msg
    assert {q.name: q.read_bytes() for q in (tmp_path / "out").iterdir()} == before  # intact
    assert not lock.exists()  # removed on release


def test_case_6_two_force_runs_at_once_one_wins(tmp_path):
    """Two ``run --force`` into one folder at once: each exits 0 or 2 ("in use"), never a traceback; the folder
    is whole."""
    import json

    p = _write(tmp_path, HERTZ)
    procs = [_cli("run", str(p), "--out", "out", "--force", "-q", cwd=tmp_path) for _ in range(2)]
    outs = [(proc.wait(timeout=180), proc.communicate()[1]) for proc in procs]
    for code, err in outs:
        assert code in (0, 2) and "Traceback" not in err, err
        assert code == 0 or "is in use" in flat(err)
    assert 0 in [c for c, _ in outs]
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert sorted(s["files"]) == sorted(q.name for q in (tmp_path / "out").iterdir())
    assert sorted(q.name for q in tmp_path.iterdir()) == ["out", "p.toml"]  # no staging folder, no lock file


def test_case_6_a_full_disk_is_a_clean_error_and_the_folder_is_intact(tmp_path, monkeypatch):
    import errno

    import alcontact.app.pipeline as pipeline_mod

    p = _write(tmp_path, HERTZ)
    assert runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "out"), "-q"]).exit_code == 0
    before = {q.name: q.read_bytes() for q in (tmp_path / "out").iterdir()}

    def full(folder, *args, **kwargs):
        (Path(folder) / "solution.vtu").write_text("partial")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(pipeline_mod, "write_setup_results", full)
    msg = _refused(runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "out"), "-q", "--force"]),
                   "No space left on device", "left as it was", "Free space")
    assert "Traceback" not in msg
    assert {q.name: q.read_bytes() for q in (tmp_path / "out").iterdir()} == before


# ---------------------------------------------------------------------------------------------- case 11
@pytest.mark.parametrize("link", ["dangling", "loop"])
def test_case_11_a_bad_symlink_as_out_is_refused_before_solving(tmp_path, link, monkeypatch):
    import alcontact.contact as contact_mod

    if link == "dangling":
        (tmp_path / "out").symlink_to(tmp_path / "nowhere" / "x")
    else:
        (tmp_path / "out").symlink_to(tmp_path / "other")
        (tmp_path / "other").symlink_to(tmp_path / "out")
    monkeypatch.setattr(contact_mod, "solve", lambda *a, **k: pytest.fail("solved before refusing --out"))
    p = _write(tmp_path, HERTZ)
    _refused(runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "out"), "-q"]), "symbolic link",
             "remove the link")


def test_case_11_dot_dot_in_out_leaves_no_stray_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    p = _write(tmp_path, HERTZ)
    result = runner.invoke(app, ["run", str(p), "--out", "a/b/../c", "-q"])
    assert result.exit_code == 0, result.output
    assert sorted(q.name for q in (tmp_path / "a").iterdir()) == ["c"]
    assert (tmp_path / "a" / "c" / "summary.json").is_file()


@pytest.mark.parametrize("exists", [False, True])
def test_case_11_stale_partial_folders_of_killed_runs_are_removed(tmp_path, exists, caplog):
    """``.out.partial-*`` beside (and ``.alcontact-partial-*`` inside) left by a SIGKILL: the next run removes them."""
    p = _write(tmp_path, HERTZ)
    if exists:
        assert runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "out"), "-q"]).exit_code == 0
        (tmp_path / "out" / ".alcontact-partial-k1ll3d00" / "steps").mkdir(parents=True)
    (tmp_path / ".out.partial-k1ll3d00").mkdir()
    (tmp_path / ".out.partial-k1ll3d00" / "solution.vtu").write_text("half")
    args = ["run", str(p), "--out", str(tmp_path / "out"), "-v"] + (["--force"] if exists else [])
    with caplog.at_level("INFO", logger="alcontact"):
        assert runner.invoke(app, args).exit_code == 0
    assert sorted(q.name for q in tmp_path.iterdir()) == ["out", "p.toml"]
    assert not [q for q in (tmp_path / "out").iterdir() if q.name.startswith(".")]
    assert "staging folder(s) of interrupted runs" in caplog.text


# ---------------------------------------------------------------------------------------------- case 7
@pytest.mark.parametrize("kwargs, texts", [
    (dict(level=1.5), ["hertz_2d: level = 1.5", "whole number"]),
    (dict(level="1"), ["hertz_2d: level = '1'", "not a string"]),
    (dict(level=-1), ["hertz_2d: level = -1", "[0, 5]"]),
    (dict(level=6), ["hertz_2d: level = 6", "[0, 5]"]),
])
def test_case_7_hertz_2d_level_of_a_wrong_type_or_range(kwargs, texts):
    """``hertz_2d(level=1.5 / "1")`` gave a TypeError from deep inside; ``level=-1`` built the finest level."""
    from alcontact.errors import InputError
    from alcontact.problems.hertz import hertz_2d

    with pytest.raises(InputError) as info:
        hertz_2d(**kwargs)
    for t in texts:
        assert t in str(info.value)


@pytest.mark.parametrize("field, value, texts", [
    ("obstacle", None, ["obstacle = None", "obstacles.make"]),
    ("supports", "Support", ["supports = Support(...)", "wrap the single item in a list"]),
    ("loads", "Pressure", ["loads = Pressure(...)", "wrap the single item in a list"]),
])
def test_case_7_contact_problem_with_a_wrong_field(field, value, texts):
    """``ContactProblem(obstacle=None)`` and a bare Support/Pressure where a list is expected: AttributeError before."""
    import dataclasses

    from alcontact.contact import Pressure, Support
    from alcontact.errors import InputError
    from alcontact.problems.hertz import hertz_2d

    value = {"Support": Support("bottom"), "Pressure": Pressure("top", 1.0)}.get(value, value)
    with pytest.raises(InputError) as info:
        dataclasses.replace(hertz_2d(level=0), **{field: value})
    for t in texts:
        assert t in str(info.value)


# ---------------------------------------------------------------------------------------------- case 8
@pytest.mark.parametrize("loading", ["", "[loading]\nsteps = 8\nt_end = 1e6\n"], ids=["no-loading", "huge-t_end"])
def test_case_8_a_tangential_support_before_contact_is_refused_by_check(tmp_path, loading):
    """Cattaneo-Mindlin without ``[loading]`` (one step at t = 1) or with ``t_end = 1e6``: ``run`` exited 2 after
    ``check`` said OK."""
    text = (ROOT / "examples" / "cattaneo_mindlin.toml").read_text()
    text = text.replace("h_min = 0.125", "h_min = 1.0").replace("cells = [16, 8]", "cells = [8, 4]")
    text = text.replace("[loading]\nsteps = 8\n", loading)
    _check_and_run_refuse(tmp_path, _write(tmp_path, text), "loading:", "support[2]", "already non-zero at the "
                          "first step time", "start the tangential ramp at 0")


def test_case_8_the_example_still_passes_check(tmp_path):
    text = (ROOT / "examples" / "cattaneo_mindlin.toml").read_text()
    text = text.replace("h_min = 0.125", "h_min = 1.0").replace("cells = [16, 8]", "cells = [8, 4]")
    result = runner.invoke(app, ["check", str(_write(tmp_path, text))])
    assert result.exit_code == 0, result.output


# ---------------------------------------------------------------------------------------------- case 9
def _two_squares(tmp_path: Path, shift: float) -> Path:
    from _gmsh import msh_text

    pts, tri, lines = square()
    order = ["left", "right", "bottom", "top"]
    blocks = [("line", k + 1, lines[n]) for k, n in enumerate(order)]
    blocks.append(("triangle", 5, np.vstack([tri, tri + len(pts)])))  # a second square, no boundary groups
    names = [(1, k + 1, n) for k, n in enumerate(order)] + [(2, 5, "body")]
    (tmp_path / "body.msh").write_text(msh_text(np.vstack([pts, pts + [shift, 0.0, 0.0]]), blocks, names))
    return _write(tmp_path, SQUARE_PROBLEM)


def test_case_9_a_disconnected_unsupported_piece_is_refused_by_check(tmp_path):
    """A second, unsupported piece of the mesh: ``run`` exited 2 on a singular matrix after ``check`` said OK."""
    _check_and_run_refuse(tmp_path, _two_squares(tmp_path, 2.0), "mesh:", "2 disconnected pieces",
                          "nothing holds piece 2", "[2, 3] x [0, 1]", "add a [[support]]")


def test_case_12_runtime_warnings_do_not_leak_to_stderr(tmp_path):
    """NumPy/Matplotlib RuntimeWarnings printed raw on stderr; the CLI now turns them into debug log records.

    In a subprocess: pytest captures warnings itself, so in-process they never reach stderr.
    """
    import subprocess
    import sys

    script = "\n".join([
        "import sys, warnings, numpy as np",
        "import alcontact.app.pipeline as r",
        "from alcontact.cli import main",
        "orig = r.write_setup_results",
        "def noisy(*a, **k):",
        "    np.exp(np.array([1000.0]))  # NumPy: RuntimeWarning: overflow encountered in exp",
        "    warnings.warn('Attempting to set identical low and high ylims', UserWarning)  # as Matplotlib does",
        "    return orig(*a, **k)",
        "r.write_setup_results = noisy",
        "main(sys.argv[1:])",
    ])
    p = _write(tmp_path, HERTZ)
    proc = subprocess.run([sys.executable, "-c", script, "run", str(p), "--out", str(tmp_path / "out"), "-v"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "out" / "summary.json").is_file()
    assert "Warning" not in proc.stderr and "overflow" not in proc.stderr and "ylims" not in proc.stderr, proc.stderr
