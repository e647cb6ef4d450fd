"""``alcontact`` command line: run, list, help, exit codes, results folder."""

from __future__ import annotations

import json

import pytest

from _helpers import flat, runner
from alcontact.cli import app, main
from alcontact.io import POINT_FIELDS, SUMMARY_KEYS
from alcontact.runner import RESULT_FILES

# wide console: rich would otherwise wrap long paths in messages
@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "results"
    # level 1 (about 4.7k DOFs): level 0 is too coarse for a 5 % peak pressure
    result = runner.invoke(app, ["run", "--out", str(out), "--level", "1"])
    return out, result


def test_run_writes_the_results_folder(first_run):
    out, result = first_run
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == sorted(RESULT_FILES)  # no temp files left
    assert all((out / name).stat().st_size > 0 for name in RESULT_FILES)
    assert (out / "pressure.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (out / "history.csv").read_text().splitlines()[0].startswith("k,penetration,complementarity")
    assert "converged" in result.stdout and "peak pressure" in result.stdout


def test_summary_json_keys_and_values(first_run):
    out, _ = first_run
    s = json.loads((out / "summary.json").read_text())
    missing = set(SUMMARY_KEYS) - set(s)
    assert not missing
    assert s["status"] == "converged"
    assert s["algorithm"] == "simo-laursen" and s["penalty"] == "rockafellar"
    assert s["dofs"] > 0 and s["outer_iterations"] >= 1 and s["linear_solves"] >= 1
    assert s["newton_iterations"] >= s["outer_iterations"]
    assert 0 < s["linear_solve_time_s"] <= s["wall_time_s"]
    assert s["contact_half_width"] == pytest.approx(s["contact_half_width_exact"], rel=0.05)
    assert s["peak_pressure"] == pytest.approx(s["peak_pressure_exact"], rel=0.05)
    assert s["total_contact_force"] == pytest.approx(2 * s["model_contact_force"])
    assert s["problem"] == "hertz-2d" and s["level"] == 1


def test_vtu_has_the_point_fields(first_run):
    import meshio

    out, _ = first_run
    mesh = meshio.read(out / "solution.vtu")
    assert set(POINT_FIELDS) <= set(mesh.point_data)


def test_existing_folder_needs_force(first_run):
    out, _ = first_run
    before = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in out.iterdir()}
    result = runner.invoke(app, ["run", "--out", str(out), "--level", "0"])
    assert result.exit_code == 2
    assert result.exception is None or isinstance(result.exception, SystemExit)
    msg = flat(result.stderr)
    assert str(out) in msg and "--force" in msg and "Traceback" not in result.output
    after = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in out.iterdir()}
    assert after == before

    (out / "notes.txt").write_text("mine")
    result = runner.invoke(app, ["run", "--out", str(out), "--level", "0", "--force", "--quiet"])
    assert result.exit_code == 0, result.output
    assert result.stdout == ""  # --quiet
    s = json.loads((out / "summary.json").read_text())
    assert s["level"] == 0 and s["status"] == "converged"
    assert (out / "notes.txt").read_text() == "mine"  # only our files are replaced
    assert sorted(p.name for p in out.iterdir()) == sorted([*RESULT_FILES, "notes.txt"])


def test_non_convergence_exits_1_with_advice(tmp_path):
    out = tmp_path / "res"
    result = runner.invoke(app, ["run", "--out", str(out), "--level", "0", "--maxiter", "1", "--quiet"])
    assert result.exit_code == 1
    msg = flat(result.stderr)
    assert "not converged (maxiter)" in msg and "what to try" in msg
    assert json.loads((out / "summary.json").read_text())["status"] == "maxiter"


@pytest.mark.parametrize(
    "args, text",
    [
        (["--algorithm", "simo-laursn"], "Did you mean 'simo-laursen'"),
        (["--algorithm", "family-p", "--penalty", "nope"], "unknown contact penalty"),
        (["--problem", "hertz-9d"], "unknown problem"),
        (["--level", "9"], "out of range"),
        (["--quiet", "--verbose"], "exclude each other"),
    ],
)
def test_bad_input_exits_2_without_traceback(tmp_path, args, text):
    out = tmp_path / "res"
    result = runner.invoke(app, ["run", "--out", str(out), *args])
    assert result.exit_code == 2
    assert text in flat(result.stderr) and "Traceback" not in result.output
    assert not out.exists()  # checked before anything is written


def test_help():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0 and "run" in result.output and "list" in result.output
    result = runner.invoke(app, ["run", "--help"])
    assert result.exit_code == 0
    for opt in ("--out", "--algorithm", "--penalty", "--level", "--force", "--quiet", "--verbose"):
        assert opt in result.output


def test_list_prints_the_registered_names():
    from alcontact import penalties
    from alcontact.contact import available_algorithms, obstacles

    result = runner.invoke(app, ["list"])
    assert result.exit_code == 0
    for name in [*available_algorithms(), *penalties.available(), *obstacles.available(), "hertz-2d", "hertz-3d"]:
        assert name in result.output
    result = runner.invoke(app, ["list", "algorithms"])
    assert "simo-laursen" in result.output and "exp-met1" not in result.output


def test_main_entry_point(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert "alcontact" in capsys.readouterr().out


def test_run_problem_in_python_without_files():
    from alcontact.runner import run_problem

    sol, summary = run_problem(level=0)
    assert summary["status"] == "converged" and sol.result.success
    assert summary["dofs"] == sol.u.size


# ------------------------------------------------------------------ problem files, check, bench, docs
from pathlib import Path  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_run_problem_file_with_load_steps_writes_series_and_report(tmp_path):
    out = tmp_path / "res"
    result = runner.invoke(app, ["run", str(EXAMPLES / "sliding_block.toml"), "--out", str(out)])
    assert result.exit_code == 0, result.output
    names = {p.name for p in out.iterdir()}
    assert {"solution.vtu", "solution.pvd", "steps", "steps.csv", "pressure.png", "convergence.png",
            "load_displacement.png", "report.md", "summary.json"} <= names
    assert not any(n.startswith(".") for n in names)  # no temporary files left
    s = json.loads((out / "summary.json").read_text())
    assert set(SUMMARY_KEYS) <= set(s) and s["status"] == "converged" and s["load_steps"] == 8
    assert len(list((out / "steps").glob("solution_*.vtu"))) == 8
    assert (out / "solution.pvd").read_text().count("<DataSet") == 8
    import meshio

    from alcontact.io import FRICTION_FIELDS

    mesh = meshio.read(out / "solution.vtu")
    assert set(POINT_FIELDS) | set(FRICTION_FIELDS) <= set(mesh.point_data)
    assert "![Contact pressure](pressure.png)" in (out / "report.md").read_text()
    # the results folder is not overwritten without --force
    again = runner.invoke(app, ["run", str(EXAMPLES / "sliding_block.toml"), "--out", str(out)])
    assert again.exit_code == 2 and "--force" in flat(again.stderr)


def test_run_problem_file_uses_output_folder_and_quiet(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["run", str(EXAMPLES / "signorini_liftoff.toml"), "--quiet",
                                 "--algorithm", "ssn"])
    assert result.exit_code == 0, result.output
    assert result.stdout == ""
    s = json.loads((tmp_path / "results-signorini" / "summary.json").read_text())
    assert s["algorithm"] == "ssn" and "solution.pvd" not in s["files"]


def test_run_problem_file_rejects_builtin_options(tmp_path):
    result = runner.invoke(app, ["run", str(EXAMPLES / "hertz_2d.toml"), "--level", "2", "--out", str(tmp_path / "r")])
    assert result.exit_code == 2 and "built-in problem" in flat(result.stderr)


def test_check_ok_and_errors(tmp_path):
    result = runner.invoke(app, ["check", str(EXAMPLES / "hertz_3d.toml")])
    assert result.exit_code == 0 and result.stdout.startswith("OK hertz-3d: 3D P1")
    bad = tmp_path / "bad.toml"
    bad.write_text((EXAMPLES / "hertz_2d.toml").read_text().replace('boundary = "top"', 'boundary = "topp"')
                   .replace("nu = 0.3", "nu = 0.6"))
    result = runner.invoke(app, ["check", str(bad)])
    msg = flat(result.stderr)
    assert result.exit_code == 2 and "2 errors" in msg
    assert "contact.boundary = 'topp'" in msg and "Did you mean 'top'" in msg and "material.nu = 0.6" in msg
    assert "Traceback" not in result.output


def test_docs_check_and_write(tmp_path):
    result = runner.invoke(app, ["docs", "--check"])
    assert result.exit_code == 0, result.output
    target = tmp_path / "pf.md"
    result = runner.invoke(app, ["docs", "--out", str(target)])
    assert result.exit_code == 0 and target.read_text().startswith("# Problem files")
    target.write_text("stale")
    assert runner.invoke(app, ["docs", "--check", "--out", str(target)]).exit_code == 1


def test_bench_runs_scripts_and_writes_report(tmp_path):
    bench = tmp_path / "bench"
    bench.mkdir()
    (bench / "hertz.py").write_text(
        "from pathlib import Path\n"
        "def run(out_dir=None, cases=None, variants=None, log=print):\n"
        "    Path(out_dir, 'hertz.md').write_text(f'# Hertz benchmark\\n\\ncases={cases} variants={variants}\\n')\n"
        "    return Path(out_dir)\n")
    (bench / "friction.py").write_text(
        "from pathlib import Path\n"
        "def run(out_dir=None, cases=None, variants=None, log=print):\n"
        "    Path(out_dir, 'friction.md').write_text(f'# Friction benchmark\\n\\ncases={cases}\\n')\n"
        "    return Path(out_dir)\n")
    (bench / "nlp_hs.py").write_text(
        "from pathlib import Path\n"
        "def run(out_dir=None, variants=None):\n"
        "    Path(out_dir, 'nlp_hs.md').write_text(f'# NLP\\n\\nvariants={variants}\\n')\n"
        "    return Path(out_dir, 'nlp_hs.csv')\n")
    (bench / "finite.py").write_text(
        "from pathlib import Path\n"
        "def run(out_dir=None, cases=None, variants=None, log=print):\n"
        "    Path(out_dir, 'finite.md').write_text(f'# Finite deformation\\n\\ncases={cases} variants={variants}\\n')\n"
        "    return Path(out_dir)\n")
    (bench / "ironing.py").write_text(
        "from pathlib import Path\n"
        "def run(out_dir=None, cases=None, variants=None, log=print):\n"
        "    Path(out_dir, 'ironing.md').write_text(f'# Ironing\\n\\ncases={cases} variants={variants}\\n')\n"
        "    return Path(out_dir)\n")
    (bench / "two_body_ironing.py").write_text(
        "from pathlib import Path\n"
        "def run(out_dir=None, cases=None, variants=None, log=print):\n"
        "    Path(out_dir, 'two_body_ironing.md').write_text(f'# Two-body ironing\\n\\ncases={cases}\\n')\n"
        "    return Path(out_dir)\n")
    out = tmp_path / "out"
    result = runner.invoke(app, ["bench", "--out", str(out), "--quick", "--benchmarks-dir", str(bench)])
    assert result.exit_code == 0, result.output
    report = (out / "bench.md").read_text()
    assert "## Hertz benchmark" in report and "cases=['2d-10k']" in report and "## NLP" in report
    assert "## Friction benchmark" in report and "cases=['mindlin-2d']" in report
    assert "## Finite deformation" in report and "cases=['2d-5k']" in report
    assert "## Ironing" in report and "cases=['2d-s']" in report
    assert "## Two-body ironing" in report and "cases=['tiny']" in report
    result = runner.invoke(app, ["bench", "--out", str(out), "--suite", "nlp", "--variant", "exp-met1",
                                 "--benchmarks-dir", str(bench)])
    assert result.exit_code == 0 and "variants=['exp-met1']" in (out / "bench.md").read_text()
    result = runner.invoke(app, ["bench", "--suite", "hertzz", "--benchmarks-dir", str(bench)])
    assert result.exit_code == 2 and "Did you mean 'hertz'" in flat(result.stderr)
    result = runner.invoke(app, ["bench", "--benchmarks-dir", str(tmp_path / "none")])
    assert result.exit_code == 2 and "--benchmarks-dir" in flat(result.stderr)


def test_list_shows_friction_algorithms_and_examples():
    result = runner.invoke(app, ["list"])
    assert result.exit_code == 0
    assert "friction-algorithms" in result.output and "examples/hertz_2d.toml" in result.output


@pytest.mark.parametrize("cmd", ["run", "check", "list", "bench", "study", "docs"])
def test_help_of_every_command(cmd):
    result = runner.invoke(app, [cmd, "--help"])
    assert result.exit_code == 0 and "Usage" in result.output


# ------------------------------------------------------------------ make run: report.md; stepped summary table
def test_make_run_writes_report_md(tmp_path):
    """``make run`` is ``alcontact run --out results --force``: its folder has report.md (README step 1)."""
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", "--out", str(out), "--force", "--level", "0"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == sorted(RESULT_FILES)
    report = (out / "report.md").read_text()
    s = json.loads((out / "summary.json").read_text())
    assert report.startswith(f"# {s['problem_label']}") and "**Status: converged**" in report
    assert f"| peak pressure p0 (MPa) | {s['peak_pressure']:.5g} | {s['peak_pressure_exact']:.5g} |" in report
    assert f"| contact half-width a (mm) | {s['contact_half_width']:.5g} |" in report
    for png in ("pressure.png", "convergence.png"):
        assert f"]({png})" in report and (out / png).is_file()
    for name in RESULT_FILES:
        if name != "report.md":
            assert f"- `{name}`:" in report
    assert s["units"] == {"length": "mm", "stress": "MPa", "force": "N/mm"}
    text = flat(result.stdout.replace("│", " "))
    assert "contact half-width a (mm)" in text and "peak pressure p0 (MPa)" in text and "force P (N/mm)" in text


def test_stepped_summary_compares_the_total_time_with_one_linear_solve(tmp_path):
    out = tmp_path / "res"
    result = runner.invoke(app, ["run", str(EXAMPLES / "flat_punch.toml"), "--out", str(out)])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    assert s["load_steps"] == 4
    assert s["time_ratio_contact_to_linear"] == pytest.approx(s["wall_time_s"] / s["linear_solve_time_s"], rel=1e-12)
    text = flat(result.stdout.replace("│", " "))
    assert f"wall time, all steps (s) {s['wall_time_s']:.3f}" in text
    assert f"wall time / linear solve {s['time_ratio_contact_to_linear']:.2f}" in text
    report = (out / "report.md").read_text()
    assert f"| wall time of all steps (s) | {s['wall_time_s']:.3f} |" in report
