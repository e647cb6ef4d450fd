"""Results folders are whole or absent: staging, --force, foreign files, bad --out, signals.

Reaches inside the package: the CLI's and the results folder's private signal helpers, to test an
interrupted run without sending signals to the test process.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

from _helpers import flat, runner
from alcontact.cli import Interrupted, _raise_interrupted, _signals_raise, app
from alcontact.errors import InputError, OutputExistsError, OutputPathError
from alcontact.io import ResultsFolder, check_output_dir, owned_entries, write_json, write_text_atomic
from alcontact.io.results import _signals_deferred
from alcontact.runner import RESULT_FILES


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _write_run(out: Path, files: dict[str, str], force: bool = False) -> None:
    """A results folder as a run writes it: the files, then summary.json listing them."""
    with ResultsFolder(out, force) as rf:
        for name, text in files.items():
            (rf.path / name).parent.mkdir(exist_ok=True)
            write_text_atomic(rf.path / name, text)
        listed = sorted({n.split("/")[0] + "/" if "/" in n else n for n in files})
        write_json(rf.path / "summary.json", {"files": [*listed, "summary.json"]})


def _stepped_run(out: Path) -> None:
    _write_run(out, {"solution.vtu": "old", "solution.pvd": "old", "steps/solution_0001.vtu": "old",
                     "load_displacement.png": "old", "report.md": "old"})


# ------------------------------------------------------------------ whole or absent
def test_new_folder_appears_only_at_the_end(tmp_path):
    out = tmp_path / "a" / "res"
    with ResultsFolder(out) as rf:
        write_text_atomic(rf.path / "solution.vtu", "new")
        assert not out.exists()  # nothing at the target while writing
        assert rf.path.parent == out.parent and rf.path.name.startswith(".res.partial-")
    assert rf.committed and sorted(p.name for p in out.iterdir()) == ["solution.vtu"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["res"]  # staging folder gone


def test_failure_while_writing_leaves_no_trace(tmp_path):
    out = tmp_path / "res"
    with pytest.raises(RuntimeError, match="disk full") as info:
        with ResultsFolder(out):
            raise RuntimeError("disk full")
    assert info.value.results_state == "unchanged"
    assert list(tmp_path.iterdir()) == []


def test_interrupt_during_force_keeps_the_old_results(tmp_path):
    """The tester's case: interrupted after --force, the old summary.json never sits beside new files."""
    out = tmp_path / "res"
    _stepped_run(out)
    before = _snapshot(out)
    with pytest.raises(KeyboardInterrupt):
        with ResultsFolder(out, force=True) as rf:
            write_text_atomic(rf.path / "solution.vtu", "new")
            raise KeyboardInterrupt
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_force_replaces_the_whole_owned_set(tmp_path):
    """A single solve with --force over a stepped run leaves no steps/, solution.pvd, load_displacement.png."""
    out = tmp_path / "res"
    _stepped_run(out)
    os.chmod(out, 0o750)
    _write_run(out, {"solution.vtu": "new"}, force=True)
    assert sorted(p.name for p in out.iterdir()) == ["solution.vtu", "summary.json"]
    assert (out / "solution.vtu").read_text() == "new"
    assert oct(out.stat().st_mode & 0o777) == oct(0o750)  # the folder keeps its permissions
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_force_keeps_files_it_does_not_own(tmp_path):
    out = tmp_path / "res"
    _stepped_run(out)
    (out / "notes.txt").write_text("mine")
    (out / "mine").mkdir()
    (out / "mine" / "data.csv").write_text("1,2")
    assert owned_entries(out) == (["load_displacement.png", "report.md", "solution.pvd", "solution.vtu",
                                   "steps/", "summary.json"], ["mine/", "notes.txt"])
    _write_run(out, {"solution.vtu": "new"}, force=True)
    assert sorted(p.name for p in out.iterdir()) == ["mine", "notes.txt", "solution.vtu", "summary.json"]
    assert (out / "notes.txt").read_text() == "mine" and (out / "mine" / "data.csv").read_text() == "1,2"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_force_refuses_to_overwrite_a_file_it_did_not_write(tmp_path):
    out = tmp_path / "res"
    out.mkdir()
    (out / "report.md").write_text("my own report")  # no summary.json: not from an alcontact run
    with pytest.raises(OutputExistsError) as info:
        check_output_dir(out, force=True)
    msg = str(info.value)
    assert "'report.md'" in msg and str(out) in msg and "move it away" in msg
    with pytest.raises(OutputExistsError):
        _write_run(out, {"report.md": "new"}, force=True)
    assert (out / "report.md").read_text() == "my own report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_a_damaged_manifest_owns_nothing_outside_the_folder(tmp_path):
    out = tmp_path / "res"
    out.mkdir()
    (tmp_path / "precious.txt").write_text("keep")
    (out / "summary.json").write_text(json.dumps({"files": ["../precious.txt", "/etc/passwd", "solution.vtu"]}))
    (out / "solution.vtu").write_text("old")
    assert owned_entries(out) == (["solution.vtu", "summary.json"], [])
    _write_run(out, {"pressure.png": "new"}, force=True)
    assert (tmp_path / "precious.txt").read_text() == "keep"
    assert sorted(p.name for p in out.iterdir()) == ["pressure.png", "summary.json"]


def test_temporary_files_of_an_old_interrupted_write_do_not_block_a_plain_run(tmp_path):
    """Older versions left ``.solution.<random>.tmp.vtu`` after SIGTERM; a plain re-run was refused."""
    out = tmp_path / "res"
    out.mkdir()
    (out / ".solution.k2j3h4.tmp.vtu").write_text("partial")
    assert check_output_dir(out, force=False) == out
    _write_run(out, {"solution.vtu": "new"})
    assert sorted(p.name for p in out.iterdir()) == ["solution.vtu", "summary.json"]


def test_non_empty_folder_still_needs_force(tmp_path):
    out = tmp_path / "res"
    _write_run(out, {"solution.vtu": "old"})
    with pytest.raises(OutputExistsError, match="--force"):
        _write_run(out, {"solution.vtu": "new"})
    assert (out / "solution.vtu").read_text() == "old"


def test_existing_folder_is_staged_inside_it_so_its_parent_may_be_read_only(tmp_path, monkeypatch):
    """E.g. a mounted volume or ``--out .``: the folder itself is never renamed."""
    out = tmp_path / "res"
    _stepped_run(out)
    inode = out.stat().st_ino
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode, **kw: False if Path(p) == tmp_path else real(p, mode, **kw))
    with ResultsFolder(out, force=True) as rf:
        assert rf.path.parent == out and rf.path.name.startswith(".alcontact-partial-")
        write_text_atomic(rf.path / "solution.vtu", "new")
        write_json(rf.path / "summary.json", {"files": ["solution.vtu", "summary.json"]})
    assert out.stat().st_ino == inode
    assert sorted(p.name for p in out.iterdir()) == ["solution.vtu", "summary.json"]


def test_out_dot_in_the_current_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "input.toml").write_text("mine")
    _write_run(Path("."), {"solution.vtu": "new"}, force=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["input.toml", "solution.vtu", "summary.json"]
    _write_run(Path("."), {"pressure.png": "new"}, force=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["input.toml", "pressure.png", "summary.json"]


def test_staging_folder_of_a_killed_run_is_cleaned_up(tmp_path):
    out = tmp_path / "res"
    (out / ".alcontact-partial-dead1234").mkdir(parents=True)
    (out / ".alcontact-partial-dead1234" / "solution.vtu").write_text("partial")
    assert check_output_dir(out, force=False) == out  # only leftovers: no --force needed
    _write_run(out, {"solution.vtu": "new"})
    assert sorted(p.name for p in out.iterdir()) == ["solution.vtu", "summary.json"]


# ------------------------------------------------------------------ --out that cannot be created
def test_out_under_a_regular_file(tmp_path):
    f = tmp_path / "data.txt"
    f.write_text("x")
    with pytest.raises(OutputPathError) as info:
        check_output_dir(f / "sub" / "results")
    msg = str(info.value)
    assert isinstance(info.value, InputError)
    assert f"'{f}' is a file" in msg and "choose an --out outside it" in msg
    result = runner.invoke(app, ["run", "--out", str(f / "results"), "--level", "0"])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert f"'{f}' is a file" in flat(result.stderr)
    assert f.read_text() == "x"


def test_out_in_a_read_only_place_is_checked_before_solving(tmp_path, monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode, **kw: False if Path(p) == ro else real(p, mode, **kw))
    with pytest.raises(OutputPathError) as info:
        check_output_dir(ro / "results")
    assert f"cannot write in '{ro}'" in str(info.value) and "writable" in str(info.value)
    result = runner.invoke(app, ["run", "--out", str(ro / "results"), "--level", "0"])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert f"cannot write in '{ro}'" in flat(result.stderr)


def test_failing_staging_folder_becomes_a_clear_error(tmp_path, monkeypatch):
    import tempfile

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(tempfile, "mkdtemp", refuse)
    with pytest.raises(OutputPathError, match="cannot create a folder in .*Permission denied.*writable"):
        with ResultsFolder(tmp_path / "res"):
            pass  # pragma: no cover - not reached
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_folder_for_real(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    os.chmod(ro, 0o555)
    try:
        with pytest.raises(OutputPathError, match="cannot write"):
            check_output_dir(ro / "results")
    finally:
        os.chmod(ro, 0o755)


# ------------------------------------------------------------------ signals
@pytest.fixture
def python_sigint():
    """Python's own SIGINT handler for the test (pytest-xdist workers ignore SIGINT)."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be set in the main thread")
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


def test_signals_are_deferred_during_the_renames(python_sigint):
    seen = []
    with pytest.raises(KeyboardInterrupt):
        with _signals_deferred():
            signal.raise_signal(signal.SIGINT)
            seen.append("still running")  # the signal waits for the end of the block
    assert seen == ["still running"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_cli_handler_turns_signals_into_interrupted(python_sigint):
    with pytest.raises(Interrupted) as info:
        _raise_interrupted(signal.SIGTERM, None)
    assert info.value.signum == signal.SIGTERM and isinstance(info.value, KeyboardInterrupt)
    old = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Interrupted):
        with _signals_raise():
            signal.raise_signal(signal.SIGTERM)
    assert signal.getsignal(signal.SIGTERM) == old


def test_an_ignored_sigint_stays_ignored():
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be set in the main thread")
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with _signals_raise():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
            assert signal.getsignal(signal.SIGTERM) is _raise_interrupted
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, old)


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_cli_reports_an_interrupt_with_its_exit_code(tmp_path, monkeypatch, signum, code):
    import alcontact.app as app_mod

    def interrupted(*args, **kwargs):
        raise Interrupted(signum)

    monkeypatch.setattr(app_mod, "run_problem", interrupted)
    out = tmp_path / "res"
    result = runner.invoke(app, ["run", "--out", str(out), "--quiet"])
    assert result.exit_code == code
    msg = flat(result.stderr)
    assert f"interrupted by {signal.Signals(signum).name}" in msg and f"'{out}' was left as it was" in msg


_SCRIPT = textwrap.dedent("""
    import pathlib, sys, time
    import alcontact.viz as viz

    ready = pathlib.Path(sys.argv[1])
    original = viz.save_convergence_plot

    def slow(*args, **kwargs):  # pause while the results are being written
        path = original(*args, **kwargs)
        ready.write_text("writing")
        time.sleep(120)
        return path

    viz.save_convergence_plot = slow
    from alcontact.cli import main
    main(sys.argv[2:])
""")


@pytest.mark.slow  # starts a Python process that imports the package and solves (5-10 s each)
@pytest.mark.parametrize("signum, existing", [(signal.SIGTERM, True), (signal.SIGINT, False)])
def test_signal_while_writing_leaves_no_temporary_files(tmp_path, signum, existing):
    """A real signal sent to ``alcontact run`` while it writes: exit 128 + signum, a message, no partial files.

    The child pauses inside the writing of the results (after some files of
    the new set exist) and tells the test so through a file, so the signal
    always arrives at that point.
    """
    work = tmp_path / "work"
    work.mkdir()
    out = work / "res"
    if existing:
        _stepped_run(out)
    before = _snapshot(out) if existing else None
    script, ready = tmp_path / "child.py", tmp_path / "ready"
    script.write_text(_SCRIPT)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(Path(__file__).parents[2] / "src"),
                                                                      os.environ.get("PYTHONPATH")])),
           "COLUMNS": "400", "NO_COLOR": "1"}
    cmd = [sys.executable, str(script), str(ready), "run", "--out", str(out), "--level", "0", "--quiet",
           *(["--force"] if existing else [])]
    # the child gets the default SIGINT disposition (a pytest-xdist worker ignores SIGINT, and
    # ignored signals are inherited; alcontact leaves ignored signals ignored)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 300
        while not ready.exists() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert ready.exists(), proc.communicate(timeout=60)
        proc.send_signal(signum)
        stdout, stderr = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 128 + signum, stderr
    msg = flat(stderr)
    assert f"interrupted by {signal.Signals(signum).name}" in msg and "left as it was" in msg
    assert "Traceback" not in stderr
    if existing:
        assert _snapshot(out) == before
        assert sorted(p.name for p in work.iterdir()) == ["res"]
    else:
        assert list(work.iterdir()) == []


# ------------------------------------------------------------------ the CLI over an earlier stepped run
def test_cli_force_over_a_stepped_run_leaves_exactly_its_files(tmp_path):
    out = tmp_path / "results"
    _stepped_run(out)
    (out / "notes.txt").write_text("mine")
    result = runner.invoke(app, ["run", "--out", str(out), "--level", "0", "--force", "--quiet"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == sorted([*RESULT_FILES, "notes.txt"])
    s = json.loads((out / "summary.json").read_text())
    assert s["files"] == list(RESULT_FILES) and s["level"] == 0
