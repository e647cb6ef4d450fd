"""Result files: atomic writes, results folder handling, summary/history, VTU output."""

from __future__ import annotations

import csv
import json
import numpy as np
import pytest

from alcontact.errors import OutputExistsError, OutputPathError
from alcontact.io import (
    HISTORY_COLUMNS,
    POINT_FIELDS,
    SUMMARY_KEYS,
    atomic_path,
    prepare_output_dir,
    write_history_csv,
    write_json,
    write_solution_vtu,
    write_text_atomic,
)


@pytest.fixture(scope="module")
def hertz_solution():
    from alcontact.contact import solve
    from alcontact.problems import hertz

    prob = hertz.hertz_2d(level=0)
    return prob, solve(prob)


# ------------------------------------------------------------------ atomic writes
def test_atomic_write_leaves_only_the_file(tmp_path):
    target = tmp_path / "a.txt"
    write_text_atomic(target, "one\n")
    write_text_atomic(target, "two\n")  # replacing an existing file
    assert target.read_text() == "two\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]


def test_atomic_write_failure_keeps_old_file_and_no_temp(tmp_path):
    target = tmp_path / "a.json"
    write_text_atomic(target, "old")
    with pytest.raises(RuntimeError, match="boom"):
        with atomic_path(target) as tmp:
            tmp.write_text("partial")
            raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json"]


def test_atomic_path_keeps_suffix_for_format_sniffing(tmp_path):
    with atomic_path(tmp_path / "x.vtu") as tmp:
        assert tmp.suffix == ".vtu" and tmp.parent == tmp_path and tmp.name.startswith(".")
        tmp.write_text("data")
    assert (tmp_path / "x.vtu").read_text() == "data"


def test_atomic_write_onto_a_folder_is_a_clean_error(tmp_path):
    """API fuzzing: a history path that is an existing folder ended in a raw IsADirectoryError."""
    (tmp_path / "x").mkdir()
    with pytest.raises(OutputPathError, match="a folder of that name exists"):
        write_text_atomic(tmp_path / "x", "data")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x"] and not any((tmp_path / "x").iterdir())


def test_write_json_converts_numpy_and_nonfinite(tmp_path):
    path = write_json(tmp_path / "s.json", {"a": np.float64(1.5), "n": np.int64(3), "bad": float("nan"),
                                            "v": np.arange(3), "t": (1, 2), "ok": np.bool_(True)})
    data = json.loads(path.read_text())
    assert data == {"a": 1.5, "n": 3, "bad": None, "v": [0, 1, 2], "t": [1, 2], "ok": True}


# ------------------------------------------------------------------ results folder
def test_prepare_output_dir_creates_and_accepts_empty(tmp_path):
    out = tmp_path / "new" / "results"
    assert prepare_output_dir(out, create=False) == out and not out.exists()
    assert prepare_output_dir(out).is_dir()
    assert prepare_output_dir(out).is_dir()  # empty folder: reused without --force


def test_prepare_output_dir_refuses_non_empty_without_force(tmp_path):
    (tmp_path / "keep.txt").write_text("x")
    with pytest.raises(OutputExistsError) as info:
        prepare_output_dir(tmp_path)
    assert str(tmp_path) in str(info.value) and "--force" in str(info.value)
    assert isinstance(info.value, FileExistsError)
    assert prepare_output_dir(tmp_path, force=True) == tmp_path
    assert (tmp_path / "keep.txt").read_text() == "x"


def test_prepare_output_dir_refuses_a_file(tmp_path):
    f = tmp_path / "results"
    f.write_text("x")
    with pytest.raises(OutputExistsError, match="not a folder"):
        prepare_output_dir(f, force=True)


# ------------------------------------------------------------------ history / summary
def test_history_csv_round_trip(tmp_path, hertz_solution):
    _, sol = hertz_solution
    path = write_history_csv(tmp_path / "history.csv", sol.result.history)
    rows = list(csv.DictReader(path.open()))
    assert tuple(rows[0].keys()) == HISTORY_COLUMNS
    assert len(rows) == sol.result.outer_iterations
    assert float(rows[-1]["penetration"]) == sol.result.history[-1].penetration
    assert write_history_csv(tmp_path / "empty.csv", ()).read_text().strip() == ",".join(HISTORY_COLUMNS)


def test_summary_has_contract_keys(hertz_solution):
    from alcontact.runner import summarize

    prob, sol = hertz_solution
    s = summarize(prob, sol, problem_name="hertz-2d", level=0)
    assert set(SUMMARY_KEYS) <= set(s)
    assert s["status"] == "converged" and s["dofs"] == prob.model.ndofs
    assert s["total_contact_force"] == pytest.approx(2 * sol.normal_force)  # half model: total load
    assert s["linear_solve_time_s"] == sol.timings["linear_solve_s"]
    json.dumps(s)  # serializable as is


# ------------------------------------------------------------------ VTU
def test_vtu_readable_by_meshio(tmp_path, hertz_solution):
    import meshio

    prob, sol = hertz_solution
    path = write_solution_vtu(tmp_path / "solution.vtu", sol)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["solution.vtu"]
    mesh = meshio.read(path)
    nverts = prob.model.mesh.p.shape[1]
    assert mesh.points.shape == (nverts, 3)
    assert set(POINT_FIELDS) <= set(mesh.point_data)
    assert mesh.cells_dict["triangle"].shape[0] == prob.model.mesh.t.shape[1]
    p = mesh.point_data["contact_pressure"]
    assert p.max() == pytest.approx(sol.peak_pressure_nodal_max)
    assert np.all(p >= 0)
    gap = mesh.point_data["gap"]
    assert np.isfinite(gap).sum() == sol.points.shape[0]  # gap only on the contact boundary
    disp = mesh.point_data["displacement"]
    assert disp.shape == (nverts, 3) and np.all(disp[:, 2] == 0)
    assert np.nanmin(disp[:, 1]) < 0  # pressed down
    assert np.all(mesh.point_data["von_mises"] >= 0)


def test_vtu_p2_writes_vertex_values(tmp_path):
    import meshio

    from alcontact.contact import solve
    from alcontact.problems import hertz

    prob = hertz.hertz_2d(level=0, order=2, n_per_a=4)
    sol = solve(prob)
    mesh = meshio.read(write_solution_vtu(tmp_path / "p2.vtu", sol))
    nverts = prob.model.mesh.p.shape[1]
    assert mesh.points.shape[0] == nverts < prob.model.dof_map.shape[0]
    # vertex displacement equals the P2 solution at the vertex DOFs
    vdofs = prob.model.scalar_basis.nodal_dofs[0]
    np.testing.assert_allclose(mesh.point_data["displacement"][:, :2], sol.u[prob.model.dof_map[vdofs]])
    p = mesh.point_data["contact_pressure"]
    assert 0 < p.max() <= sol.peak_pressure_nodal_max  # edge-midpoint values are not written
