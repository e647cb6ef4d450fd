"""Axisymmetric bodies (``geometry="axisymmetric"``) against closed-form solutions.

References and tolerances:

- Lamé thick cylinder (Timoshenko & Goodier, *Theory of Elasticity*, 1951, sec. 28), inner
  radius a = 1, outer b = 2, internal pressure p, plane strain (u_z = 0):
  ``u_r = (1 + nu)/E * A * ((1 - 2 nu) r + b^2 / r)``, ``A = p a^2 / (b^2 - a^2)``,
  ``sigma_tt(a) = p (a^2 + b^2) / (b^2 - a^2)``. P2 nodal u_r within 5e-5 (relative) at 16
  elements across the wall, converging at least at rate 2 (measured 2.6-2.8); P1 converging.
- Uniform compression of a solid cylinder (u_r = -p (1 - 2 nu)(1 + nu)/E r, u_z = 0): a linear
  field, exact for P1 to round-off, axis included (patch test).
- Hertz: rigid sphere on an elastic cylinder (Johnson, *Contact Mechanics*, 1985, eq. 4.22-4.23),
  ``a = (3PR/4E*)^(1/3)``, ``p0 = 3P/(2 pi a^2)``, P the total load of the model (2 pi
  integrated), a/R about 0.1: P1 peak nodal pressure within 1% at 128 elements per a with the
  error decreasing over four meshes (measured 2.4%, 1.7%, 1.2%, 0.85%); contact radius within 1%
  on every mesh; P2 within 1% (a and p0).
"""

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Support, solve
from alcontact.contact.obstacles import Circle
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.problems import hertz

E, NU = 1000.0, 0.3


def _lame(n: int, order: int):
    a, b, p = 1.0, 2.0, 1.0
    model = LinearElasticity(meshes.rectangle(a, b, 0.0, 0.5, n, max(1, n // 4)), Material(E, NU), order=order,
                             geometry="axisymmetric")
    bc = [model.dirichlet("bottom", components=[1]), model.dirichlet("top", components=[1])]
    u = model.solve(model.pressure_load("left", p), dirichlet=bc)
    pts, dofs = model.all_node_dofs()
    r = pts[:, 0]
    A = p * a * a / (b * b - a * a)
    exact = (1 + NU) / E * A * ((1 - 2 * NU) * r + b * b / r)
    err = float(np.max(np.abs(u[dofs[:, 0]] - exact)) / np.max(np.abs(exact)))
    return err, model, u


def test_lame_cylinder_p2_converges_to_closed_form():
    errs = [_lame(n, 2)[0] for n in (4, 8, 16)]
    assert errs[-1] <= 5e-5, errs
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(rates >= 2.0), (errs, rates)


def test_lame_cylinder_p1_converges_and_hoop_stress():
    errs = [_lame(n, 1)[0] for n in (4, 8, 16)]
    assert errs[0] > errs[1] > errs[2] and errs[-1] <= 5e-3, errs
    _, model, u = _lame(16, 2)
    s = model.stress(u, include_zz=True)  # columns rr, zz, rz, hoop
    pts, _ = model.all_node_dofs()
    inner = np.isclose(pts[:, 0], 1.0)
    exact = 1.0 * (1.0 + 4.0) / (4.0 - 1.0)
    assert np.max(np.abs(s[inner, 3] / exact - 1)) <= 2e-2
    assert np.max(np.abs(s[inner, 0] / -1.0 - 1)) <= 2e-2  # sigma_rr(a) = -p


def test_uniform_compression_is_exact_for_p1_with_the_axis():
    p = 2.0
    model = LinearElasticity(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 5, 4), Material(E, NU), geometry="axisymmetric")
    bc = [model.dirichlet("bottom", components=[1]), model.dirichlet("top", components=[1])]
    u = model.solve(model.pressure_load("right", p), dirichlet=bc)
    pts, dofs = model.all_node_dofs()
    exact = -p * (1 - 2 * NU) * (1 + NU) / E * pts[:, 0]
    np.testing.assert_allclose(u[dofs[:, 0]], exact, atol=1e-12 * p / E)
    np.testing.assert_allclose(u[dofs[:, 1]], 0.0, atol=1e-12 * p / E)
    assert model.axis_dofs.size == 5 and np.all(u[model.axis_dofs] == 0.0)


def test_forces_are_totals_over_the_revolution():
    """A traction t on the top face of a cylinder of radius 1 carries t * pi * 1^2 in total."""
    model = LinearElasticity(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 3, 3), Material(E, NU), order=2,
                             geometry="axisymmetric")
    f = model.traction_load("top", [0.0, -3.0])
    _, dofs = model.node_dofs("top")
    assert f[dofs[:, 1]].sum() == pytest.approx(-3.0 * np.pi, rel=1e-12)
    assert model.boundary_weights("top").sum() == pytest.approx(np.pi, rel=1e-12)
    assert model.boundary_weights("right").sum() == pytest.approx(2 * np.pi, rel=1e-12)
    assert np.all(model.boundary_weights("top") > 0)  # P2: the axis vertex too
    assert model.body_load([0.0, 1.0])[model.dof_map[:, 1]].sum() == pytest.approx(np.pi, rel=1e-12)


def _hertz_errors(prob, sol):
    ref = prob.reference
    P = ref.load(sol.normal_force)
    a_ex, p0_ex = ref.half_width(P), ref.peak_pressure(P)
    return {"a": sol.contact_half_width(axis=0, center=(0.0, 0.0)) / a_ex - 1,
            "p0": sol.peak_pressure_nodal_max / p0_ex - 1, "a_over_R": a_ex / ref.radius}


@pytest.fixture(scope="module")
def hertz_axisym_p1():
    out = []
    for level in (1, 2, 3, 4):
        prob = hertz.hertz_axisym(level)
        sol = solve(prob)
        assert sol.result.success, sol.result.message
        out.append(_hertz_errors(prob, sol))
    return out


def test_hertz_axisym_p1_within_1_percent_and_converging(hertz_axisym_p1):
    p0 = [abs(e["p0"]) for e in hertz_axisym_p1]
    assert all(x > y for x, y in zip(p0, p0[1:])), p0
    assert p0[-1] <= 0.01, p0
    assert all(abs(e["a"]) <= 0.01 for e in hertz_axisym_p1), hertz_axisym_p1
    assert 0.09 < hertz_axisym_p1[-1]["a_over_R"] < 0.11


def test_hertz_axisym_p2_within_1_percent():
    prob = hertz.hertz_axisym(1, order=2)
    sol = solve(prob)
    assert sol.result.success, sol.result.message
    err = _hertz_errors(prob, sol)
    assert abs(err["a"]) <= 0.01 and abs(err["p0"]) <= 0.01, err


def test_hertz_axisym_matches_the_3d_quarter_model_force():
    """Same approach, same body of revolution: the axisymmetric total force is 4 times the 3D quarter's
    (coarse 3D mesh: within 3%)."""
    ax = solve(hertz.hertz_axisym(0, size=6.0))
    q = solve(hertz.hertz_3d(0, size=6.0))
    assert ax.result.success and q.result.success
    assert ax.normal_force == pytest.approx(4.0 * q.normal_force, rel=3e-2)


# ------------------------------------------------------------------------------------------- bad input
def test_axisymmetric_refuses_3d_negative_radius_plane_stress_and_p0():
    with pytest.raises(InputError, match="geometry='axisymmetric' needs a 2D mesh"):
        LinearElasticity(meshes.box(0, 1, 0, 1, 0, 1, 1, 1, 1), Material(E, NU), geometry="axisymmetric")
    with pytest.raises(InputError, match="x >= 0"):
        LinearElasticity(meshes.rectangle(-1, 1, 0, 1, 2, 2), Material(E, NU), geometry="axisymmetric")
    with pytest.raises(InputError, match="plane='stress'"):
        LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E, NU, plane="stress"),
                         geometry="axisymmetric")
    with pytest.raises(InputError, match="volumetric='p0'"):
        LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E, NU), order=2, volumetric="p0",
                         geometry="axisymmetric")
    with pytest.raises(InputError, match="geometry='cylindrical' is not known"):
        LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E, NU), geometry="cylindrical")


def test_a_nonzero_radial_support_on_the_axis_is_refused():
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E, NU), geometry="axisymmetric")
    with pytest.raises(InputError, match="u_r = 0.1 prescribed on the axis"):
        model.dirichlet("left", components=[0], value=0.1)
    with pytest.raises(InputError, match="on the axis"):
        ContactProblem(model=model, obstacle=Circle(center=(0.0, 11.0), radius=10.0), contact_boundary="top",
                       supports=[Support("bottom", value=0.1)])
    model.dirichlet("left", components=[1], value=0.1)  # axial motion of the axis is allowed


def test_axis_is_fixed_by_the_body_and_only_the_axial_translation_is_a_rigid_motion():
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E, NU), geometry="axisymmetric")
    prob = ContactProblem(model=model, obstacle=Circle(center=(0.0, 11.0), radius=10.0), contact_boundary="top",
                          supports=[Support("bottom", components=(1,))])
    fixed, vals = prob.dirichlet()
    assert set(model.axis_dofs) <= set(fixed.tolist()) and np.all(vals[np.isin(fixed, model.axis_dofs)] == 0)
    model.check_restrained(fixed)  # u_z on the bottom stops the only rigid motion
    with pytest.raises(InputError, match="translation along the axis"):
        model.check_restrained(model.axis_dofs)
