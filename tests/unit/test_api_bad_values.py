"""Python API bad values (issue 8, leftovers): load steps, material, obstacles, rigid motions per solver path.

Every bad value raises a project error (``alcontact.errors``) that names the key, the value
and the way out; nothing overflows, allocates without bound or warns. A Hypothesis test builds
random small ContactProblems with random (possibly bad) material, obstacle, supports and loads
and checks that ``solve`` either returns a ContactSolution or raises a project error.
"""

from __future__ import annotations

import dataclasses

import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from alcontact import errors
from alcontact.contact import (ContactProblem, ContactSolution, LoadHistory, Pressure, Support, Traction, solve,
                               solve_friction)
from alcontact.contact.obstacles import Circle, ConvexPolytope, Cylinder, HalfSpace, Sphere
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.io.config import load_problem
from alcontact.io.schema import MAX_STEPS, VALUE_RANGE

# ------------------------------------------------------------------ table: value -> InputError naming it
BAD = [
    ("steps-huge", lambda: LoadHistory.uniform(10**9), ["n = 1000000000", f"[1, {MAX_STEPS}]", "fewer steps"]),
    ("steps-zero", lambda: LoadHistory.uniform(0), ["n = 0", f"[1, {MAX_STEPS}]"]),
    ("steps-bool", lambda: LoadHistory.uniform(True), ["n = True"]),
    ("steps-float", lambda: LoadHistory.uniform(2.5), ["n = 2.5", "integer"]),
    ("steps-str", lambda: LoadHistory.uniform("3"), ["n = '3'"]),
    ("steps-400-digits", lambda: LoadHistory.uniform(10**400), ["digits", f"[1, {MAX_STEPS}]"]),
    ("t_end-nan", lambda: LoadHistory.uniform(3, math.nan), ["t_end = nan", "> 0"]),
    ("with_times-huge", lambda: LoadHistory((), (1.0,)).with_times(10**9), ["n = 1000000000", "fewer steps"]),
    ("times-too-many", lambda: LoadHistory((), range(1, MAX_STEPS + 2)), [f"{MAX_STEPS + 1:,} steps", "fewer"]),
    ("times-not-a-sequence", lambda: LoadHistory((), 5), ["times = 5", "sequence"]),
    ("times-strings", lambda: LoadHistory((), ["a"]), ["times = ['a']", "numbers"]),
    ("E-huge", lambda: Material(E=1e308, nu=0.3), ["E=1e+308", "1e+100", "units"]),
    ("E-tiny", lambda: Material(E=1e-320, nu=0.3), ["E=", "1e-100", "units"]),
    ("E-400-digits", lambda: Material(E=10**400, nu=0.3), ["E=", "digits", "finite"]),
    ("E-str", lambda: Material(E="1e3", nu=0.3), ["E='1e3'", "not a string"]),
    ("E-bool", lambda: Material(E=True, nu=0.3), ["E=True", "number"]),
    ("E-zero", lambda: Material(E=0.0, nu=0.3), ["E=0.0", "> 0"]),
    ("nu-half", lambda: Material(E=1.0, nu=0.5), ["nu=0.5", "-1 < nu < 0.5", "nu=0.49"]),
    ("nu-nan", lambda: Material(E=1.0, nu=math.nan), ["nu=nan"]),
    ("nu-None", lambda: Material(E=1.0, nu=None), ["nu=None", "number"]),
    ("plane", lambda: Material(E=1.0, nu=0.3, plane="strian"), ["plane='strian'", "'strain'"]),
    ("point-huge", lambda: HalfSpace([1e300, 0.0], [0.0, 1.0]), ["point", "1e+300", "units"]),
    ("point-400-digits", lambda: HalfSpace([10**400, 0.0], [0.0, 1.0]), ["point must be a vector of numbers"]),
    ("normal-zero", lambda: HalfSpace([0.0, 0.0], [0.0, 0.0]), ["normal", "non-zero", "normal=[0.0, 1.0]"]),
    ("normal-nan", lambda: HalfSpace([0.0, 0.0], [math.nan, 1.0]), ["normal", "finite", "nan"]),
    ("radius-huge", lambda: Circle([0.0, 0.0], 1e308), ["radius = 1e+308", "1e+100", "units"]),
    ("radius-tiny", lambda: Sphere([0.0, 0.0, 0.0], 1e-300), ["radius = 1e-300", "1e-100"]),
    ("radius-400-digits", lambda: Circle([0.0, 0.0], 10**400), ["radius", "digits"]),
    ("radius-bool", lambda: Circle([0.0, 0.0], True), ["radius = True", "bool"]),
    ("axis-zero", lambda: Cylinder([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 1.0), ["axis", "non-zero", "[0.0, 0.0, 1.0]"]),
    ("face-far", lambda: ConvexPolytope(np.array([[1e-300, 0], [-1, 0], [0, 1], [0, -1.0]]),
                                        np.array([1e300, 1, 1, 1.0])), ["face 0", "b[0] = 1e+300", "units"]),
]


@pytest.mark.parametrize("label,call,words", BAD, ids=[b[0] for b in BAD])
def test_bad_value_is_an_input_error_naming_it(label, call, words):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow warning on the way to the error
        with pytest.raises(errors.InputError) as info:
            call()
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_material_range_is_the_preflight_range():
    """One declaration: the ends of VALUE_RANGE are accepted, the next floats outside are not."""
    lo, hi = VALUE_RANGE
    assert Material(E=lo, nu=0.3).E == lo and Material(E=hi, nu=0.3).E == hi
    for E in (np.nextafter(lo, 0.0), np.nextafter(hi, np.inf)):
        with pytest.raises(errors.InputError, match="outside"):
            Material(E=float(E), nu=0.3)


@pytest.mark.parametrize("normal", [[1e308, 1e308], [-1.7e308, 1e308], [5e-324, 0.0], [1e-320, 1e-320]])
def test_extreme_normals_are_normalized_without_overflow(normal):
    """A direction is a direction: |n| = 1 to 1e-15 and parallel to the input, without a RuntimeWarning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        n = HalfSpace([0.0, 0.0], normal).normal_vector
    assert abs(np.linalg.norm(n) - 1.0) <= 1e-15
    ref = np.asarray(normal) / np.max(np.abs(normal))
    assert np.allclose(n, ref / np.linalg.norm(ref), rtol=1e-15, atol=0)


def test_polytope_with_huge_rows_is_normalized():
    """A x <= b with rows of size 1e308 is the square [-1, 1]^2 (rows scaled before their norms)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ob = ConvexPolytope(np.array([[1e308, 0], [-1e308, 0], [0, 1], [0, -1.0]]), np.array([1e308, 1e308, 1, 1.0]))
    assert np.allclose(np.sort(ob.vertices, axis=0), [[-1, -1], [-1, -1], [1, 1], [1, 1]])


def test_uniform_at_the_limit_is_accepted():
    times = LoadHistory.uniform(MAX_STEPS)
    assert len(times) == MAX_STEPS and times[-1] == 1.0


# ------------------------------------------------------------------ rigid motions on each solver path
def _held_by_obstacle(*extra):
    """Block on a half-space, x fixed on the left, pressed down: translation y is held only by the obstacle."""
    model = LinearElasticity(meshes.rectangle(-1.0, 1.0, 0.0, 0.5, 8, 2), Material(E=1000.0, nu=0.3))
    return ContactProblem(model, HalfSpace([0.0, 0.0], [0.0, 1.0]), "bottom",
                          supports=(Support("left", components=(0,)), *extra), loads=(Pressure("top", 1.0),))


def test_direct_path_lets_the_obstacle_hold_the_body():
    sol = solve(_held_by_obstacle())
    assert isinstance(sol, ContactSolution) and sol.result.status > 0


def test_amg_path_lets_the_obstacle_hold_the_body_and_names_the_way_out_when_nothing_does():
    """Issue 9: the AMG path holds the body by contact springs as the direct path does (same displacement,
    relative 1e-8); with the obstacle out of reach the error names the free motion and the support."""
    ref = solve(_held_by_obstacle())
    sol = solve(_held_by_obstacle(), linear_solver="amg")
    assert isinstance(sol, ContactSolution) and sol.result.status > 0
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-8 * np.max(np.abs(ref.u))
    far = dataclasses.replace(_held_by_obstacle(), obstacle=HalfSpace([0.0, -1.0], [0.0, 1.0]))
    with pytest.raises(errors.InputError) as info:
        solve(far, linear_solver="amg")
    msg = str(info.value)
    for w in ("translation y", "does not touch the obstacle", "Support('left', components=[1])",
              "[[support]] boundary = 'left', components = [1]"):
        assert w in msg, (w, msg)
    assert "model.dirichlet" not in msg
    # the suggested support is enough for the AMG path
    sol = solve(_held_by_obstacle(Support("left", components=(1,))), linear_solver="amg")
    assert isinstance(sol, ContactSolution)


def test_friction_path_lets_the_obstacle_hold_the_body_and_names_the_way_out_when_nothing_does():
    sol = solve_friction(_held_by_obstacle(), LoadHistory((), LoadHistory.uniform(2)), friction=0.3)
    assert sol.status > 0, sol.message
    # the same body with the obstacle out of reach: nothing holds translation y
    far = dataclasses.replace(_held_by_obstacle(), obstacle=HalfSpace([0.0, -1.0], [0.0, 1.0]))
    with pytest.raises(errors.InputError) as info:
        solve_friction(far, LoadHistory((), LoadHistory.uniform(2)), friction=0.3)
    msg = str(info.value)
    for w in ("translation y", "components=[1])", "[[support]]", "nothing restrains it"):
        assert w in msg, (w, msg)


def test_model_solve_without_supports_names_every_motion_and_both_ways_out():
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1.0, nu=0.3))
    with pytest.raises(errors.InputError) as info:
        model.solve(np.zeros(model.ndofs))
    msg = str(info.value)
    assert "singular" in msg and "translation x; translation y; rotation about z" in msg
    assert "Support(" in msg and "[[support]]" in msg


# ------------------------------------------------------------------ Gmsh file without a body group
def test_load_problem_names_the_physical_groups_of_a_lines_only_gmsh_file(tmp_path):
    """``load_problem`` alone (not only ``check``) says which groups the file has and how to add the body."""
    from test_mesh_quality import _FILE_PROBLEM, _write_msh

    good = meshes.rectangle(0, 1, 0, 1, 4, 4)
    _write_msh(tmp_path / "lines.msh", good, good.boundaries, body=False)
    with pytest.raises(errors.ConfigError) as info:
        (tmp_path / "p.toml").write_text(_FILE_PROBLEM.format(name="lines.msh"))
        load_problem(tmp_path / "p.toml")
    msg = str(info.value)
    assert "mesh.file" in msg and "'bottom', 'left', 'right', 'top'" in msg and "Physical Surface" in msg
    assert "the mesh is 1D" not in msg


# ------------------------------------------------------------------ random problems: solution or project error
_FLOATS = st.one_of(
    st.floats(-2.0, 2.0),
    st.sampled_from([0.0, -0.0, 1e-320, 1e-100, 1e100, 1e200, 1e308, -1e308, math.inf, -math.inf, math.nan]),
)
_ANY = st.one_of(_FLOATS, st.sampled_from([10**400, True, None, "1", [1.0]]))
_BOUNDARIES = ["left", "right", "top", "bottom", "nowhere"]


_PARTS = ("material", "obstacle", "supports", "loads")


@st.composite
def _problem(draw):
    """A block on an obstacle; in about half of the examples one part gets random (possibly bad) values."""
    bad = draw(st.sampled_from((None,) * 4 + _PARTS))

    def num(good, part):
        return draw(st.one_of(good, _ANY) if bad == part else good)

    mat = Material(E=num(st.floats(0.5, 2e3), "material"), nu=num(st.floats(-0.5, 0.45), "material"))
    n = draw(st.integers(1, 3))
    model = LinearElasticity(meshes.rectangle(0.0, 1.0, 0.0, 1.0, n, n), mat)
    if draw(st.booleans()):
        ob = HalfSpace([num(st.floats(-1.0, 2.0), "obstacle"), num(st.floats(-0.1, 0.05), "obstacle")],
                       [num(st.floats(-0.3, 0.3), "obstacle"), num(st.floats(0.5, 1.0), "obstacle")])
    else:
        r = num(st.floats(0.5, 3.0), "obstacle")
        dy = draw(st.floats(-0.1, 0.05))
        ob = Circle([num(st.floats(0.0, 1.0), "obstacle"), -r + dy if isinstance(r, float) and math.isfinite(r)
                     else num(st.floats(-3.0, 0.0), "obstacle")], r)
    boundary = st.sampled_from(_BOUNDARIES) if bad == "supports" else st.sampled_from(["top", "left", "right"])
    supports = [Support("top", (1,), num(st.floats(-0.05, 0.0), "supports"))]
    for _ in range(draw(st.integers(0, 2))):  # x held on a side (conflicting values only as bad input)
        comps = draw(st.sampled_from([(0,)] + ([None, (1,), (2,), (0, 0)] if bad == "supports" else [])))
        supports.append(Support(draw(boundary), comps, num(st.just(0.0), "supports")))
    if draw(st.booleans()):
        supports = supports[1:]  # maybe no support on top: held by loads and the obstacle, or not at all
    loads = []
    lb = st.sampled_from(_BOUNDARIES) if bad == "loads" else st.sampled_from(["top", "left", "right"])
    for _ in range(draw(st.integers(0, 2))):
        if draw(st.booleans()):
            loads.append(Pressure(draw(lb), num(st.floats(0.0, 5.0), "loads")))
        else:
            loads.append(Traction(draw(lb), (num(st.floats(-1.0, 1.0), "loads"), num(st.floats(-5.0, 0.0), "loads"))))
    contact = draw(st.sampled_from(["bottom"] * 3 + ["nowhere"])) if bad == "supports" else "bottom"
    return ContactProblem(model, ob, contact, supports=tuple(supports), loads=tuple(loads))


@settings(max_examples=200, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(data=st.data())
def test_random_problems_solve_or_raise_a_project_error(data):
    """Building and solving never fails with anything but an ``alcontact.errors`` type (or a solution)."""
    try:
        prob = data.draw(_problem())
        algorithm = data.draw(st.sampled_from(["ssn", "family-p"]))
        sol = solve(prob, algorithm, maxiter=15)
    except errors.AlcontactError:
        return
    assert isinstance(sol, ContactSolution)
    status = sol.result.status
    assert isinstance(status, int) and status != 0 and sol.result.message
    if status > 0:  # a solution reported converged is a finite field with the right shapes
        assert np.all(np.isfinite(sol.u)) and sol.u.shape == (prob.model.ndofs,)
        assert sol.pressure.shape == sol.gap.shape == (sol.points.shape[0],)


# ------------------------------------------------------------------ built-in problems: the preflight size check
def test_builtin_problem_too_large_is_refused_before_meshing(tmp_path):
    """``run --problem hertz-3d --level 5 --order 2`` (about 13 M DOFs) is refused with exit 2, nothing written."""
    from typer.testing import CliRunner

    from alcontact.cli import app
    from alcontact.io.preflight import MAX_DOFS

    out = tmp_path / "res"
    result = CliRunner(env={"COLUMNS": "400", "NO_COLOR": "1"}).invoke(
        app, ["run", "--problem", "hertz-3d", "--level", "5", "--order", "2", "--out", str(out)])
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    for w in ("--problem hertz-3d --level 5 --order 2", "DOFs", f"more than {MAX_DOFS:,} DOFs", "--level (0 .. 4)",
              "--order 1"):
        assert w in text, (w, text)
    assert not out.exists()


@pytest.mark.parametrize("dim,level", [(2, 0), (3, 0)])
def test_builtin_mesh_spec_counts_are_exact(dim, level):
    """The counts the check uses (hertz.mesh_spec + preflight) equal the built problem's nodes and elements."""
    from alcontact.io import preflight
    from alcontact.problems import hertz

    levels = hertz.LEVELS_2D if dim == 2 else hertz.LEVELS_3D
    md = hertz.mesh_spec(dim, levels[level], 1)
    est = preflight.estimate_size({"mesh": {**md, "generator": "rectangle" if dim == 2 else "box", "order": 1}})
    prob = (hertz.hertz_2d if dim == 2 else hertz.hertz_3d)(level=level)
    assert est.ndofs == prob.model.ndofs and est.elements == prob.model.mesh.nelements
