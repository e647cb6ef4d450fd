"""``alcontact study``: the report is generated from the CSV, resume, timeouts, bad input (issue 26).

The tiniest configuration (``--quick --meshes 1``): the smallest quick mesh of the Signorini block
(54 DOFs), of the two-body Hertz cylinders (3906 DOFs, mortar) and of Cattaneo-Mindlin (friction,
1088 DOFs), with the ssn reference, Algorithm 6.1 and Algorithm 6.3 with exp-met1 (3 eps scales x 4
update rules on the frictionless problems, 3 scales without a rule with friction) and the log-barrier
anchor (3 eps scales), 66 cells.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from alcontact.app.study import COLUMNS, CSV_NAME, PROBLEMS, STUDY_VERSION, plan, read_rows, run_study
from alcontact.cli import app

ONLY = ["signorini", "hertz-2body", "cattaneo-mindlin", "ssn", "simo-laursen", "exp-met1", "log-barrier"]
# a generous timeout per cell: the cells' wall time on a loaded machine is not what this module tests
ARGS = ["study", "--quick", "--meshes", "1", "--jobs", "2", "--timeout", "900"] + [x for n in ONLY for x in ("--only", n)]
N_CELLS = 66
RULES = ("fixed", "infeasibility", "alg54-printed", "alg54-corrected")


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("study") / "run"
    res = CliRunner().invoke(app, ARGS + ["--out", str(out)])
    assert res.exit_code == 0, res.output
    return out, res.output


def _tables(md: str) -> list[tuple[str, list[list[str]]]]:
    """(heading, rows) of every markdown table of the report, cells stripped."""
    out, heading, rows = [], "", None
    for line in md.splitlines():
        if line.startswith("#"):
            heading = line.lstrip("#").strip()
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if rows is None:
                rows = [cells]
            elif not set("".join(cells)) <= set("-:"):
                rows.append(cells)
        elif rows is not None:
            out.append((heading, rows))
            rows = None
    if rows is not None:
        out.append((heading, rows))
    return out


def test_every_cell_of_the_plan_is_one_csv_row(study):
    out, output = study
    rows = read_rows(out / CSV_NAME)
    keys = [c.key for c in plan(quick=True, only=ONLY, meshes=1)]
    assert len(keys) == N_CELLS
    assert sorted(r["key"] for r in rows) == sorted(keys)
    assert list(rows[0]) == list(COLUMNS)
    assert {r["study_version"] for r in rows} == {str(STUDY_VERSION)}
    assert {(r["problem"], r["mesh"]) for r in rows} == {("signorini", "2"), ("hertz-2body", "8"),
                                                          ("cattaneo-mindlin", "2")}
    assert json.loads((out / "study.json").read_text())["study_version"] == STUDY_VERSION
    for name in ("heatmap-signorini.png", "heatmap-hertz-2body.png", "heatmap-rules.png"):
        assert (out / name).stat().st_size > 1000
    assert f"{N_CELLS} solved" in output
    for r in rows:  # the ssn references converged, so every converged cell has its error
        assert r["status"] in {"converged", "maxiter", "newton-failed", "penalty-limit"}, r
        assert float(r["time_per_linear_solve"]) > 0 and int(r["steps"]) >= 1
        if r["status"] == "converged" and r["problem"] != "hertz-2body" and r["method"] != "ssn":
            assert r["error_reference"] == "ssn u" and float(r["error"]) < 1e-3, r


def test_two_body_cells_meet_hertz_with_the_effective_modulus(study):
    """The two-body problem's error is against Hertz's p0 for two cylinders (Johnson 1985, eq. 4.45-4.47: 1/R =
    1/R1 + 1/R2, 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2, p0 = 2P/(pi a)) for the load the model carries.

    Tolerance: 2 % at 8 elements per a (measured 0.93 %, the discretization error); every converged method
    solves the same discrete problem, so its error equals the ssn reference's to 1e-6 (the AL tolerances are 1e-8).
    """
    rows = [r for r in read_rows(study[0] / CSV_NAME) if r["problem"] == "hertz-2body"]
    ssn = [r for r in rows if r["method"] == "ssn"]
    assert len(ssn) == 1 and ssn[0]["status"] == "converged" and ssn[0]["error_reference"] == "hertz p0"
    ref = float(ssn[0]["error"])
    assert 0 < ref < 0.02
    conv = [r for r in rows if r["status"] == "converged"]
    assert len(conv) >= 20
    for r in conv:
        assert r["error_reference"] == "hertz p0" and abs(float(r["error"]) - ref) <= 1e-6, r


def test_the_barrier_runs_with_friction(study):
    """The frictional problem has log-barrier cells at every quick eps scale, without an update rule; where they
    converge they meet the ssn solution (the same discrete Coulomb problem) to 1e-6."""
    rows = [r for r in read_rows(study[0] / CSV_NAME) if r["problem"] == "cattaneo-mindlin"]
    bar = [r for r in rows if r["method"] == "log-barrier"]
    assert sorted(r["eps_scale"] for r in bar) == ["0.01", "1", "100"] and {r["rule"] for r in bar} == {"-"}
    conv = [r for r in bar if r["status"] == "converged"]
    assert conv
    for r in conv:
        assert float(r["error"]) < 1e-6 and int(r["steps"]) >= 4, r


def test_configured_eps_scale_and_rule_took_effect(study):
    """Algorithm 6.1 with the fixed rule keeps eps: the final eps is the scale times the automatic one; the
    infeasibility rule raised it; every rule ran at every eps scale."""
    rows = {(r["problem"], r["method"], r["eps_scale"], r["rule"]): r for r in read_rows(study[0] / CSV_NAME)}
    for problem in ("signorini", "hertz-2body"):
        e1 = float(rows[(problem, "simo-laursen", "1", "fixed")]["eps_final"])
        e100 = float(rows[(problem, "simo-laursen", "100", "fixed")]["eps_final"])
        assert e100 == pytest.approx(100 * e1, rel=1e-3)
        fixed, inf = rows[(problem, "exp-met1", "1", "fixed")], rows[(problem, "exp-met1", "1", "infeasibility")]
        assert float(inf["eps_final"]) > float(fixed["eps_final"])  # the infeasibility rule raised eps
        for m in ("simo-laursen", "exp-met1"):
            assert {(s, r) for (p, mm, s, r) in rows if p == problem and mm == m} == \
                {(s, r) for s in ("0.01", "1", "100") for r in RULES}


def test_report_figures_are_the_csv(study):
    """Parse report.md's tables back and compare every figure with the CSV (computed here independently)."""
    out, _ = study
    rows = read_rows(out / CSV_NAME)
    md = (out / "report.md").read_text()
    tabs = _tables(md)
    assert f"{len(rows)} cells" in md
    checked = 0
    for heading, tab in tabs:
        head, body = tab[0], tab[1:]
        if head[:4] == ["method", "converged", "cells", "fraction"]:
            for m, ok, n, frac, newton, ratio in body:
                sweep = [r for r in rows if r["method"] == m and r["rule"] in ("fixed", "-")]
                conv = [r for r in sweep if r["status"] == "converged"]
                assert (int(ok), int(n)) == (len(conv), len(sweep))
                assert frac == f"{100 * len(conv) / len(sweep):.0f}%"
                nw = sorted(float(r["newton"]) for r in conv)
                assert newton == (f"{_median(nw):.1f}" if nw else "-")
                checked += 1
        elif head[:2] == ["method", "rule"]:
            scales = [h.removeprefix("eps x") for h in head[2:-4]]
            assert scales == ["0.01", "1", "100"] and head[-4:] == ["converged", "cells", "outer", "Newton"]
            for line in body:
                m, rule, per, (ok, n, outer, newton) = line[0], line[1], line[2:-4], line[-4:]
                sel = [r for r in rows if r["method"] == m and r["rule"] == rule]
                conv = [r for r in sel if r["status"] == "converged"]
                for sc, text in zip(scales, per):
                    at = [r for r in sel if r["eps_scale"] == sc]
                    assert text == f"{sum(r['status'] == 'converged' for r in at)}/{len(at)}"
                assert (int(ok), int(n)) == (len(conv), len(sel))
                if not conv:  # no converged cell: no mean
                    assert outer == newton == "-"
                    checked += 1
                    continue
                assert outer == f"{sum(int(r['outer']) for r in conv) / len(conv):.1f}"
                assert newton == f"{sum(int(r['newton']) for r in conv) / len(conv):.1f}"
                checked += 1
        elif head[0] == "method" and head[1].startswith("eps x"):
            problem, mesh = re.match(r"(\S+), mesh (\S+) \(", heading).groups()
            scales = [h.removeprefix("eps x") for h in head[1:]]
            for line in body:
                m = line[0]
                for s, text in zip(scales, line[1:]):
                    (r,) = [r for r in rows if r["problem"] == problem and r["mesh"] == mesh and r["method"] == m
                            and r["eps_scale"] in (s, "-") and r["rule"] in ("fixed", "-")]
                    assert text == (r["newton"] if r["status"] == "converged" else f"[{r['status']}]")
                    checked += 1
    assert checked >= 4 + 8 + 3 * 4 * 3  # the robustness rows, rule rows and the three sweep tables were read


def test_answers_are_the_csv(study):
    """The sentences of the "Answers" section carry figures recomputed here from the CSV."""
    out, _ = study
    rows = read_rows(out / CSV_NAME)
    md = (out / "report.md").read_text()
    answers = " ".join(md.split("## Answers", 1)[1].split("\n## ", 1)[0].split())
    # the update rules: converged / cells per eps scale and over the sweep, every method with a rule
    for rule in RULES:
        sel = [r for r in rows if r["rule"] == rule]
        per = ", ".join(f"x{sc} {sum(r['status'] == 'converged' for r in sel if r['eps_scale'] == sc)} of "
                        f"{sum(r['eps_scale'] == sc for r in sel)}" for sc in ("0.01", "1", "100"))
        ok = sum(r["status"] == "converged" for r in sel)
        assert len(sel) == 2 * 2 * 3  # two methods x two frictionless problems x three scales
        assert f"`{rule}` {per} (all: {ok} of {len(sel)}" in answers
    printed = [r for r in rows if r["rule"] == "alg54-printed" and r["status"] == "converged"]
    corrected = [r for r in rows if r["rule"] == "alg54-corrected" and r["status"] == "converged"]
    assert f"as printed (eta <- 2 eta, i.e. eps_N halved every outer iteration) converged in {len(printed)} of 12" \
        in answers
    assert f"as corrected (eps_N doubled) in {len(corrected)} of 12" in answers
    # which rule makes which method robust: the rules with the most converged cells, and fixed's count
    for m in ("simo-laursen", "exp-met1"):
        counts = {rule: sum(r["status"] == "converged" for r in rows if r["method"] == m and r["rule"] == rule)
                  for rule in RULES}
        top = max(counts.values())
        part = re.search(rf"{m}: ((?:`[a-z0-9-]+`(?:, )?)+) (\d+) of (\d+) \(fixed (\d+)\)", answers)
        assert part is not None, m
        assert set(re.findall(r"`([a-z0-9-]+)`", part.group(1))) == {r for r, c in counts.items() if c == top}
        assert (int(part.group(2)), int(part.group(3)), int(part.group(4))) == (top, 6, counts["fixed"])
    # the sweep per eps scale: every method with a penalty parameter, rule fixed (or none)
    for scale in ("0.01", "1", "100"):
        sel = [r for r in rows if r["eps_scale"] == scale and r["rule"] in ("fixed", "-")]
        ok = sum(r["status"] == "converged" for r in sel)
        assert len(sel) == 2 * 3 + 3 and f"eps x{scale} converged {ok} of {len(sel)}" in answers
    # the barrier anchor against exp-met1 on the same sweep cells, without and with friction
    for friction, label in ((False, "frictionless problems"), (True, "frictional problems")):
        keep = [r for r in rows if (r["problem"] == "cattaneo-mindlin") == friction]
        bar = [r for r in keep if r["method"] == "log-barrier"]
        al = [r for r in keep if r["method"] == "exp-met1" and r["rule"] in ("fixed", "-")]
        nb, na = (sum(r["status"] == "converged" for r in x) for x in (bar, al))
        text = answers.split(f"Barrier anchor, {label}", 1)[1].split("- **", 1)[0]
        assert f"converged in {nb} of {len(bar)} cells of the eps sweep" in text and len(bar) == (3 if friction else 6)
        assert f"methods converged in {na} of {len(al)}" in text
        newton = sorted(float(r["newton"]) for r in bar if r["status"] == "converged")
        if newton:
            assert f"/ {_median(newton):.1f} Newton iterations; on the same cells" in text


def _median(v):
    k = len(v) // 2
    return v[k] if len(v) % 2 else 0.5 * (v[k - 1] + v[k])


def test_resume_solves_nothing_new_and_completes_a_truncated_study(study, tmp_path):
    out, _ = study
    again = CliRunner().invoke(app, ARGS + ["--out", str(out)])
    assert again.exit_code == 0, again.output
    assert f"{N_CELLS} already done, 0 solved" in again.output
    assert len(read_rows(out / CSV_NAME)) == N_CELLS
    # the CSV holds the header, all rows but the last 6 and half of the next one (killed while writing it)
    part = tmp_path / "part"
    part.mkdir()
    (part / "study.json").write_text((out / "study.json").read_text())
    lines = (out / CSV_NAME).read_text().splitlines(keepends=True)
    keep = N_CELLS - 6
    (part / CSV_NAME).write_text("".join(lines[:keep + 1]) + lines[keep + 1][: len(lines[keep + 1]) // 2])
    for f in (out / "ssn").iterdir():  # the references of the finished ssn cells stay in the folder
        (part / "ssn").mkdir(exist_ok=True)
        (part / "ssn" / f.name).write_bytes(f.read_bytes())
    run = run_study(part, quick=True, only=ONLY, meshes=1, jobs=1, report=False)
    assert (run.skipped, run.solved) == (keep, 6)
    got = read_rows(part / CSV_NAME)
    assert sorted(r["key"] for r in got) == sorted(r["key"] for r in read_rows(out / CSV_NAME))
    assert all(None not in r.values() and r["status"] for r in got)  # every row whole


def test_an_interrupted_run_keeps_every_finished_cell_and_resumes(tmp_path):
    """SIGINT to a running ``alcontact study``: exit 130 with the way out, whole rows only, then the same
    command solves exactly the cells that were missing."""
    out = tmp_path / "run"
    only = ["signorini", "ssn", "exp-met1"]  # 13 cells
    cmd = [sys.executable, "-m", "alcontact.cli", "study", "--quick", "--out", str(out), "--jobs", "1",
           "--meshes", "1", "--timeout", "900"] + [x for n in only for x in ("--only", n)]
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    total = len(plan(quick=True, only=only, meshes=1))
    deadline = time.monotonic() + 300
    while len(read_rows(out / CSV_NAME)) < 3 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    proc.send_signal(signal.SIGINT)
    output, _ = proc.communicate(timeout=120)
    done = read_rows(out / CSV_NAME)
    assert proc.returncode == 128 + signal.SIGINT, output
    assert "interrupted: every finished cell is in" in " ".join(output.split()) and "Traceback" not in output
    assert 3 <= len(done) < total
    assert all(None not in r.values() and r["status"] for r in done)
    res = CliRunner().invoke(app, cmd[3:])
    assert res.exit_code == 0, res.output
    assert f"{total} cells: {len(done)} already done, {total - len(done)} solved" in " ".join(res.output.split())
    assert sorted(r["key"] for r in read_rows(out / CSV_NAME)) == sorted(c.key for c in plan(quick=True, only=only,
                                                                                            meshes=1))


def test_a_cell_past_its_timeout_is_recorded_as_timeout(tmp_path):
    run = run_study(tmp_path / "t", quick=True, only=["signorini", "ssn"], timeout=1e-3, report=False)
    rows = read_rows(tmp_path / "t" / CSV_NAME)
    assert run.solved == 2 and [r["status"] for r in rows] == ["timeout", "timeout"]
    assert all("killed after" in r["message"] for r in rows)


@pytest.mark.parametrize("name, closest", [("hertz2d", "hertz-2d"), ("exp-mte1", "exp-met1"),
                                           ("hertz-2bdy", "hertz-2body")])
def test_unknown_only_name_is_a_clear_error(tmp_path, name, closest):
    res = CliRunner().invoke(app, ["study", "--quick", "--only", name, "--out", str(tmp_path / "x")])
    assert res.exit_code == 2
    text = " ".join(res.output.split())
    assert f"unknown --only name '{name}'" in text and f"Did you mean '{closest}'" in text
    assert "Known --only names: " in text
    assert "Traceback" not in res.output
    assert not (tmp_path / "x").exists()  # nothing written


def test_folder_of_another_study_version_is_refused(tmp_path):
    out = tmp_path / "old"
    out.mkdir()
    (out / "study.json").write_text(json.dumps({"study_version": STUDY_VERSION - 1}))
    with (out / CSV_NAME).open("w", newline="") as fh:
        csv.writer(fh).writerow(["key"])
    res = CliRunner().invoke(app, ["study", "--quick", "--only", "signorini", "--out", str(out)])
    assert res.exit_code == 2
    text = " ".join(res.output.split())  # the console wraps long lines
    assert str(out) in text and "Pass a new --out folder" in text and f"this is version {STUDY_VERSION}" in text
    assert (out / CSV_NAME).read_text().strip() == "key"  # untouched


def test_results_of_another_layout_are_refused(tmp_path):
    """A folder whose study.json says this version but whose CSV has other columns (another build, an edit)."""
    out = tmp_path / "edited"
    out.mkdir()
    (out / "study.json").write_text(json.dumps({"study_version": STUDY_VERSION}))
    header = ",".join(c for c in COLUMNS if c != "cutbacks")
    (out / CSV_NAME).write_text(header + "\n")
    res = CliRunner().invoke(app, ["study", "--quick", "--only", "signorini", "--out", str(out)])
    assert res.exit_code == 2
    text = " ".join(res.output.split())
    assert "does not have the columns of a version" in text and "Pass a new --out folder" in text
    assert (out / CSV_NAME).read_text() == header + "\n"  # untouched


def test_non_study_folder_and_bad_jobs_or_meshes_are_refused(tmp_path):
    (tmp_path / "mine.txt").write_text("user data")
    res = CliRunner().invoke(app, ["study", "--quick", "--only", "signorini", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "holds no study" in " ".join(res.output.split())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.txt"]
    res = CliRunner().invoke(app, ["study", "--quick", "--jobs", "0", "--out", str(tmp_path / "j")])
    assert res.exit_code == 2 and "--jobs" in res.output
    res = CliRunner().invoke(app, ["study", "--quick", "--meshes", "0", "--out", str(tmp_path / "m")])
    assert res.exit_code == 2 and "--meshes must be a whole number of at least 1" in " ".join(res.output.split())
    assert not (tmp_path / "m").exists()


def test_plan_covers_the_matrix_of_the_issue():
    from alcontact.optim import available_strategies

    cells = plan()
    problems = {c.problem for c in cells}
    assert problems == {"hertz-2d", "hertz-3d", "signorini", "half-cylinder", "hemisphere", "cattaneo-mindlin",
                        "ironing", "hertz-2body"}
    labels = {c.method.label for c in cells}
    assert {"penalty", "simo-laursen", "rockafellar", "ssn", "exp-met1", "exp-met2", "log-met1", "log-met2",
            "log-barrier"} <= labels
    scales = sorted({c.eps_scale for c in cells if c.eps_scale is not None})
    assert math.log10(scales[-1] / scales[0]) >= 6  # six decades around the automatic value
    for p in problems:
        assert len({c.mesh for c in cells if c.problem == p}) == 4
        assert len({c.mesh for c in plan(quick=True) if c.problem == p}) == 2
        assert len({c.mesh for c in plan(quick=True, meshes=1) if c.problem == p}) == 1
    assert all(c.method.algorithm != "penalty" for c in cells if c.problem in ("cattaneo-mindlin", "ironing"))
    assert {c.problem for c in cells if c.method.label == "log-barrier"} == problems  # with friction too
    # every registered rule at every scale, for every method with a rule on a frictionless problem
    full = {(s, r) for s in scales for r in available_strategies()}
    for p in problems - {"cattaneo-mindlin", "ironing"}:
        mesh = PROBLEMS[p].full_meshes[1]
        for m in ("simo-laursen", "exp-met1", "quad-met2"):
            assert {(c.eps_scale, c.rule) for c in cells if (c.problem, c.mesh, c.method.label) == (p, mesh, m)} == full
    assert len({c.key for c in cells}) == len(cells)
