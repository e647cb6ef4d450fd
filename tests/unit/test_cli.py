"""``alcontact`` command line: run, list, help, exit codes, results folder."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from alcontact.cli import app, main
from alcontact.io import POINT_FIELDS, SUMMARY_KEYS
from alcontact.runner import RESULT_FILES

# wide console: rich would otherwise wrap long paths in messages
runner = CliRunner(env={"COLUMNS": "400", "NO_COLOR": "1"})


def _flat(text: str) -> str:
    return " ".join(text.split())


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
    msg = _flat(result.stderr)
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
    msg = _flat(result.stderr)
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
    assert text in _flat(result.stderr) and "Traceback" not in result.output
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
