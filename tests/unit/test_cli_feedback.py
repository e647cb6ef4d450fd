"""What the CLI tells a user while it works (issue 20, item 5).

- without a terminal (batch job, ``| tee``): one line per load step with the elapsed time and the ETA;
- the progress bar fits 80 columns with the step count and the ETA intact;
- ``alcontact check --quiet``;
- honest time estimates: ``check`` prints the run time calibrated on the examples (the committed
  calibration is within a factor 2 of the measured time on every example, and the code computes
  what the calibration recorded); ``bench --quick`` prints its calibrated time and marks the
  warnings of expected failed solves as expected.

Reaches inside the package: unit tests of the CLI's private progress-bar helpers.
"""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from alcontact.cli import _bar_columns, _LineProgress, app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def flat(text: str) -> str:
    return " ".join(text.split())


def test_run_without_terminal_prints_a_line_per_load_step(tmp_path):
    result = runner.invoke(app, ["run", str(EXAMPLES / "flat_punch.toml"), "--out", str(tmp_path / "o")])
    assert result.exit_code == 0, result.output
    lines = [ln for ln in result.stderr.splitlines() if "done (t =" in ln]
    assert [re.search(r"step (\d)/4", ln).group(1) for ln in lines] == ["1", "2", "3", "4"]
    assert all(re.search(r"elapsed \d+:\d\d:\d\d, ETA \d+:\d\d:\d\d", ln) for ln in lines)


def test_builtin_run_without_terminal_prints_its_phases(tmp_path):
    result = runner.invoke(app, ["run", "--level", "0", "--out", str(tmp_path / "o")])
    assert result.exit_code == 0, result.output
    assert re.search(r"elapsed \d+:\d\d:\d\d: solving hertz-2d", result.stderr)


def test_line_progress_eta_and_throttled_status():
    buf = io.StringIO()
    from rich.console import Console

    now = [0.0]
    p = _LineProgress(Console(file=buf, width=200), "job", every=5.0, clock=lambda: now[0])
    p.step(0, 4, 0.0)
    now[0] = 10.0
    p.step(1, 4, 0.25)  # 10 s per step, 3 left: ETA 30 s
    now[0] = 12.0
    p.status("outer 3")  # 2 s after the last line: not printed
    now[0] = 16.0
    p.status("outer 7")  # 6 s after: printed
    out = buf.getvalue()
    assert "step 1/4 done (t = 0.25), elapsed 0:00:10, ETA 0:00:30" in out
    assert "outer 3" not in out and "elapsed 0:00:16: outer 7" in out


def test_progress_bar_fits_80_columns_with_count_and_eta():
    from rich.console import Console
    from rich.progress import Progress

    buf = io.StringIO()
    con = Console(file=buf, width=80, force_terminal=True, color_system=None)
    bar = Progress(*_bar_columns(80), console=con, auto_refresh=False)
    task = bar.add_task("finite-ironing-friction-with-a-long-name t=0.375", total=120,
                        status="outer 12: penetration 1.23e-05 h, complementarity 2.2e-07, multiplier change 3e-4")
    bar.update(task, completed=37)
    con.print(bar.get_renderable())
    lines = buf.getvalue().rstrip("\n").splitlines()
    assert len(lines) == 1 and len(lines[0]) <= 80
    assert " 37/120 steps " in lines[0] and re.search(r"ETA (-:--:--|\d+:\d\d:\d\d)", lines[0])


def test_check_quiet(tmp_path):
    ok = runner.invoke(app, ["check", "--quiet", str(EXAMPLES / "hertz_2d.toml")])
    assert ok.exit_code == 0 and ok.stdout == "" and ok.stderr == ""
    bad = tmp_path / "bad.toml"
    bad.write_text((EXAMPLES / "hertz_2d.toml").read_text().replace('boundary = "top"', 'boundary = "topp"'))
    res = runner.invoke(app, ["check", "-q", str(bad)])
    assert res.exit_code == 2 and "topp" in flat(res.stderr) and res.stdout == ""


def test_check_prints_the_calibrated_run_time():
    res = runner.invoke(app, ["check", str(EXAMPLES / "hertz_2d.toml")])
    assert res.exit_code == 0
    assert re.search(r"run time: ~[0-9.]+ (s|min) for `alcontact run`", flat(res.stdout))
    assert "calibrated on" in flat(res.stdout) and "uncalibrated" not in res.stdout


def test_committed_calibration_is_within_2x_on_every_example():
    """docs/benchmarks/time_estimates.md: estimate / measured of `alcontact run FILE` in [0.5, 2]."""
    from alcontact.io.preflight import time_calibration

    cal = time_calibration()
    rows = cal["examples"]
    names = {r["file"] for r in rows}
    missing = {p.name for p in EXAMPLES.glob("*.toml")} - names
    assert not missing, f"{missing} not calibrated: run `python benchmarks/time_estimates.py --bench`"
    for r in rows:
        assert 0.5 <= r["estimate_s"] / r["measured_s"] <= 2.0, r


@pytest.mark.parametrize("name", ["hertz_2d", "flat_punch", "cattaneo_mindlin", "finite_ironing_friction"])
def test_check_computes_what_the_calibration_recorded(name):
    from alcontact.io.preflight import check_problem, time_calibration

    row = next(r for r in time_calibration()["examples"] if r["file"] == f"{name}.toml")
    pre = check_problem(EXAMPLES / f"{name}.toml")
    assert pre.run_seconds == pytest.approx(row["estimate_s"], rel=1e-9)


def test_bench_quick_prints_its_time_and_marks_expected_failures(tmp_path):
    """A stand-in nlp suite that logs a failed solve, as the Hock-Schittkowski suite does for hs116."""
    from alcontact.io.preflight import time_calibration
    from alcontact.runner import quick_bench_estimate

    cal = time_calibration()["bench_quick"]
    secs, where = quick_bench_estimate(["nlp"])
    assert secs == pytest.approx(cal["suites_s"]["nlp"] + cal["total_s"] - sum(cal["suites_s"].values()))
    assert "cores" in where
    bench = tmp_path / "bench"
    bench.mkdir()
    (bench / "nlp_hs.py").write_text(
        "import logging\n"
        "def run(out, variants=None):\n"
        "    logging.getLogger('alcontact.optim.fake').warning('minimize failed: no progress')\n"
        "    (out / 'nlp_hs.md').write_text('# nlp\\n')\n")
    res = runner.invoke(app, ["bench", "--quick", "--suite", "nlp", "--benchmarks-dir", str(bench),
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    err = flat(res.stderr)
    assert re.search(r"bench --quick: about \d+:\d\d:\d\d \(h:mm:ss\), measured on", err)
    assert "minimize failed: no progress [expected: the benchmark records failed solves" in err
    assert "estimated" in flat(res.stdout)
    json.dumps(cal)  # the calibration is plain data
