"""``alcontact study``: the report is generated from the CSV, resume, timeouts, bad input (issue 26).

The tiniest configuration: the Signorini block (two quick meshes, 54 and 170 DOFs) with the ssn
reference, Algorithm 6.1 and Algorithm 6.3 with exp-met1 (3 eps scales and 4 update rules) and the
log-barrier anchor (3 eps scales, no rule), 32 cells.
"""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from alcontact.app.study import COLUMNS, CSV_NAME, STUDY_VERSION, plan, read_rows, run_study
from alcontact.cli import app

ONLY = ["signorini", "ssn", "simo-laursen", "exp-met1", "log-barrier"]
ARGS = ["study", "--quick", "--jobs", "2"] + [x for n in ONLY for x in ("--only", n)]


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
    keys = [c.key for c in plan(quick=True, only=ONLY)]
    assert len(keys) == 32
    assert sorted(r["key"] for r in rows) == sorted(keys)
    assert list(rows[0]) == list(COLUMNS)
    assert {r["study_version"] for r in rows} == {str(STUDY_VERSION)}
    assert json.loads((out / "study.json").read_text())["study_version"] == STUDY_VERSION
    assert (out / "heatmap-signorini.png").stat().st_size > 1000
    assert "32 solved" in output
    for r in rows:  # the ssn reference converged on both meshes, so every converged AL cell has its error
        assert r["status"] in {"converged", "maxiter", "newton-failed", "penalty-limit"}, r
        if r["status"] == "converged" and r["method"] != "ssn":
            assert r["error_reference"] == "ssn u" and float(r["error"]) < 1e-3, r
        assert float(r["time_per_linear_solve"]) > 0


def test_configured_eps_scale_and_rule_took_effect(study):
    """Algorithm 6.1 with the fixed rule keeps eps: the final eps is the scale times the automatic one."""
    rows = {(r["mesh"], r["method"], r["eps_scale"], r["rule"]): r for r in read_rows(study[0] / CSV_NAME)}
    for mesh in ("2", "4"):
        e1 = float(rows[(mesh, "simo-laursen", "1", "fixed")]["eps_final"])
        e100 = float(rows[(mesh, "simo-laursen", "100", "fixed")]["eps_final"])
        assert e100 == pytest.approx(100 * e1, rel=1e-3)
        fixed, inf = rows[(mesh, "exp-met1", "1", "fixed")], rows[(mesh, "exp-met1", "1", "infeasibility")]
        assert float(inf["eps_final"]) > float(fixed["eps_final"])  # the infeasibility rule raised eps


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
                assert float(newton) == pytest.approx(_median(nw), abs=0.05)
                checked += 1
        elif head[:2] == ["method", "rule"]:
            for m, rule, n, ok, outer, newton in body:
                sel = [r for r in rows if r["method"] == m and r["rule"] == rule and float(r["eps_scale"]) == 1.0]
                conv = [r for r in sel if r["status"] == "converged"]
                assert (int(n), int(ok)) == (len(sel), len(conv))
                if not conv:  # no converged cell: no mean
                    assert outer == newton == "-"
                    checked += 1
                    continue
                assert float(outer) == pytest.approx(sum(int(r["outer"]) for r in conv) / len(conv), abs=0.05)
                assert float(newton) == pytest.approx(sum(int(r["newton"]) for r in conv) / len(conv), abs=0.05)
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
    assert checked >= 4 + 8 + 2 * 4 * 3  # the robustness rows, rule rows and both sweep tables were read


def test_answers_are_the_csv(study):
    """The sentences of the "Answers" section carry figures recomputed here from the CSV."""
    out, _ = study
    rows = read_rows(out / CSV_NAME)
    md = (out / "report.md").read_text()
    answers = md.split("## Answers", 1)[1].split("\n## ", 1)[0]
    # the update rules: converged / cells at eps scale 1 over every method with a rule
    for rule in ("fixed", "infeasibility", "alg54-printed", "alg54-corrected"):
        sel = [r for r in rows if r["rule"] == rule and r["eps_scale"] == "1"]
        ok = [r for r in sel if r["status"] == "converged"]
        assert len(sel) == 4  # two methods x two meshes
        assert f"`{rule}` converged {len(ok)} of {len(sel)}" in answers
    printed = [r for r in rows if r["rule"] == "alg54-printed" and r["status"] == "converged"]
    corrected = [r for r in rows if r["rule"] == "alg54-corrected" and r["status"] == "converged"]
    assert f"as printed (eta <- 2 eta, i.e. eps_N halved every outer iteration) converged in {len(printed)} of 4" \
        in " ".join(answers.split())
    assert f"as corrected (eps_N doubled) in {len(corrected)} of 4" in " ".join(answers.split())
    # the sweep per eps scale: every method with a penalty parameter, rule fixed (or none)
    for scale in ("0.01", "1", "100"):
        sel = [r for r in rows if r["eps_scale"] == scale and r["rule"] in ("fixed", "-")]
        ok = sum(r["status"] == "converged" for r in sel)
        assert len(sel) == 2 * 3 and f"eps x{scale} converged {ok} of {len(sel)}" in answers
    # the barrier anchor against exp-met1 on the same sweep cells
    bar = [r for r in rows if r["method"] == "log-barrier"]
    al = [r for r in rows if r["method"] == "exp-met1" and r["rule"] == "fixed"]
    nb, na = (sum(r["status"] == "converged" for r in x) for x in (bar, al))
    text = " ".join(answers.split())
    assert f"converged in {nb} of {len(bar)} cells of the eps sweep" in text and len(bar) == 6
    assert f"methods converged in {na} of {len(al)}" in text
    newton = sorted(float(r["newton"]) for r in bar if r["status"] == "converged")
    if newton:
        assert f"/ {_median(newton):.1f} Newton iterations; on the same cells" in text


def _median(v):
    k = len(v) // 2
    return v[k] if len(v) % 2 else 0.5 * (v[k - 1] + v[k])


def test_resume_solves_nothing_new_and_completes_an_interrupted_study(study, tmp_path):
    out, _ = study
    again = CliRunner().invoke(app, ARGS + ["--out", str(out)])
    assert again.exit_code == 0, again.output
    assert "32 already done, 0 solved" in again.output
    assert len(read_rows(out / CSV_NAME)) == 32
    # an interrupted study: the CSV holds the header and the first rows only
    part = tmp_path / "part"
    part.mkdir()
    (part / "study.json").write_text((out / "study.json").read_text())
    lines = (out / CSV_NAME).read_text().splitlines(keepends=True)
    (part / CSV_NAME).write_text("".join(lines[:21]))  # header + 20 cells
    for f in (out / "ssn").iterdir():  # the references of the finished ssn cells stay in the folder
        (part / "ssn").mkdir(exist_ok=True)
        (part / "ssn" / f.name).write_bytes(f.read_bytes())
    run = run_study(part, quick=True, only=ONLY, jobs=1, report=False)
    assert (run.skipped, run.solved) == (20, 12)
    assert sorted(r["key"] for r in read_rows(part / CSV_NAME)) == sorted(r["key"] for r in read_rows(out / CSV_NAME))


def test_a_cell_past_its_timeout_is_recorded_as_timeout(tmp_path):
    run = run_study(tmp_path / "t", quick=True, only=["signorini", "ssn"], timeout=1e-3, report=False)
    rows = read_rows(tmp_path / "t" / CSV_NAME)
    assert run.solved == 2 and [r["status"] for r in rows] == ["timeout", "timeout"]
    assert all("killed after" in r["message"] for r in rows)


def test_unknown_only_name_is_a_clear_error(tmp_path):
    res = CliRunner().invoke(app, ["study", "--quick", "--only", "hertz2d", "--out", str(tmp_path / "x")])
    assert res.exit_code == 2
    text = " ".join(res.output.split())
    assert "unknown problem or method of --only 'hertz2d'" in text and "Did you mean 'hertz-2d'" in text
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


def test_non_study_folder_and_bad_jobs_are_refused(tmp_path):
    (tmp_path / "mine.txt").write_text("user data")
    res = CliRunner().invoke(app, ["study", "--quick", "--only", "signorini", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "holds no study" in " ".join(res.output.split())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.txt"]
    res = CliRunner().invoke(app, ["study", "--quick", "--jobs", "0", "--out", str(tmp_path / "j")])
    assert res.exit_code == 2 and "--jobs" in res.output


def test_plan_covers_the_matrix_of_the_issue():
    cells = plan()
    problems = {c.problem for c in cells}
    assert problems == {"hertz-2d", "hertz-3d", "signorini", "half-cylinder", "hemisphere", "cattaneo-mindlin",
                        "ironing"}
    labels = {c.method.label for c in cells}
    assert {"penalty", "simo-laursen", "rockafellar", "ssn", "exp-met1", "exp-met2", "log-met1", "log-met2"} <= labels
    scales = sorted({c.eps_scale for c in cells if c.eps_scale is not None})
    assert math.log10(scales[-1] / scales[0]) >= 6  # six decades around the automatic value
    for p in problems:
        assert len({c.mesh for c in cells if c.problem == p}) == 4
        assert len({c.mesh for c in plan(quick=True) if c.problem == p}) == 2
    assert all(c.method.algorithm != "penalty" for c in cells if c.problem in ("cattaneo-mindlin", "ironing"))
    assert len({c.key for c in cells}) == len(cells)
