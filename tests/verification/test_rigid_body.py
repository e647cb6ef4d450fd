"""A rigid body driven by a prescribed motion or by a force and a moment (``contact.RigidBody``).

References and tolerances:

- **Force against displacement drive** (an exact identity of the discrete problem): a rigid
  body loaded by a force and a moment reaches a pose ``q``; the same body with the pose
  ``q`` prescribed has the same solution (every DOF within 1e-8 of the largest
  displacement) and its reaction is minus the applied force and moment (1e-8 relative).
  Flat punch (tilting under an eccentric load) and off-centre cylinder, 2D and 3D, the
  augmented Lagrangian algorithms and the semi-smooth Newton reference, direct and AMG paths.
- **Moment equilibrium** (statics of the rigid body, exact to round-off): the contact force
  and moment on a force-driven body equal minus the applied ones (1e-10 relative).
- **Tilted rigid flat punch on an elastic half-plane** (closed form: the airfoil equation for
  the surface slope ``du_z/dx = -(2 (1 - nu^2) / (pi E)) PV int p(s) / (x - s) ds`` of the
  half-plane, Johnson, *Contact Mechanics*, 1985, eq. (2.25b), with a constant slope under
  the punch of half-width ``a``): a force ``P`` and a moment ``M`` (counter-clockwise, about
  the punch centre, ``|M| < P a / 2`` so that the whole face stays in contact) give
  the pressure ``p(x) = (P/pi - 2 M x / (pi a^2)) / sqrt(a^2 - x^2)`` and the tilt
  ``theta = 4 (1 - nu^2) M / (pi E a^2)``. A block of half-width and depth ``32 a`` (measured: from
  ``16 a`` to ``32 a`` the finest tilt changes by 0.2 %) on graded meshes ``h = a/16, a/32, a/64``:
  the tilt error decreases at an observed rate within [0.8, 1.2] (first order: the pressure
  is singular at the punch edges), the finest within 1.5 %, the Richardson extrapolation of
  the two finest within 0.5 %; the pressure in ``|x| <= a/2`` on the finest mesh within
  1.5 % of ``P / (pi a)``.
- **A meshed rigid body** (the punch as a closed polyline, ``obstacles.make("surface")``, whose gap is
  the exact signed distance to its facets): the same pose and field as the analytic polygon to 1e-10.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import (Boundary, ContactPair, ContactProblem, LoadCase, LoadHistory, Ramp, RigidBody,
                               RigidLoad, Support, obstacles, solve)
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, meshes

E, NU = 1000.0, 0.3


def _block2d(half: float = 4.0, h: float = 1 / 16) -> LinearElasticity:
    mesh = meshes.rectangle(-half, half, -half, 0.0, 8, 4,
                            refine=dict(center=[0.0, 0.0], h_min=h, width=1.5, depth=1.0, growth=1.2))
    return LinearElasticity(mesh, Material(E=E, nu=NU))


def _flat_punch(a: float = 1.0) -> RigidBody:
    return RigidBody(obstacles.make("convex-polygon", vertices=[[-a, 0.0], [a, 0.0], [a, 2.0], [-a, 2.0]]),
                     [0.0, 0.0])


def _problem(block, body, supports, loads=()):
    return ContactProblem(bodies=[block, body], pairs=[ContactPair(Boundary(block, "top"), body)],
                          supports=[Support("body0/bottom"), *supports], loads=list(loads))


CASES = {  # (rigid body, its held components, the applied force and moment)
    "flat punch, eccentric load": (lambda: _flat_punch(), [0], [0.0, -10.0, 1.0]),
    "cylinder off centre": (lambda: RigidBody(obstacles.make("circle", center=[0.3, 1.0], radius=1.0), [0.3, 1.0]),
                            [0, 2], [0.0, -10.0, 0.0]),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("algorithm", ["ssn", "simo-laursen", "family-p"])
@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
def test_force_driven_equals_displacement_driven(case, algorithm, linear_solver):
    make, held, load = CASES[case]
    block, body = _block2d(), make()
    opts = {"linear_solver": linear_solver}
    forced = solve(_problem(block, body, [Support("body1", components=held)], [RigidLoad("body1", load)]),
                   algorithm, options=opts)
    assert forced.result.status > 0, forced.result.message
    q = forced.u[-3:]
    assert forced.extra["strategy"] == ("condensed" if linear_solver == "direct" else "krylov")
    driven = solve(_problem(block, body, [Support("body1", value=q.tolist())]), algorithm, options=opts)
    assert driven.result.status > 0, driven.result.message
    scale = np.max(np.abs(forced.u))
    assert np.max(np.abs(driven.u - forced.u)) <= 1e-8 * scale
    state = driven.extra["rigid_bodies"]["body1"]
    assert state["prescribed"] == ["u_x", "u_y", "rot_z"]
    reaction = np.array(state["reaction_force"] + state["reaction_moment"])
    free = [k for k in range(3) if k not in held]
    np.testing.assert_allclose(reaction[free], np.array(load)[free], rtol=1e-8, atol=1e-8 * abs(load[1]))
    # the force-driven body: statics of the rigid body (contact + applied = 0 on its free components)
    fs = forced.extra["rigid_bodies"]["body1"]
    contact = np.array(fs["contact_force"] + fs["contact_moment"])
    assert np.max(np.abs(contact[free] + np.array(load)[free])) <= 1e-10 * abs(load[1])
    np.testing.assert_allclose(fs["displacement"] + fs["rotation"], q, rtol=0, atol=0)
    # action = reaction between the block and the rigid body
    assert forced.extra["contact_force_balance"] <= 1e-12


def test_force_driven_3d_punch_tilts_about_two_axes():
    block = LinearElasticity(meshes.box(-2, 2, -2, 2, -2, 0, 8, 8, 4), Material(E=E, nu=NU))
    shape = obstacles.make("convex-polyhedron", vertices=[[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (0, 1)])
    body = RigidBody(shape, [0.0, 0.0, 0.0])
    load = [0.0, 0.0, -10.0, 0.5, -0.3, 0.0]
    forced = solve(_problem(block, body, [Support("body1", components=[0, 1, 5])], [RigidLoad("body1", load)]), "ssn")
    assert forced.result.status > 0, forced.result.message
    q = forced.u[-6:]
    assert q[3] > 0 and q[4] < 0  # a moment about +x turns the punch about +x, about -y about -y
    driven = solve(_problem(block, body, [Support("body1", value=q.tolist())]), "ssn")
    assert driven.result.status > 0
    assert np.max(np.abs(driven.u - forced.u)) <= 1e-8 * np.max(np.abs(forced.u))
    st = driven.extra["rigid_bodies"]["body1"]
    np.testing.assert_allclose(st["reaction_force"][2], load[2], rtol=1e-8)
    np.testing.assert_allclose(st["reaction_moment"][:2], load[3:5], rtol=1e-8)


def _tilted_punch(h: float, P: float = 10.0, M: float = 2.0, a: float = 1.0):
    block = _block2d(half=32.0 * a, h=h)
    sol = solve(_problem(block, _flat_punch(a), [Support("body1", components=[0])],
                         [RigidLoad("body1", force=[0.0, -P], moment=M)]), "ssn")
    assert sol.result.status > 0, sol.result.message
    return sol


def test_tilted_flat_punch_matches_the_half_plane_closed_form():
    P, M, a = 10.0, 2.0, 1.0
    exact = 4.0 * (1.0 - NU**2) * M / (np.pi * E * a**2)
    sols = [_tilted_punch(h, P, M, a) for h in (1 / 16, 1 / 32, 1 / 64)]
    tilt = np.array([s.extra["rigid_bodies"]["body1"]["rotation"][0] for s in sols])
    err = np.abs(tilt / exact - 1.0)
    rates = np.log2(err[:-1] / err[1:])
    assert np.all((rates >= 0.8) & (rates <= 1.2)), (err, rates)
    assert err[-1] <= 0.015, err
    assert abs((2 * tilt[-1] - tilt[-2]) / exact - 1.0) <= 0.005, tilt
    # the pressure away from the edges, and moment equilibrium of the punch
    fine = sols[-1]
    x = fine.points[:, 0]
    inner = np.abs(x) <= 0.5 * a
    p_exact = (P / np.pi - 2.0 * M * x[inner] / (np.pi * a**2)) / np.sqrt(a**2 - x[inner] ** 2)
    assert np.max(np.abs(fine.pressure[inner] - p_exact)) <= 0.015 * P / (np.pi * a)
    st = fine.extra["rigid_bodies"]["body1"]
    np.testing.assert_allclose(st["contact_moment"], [-M], rtol=1e-10)
    np.testing.assert_allclose(st["contact_force"], [0.0, P], rtol=1e-10, atol=1e-10 * P)


def test_load_steps_report_the_pose_and_reaction_of_every_step():
    block, body = _block2d(), _flat_punch()
    problem = _problem(block, body, [Support("body1", components=[0])])
    history = LoadHistory([LoadCase(RigidLoad("body1", force=[0.0, -10.0], moment=1.0),
                                    Ramp((0.0, 1.0), (0.0, 1.0)))], times=(0.5, 1.0))
    sol = solve(problem, "ssn", history=history)
    assert sol.result.status > 0, sol.result.message
    states = [f.rigid_bodies["body1"] for f in sol.frames]
    assert len(states) == 2
    np.testing.assert_allclose(states[0]["applied_force"], [0.0, -5.0])
    np.testing.assert_allclose(states[1]["applied_moment"], [1.0])
    # frictionless small deformation with the whole face in contact: the pose is linear in the load
    np.testing.assert_allclose(np.array(states[1]["rotation"]), 2 * np.array(states[0]["rotation"]), rtol=1e-8)
    np.testing.assert_allclose(states[1]["displacement"][1], 2 * states[0]["displacement"][1], rtol=1e-8)


def test_a_cylinder_free_to_turn_about_its_centre_is_refused_with_the_way_out():
    """A frictionless cylinder turning about its own centre changes no gap: nothing holds that rotation."""
    block = _block2d()
    body = RigidBody(obstacles.make("circle", center=[0.0, 1.0], radius=1.0), [0.0, 1.0])
    with pytest.raises(InputError, match="rot_z"):
        solve(_problem(block, body, [Support("body1", components=[0])], [RigidLoad("body1", force=[0.0, -1.0])]),
              "ssn")


def test_a_meshed_rigid_body_equals_the_analytic_one():
    """The punch as a meshed surface (a closed polyline, counter-clockwise) is the convex polygon exactly: the
    exact signed distance to its facets (``obstacles.make("surface")``); force-driven, the same pose to 1e-10."""
    block = _block2d()
    poly = [[-1.0, 0.0], [1.0, 0.0], [1.0, 2.0], [-1.0, 2.0]]
    meshed = RigidBody(obstacles.make("surface", vertices=poly, facets=[[0, 1], [1, 2], [2, 3], [3, 0]]), [0.0, 0.0])
    load = [RigidLoad("body1", force=[0.0, -10.0], moment=1.0)]
    a = solve(_problem(block, meshed, [Support("body1", components=[0])], load), "ssn")
    b = solve(_problem(block, _flat_punch(), [Support("body1", components=[0])], load), "ssn")
    assert a.result.status > 0 and b.result.status > 0
    np.testing.assert_allclose(a.u[-3:], b.u[-3:], rtol=1e-10)
    assert np.max(np.abs(a.u - b.u)) <= 1e-10 * np.max(np.abs(b.u))
    # a polyline whose segments disagree on the orientation is refused, naming them (MeshedSurface)
    with pytest.raises(InputError, match="segments 2 and 3 .* orientation is inconsistent"):
        RigidBody(obstacles.make("surface", vertices=poly, facets=[[0, 1], [1, 2], [3, 2], [3, 0]]), [0.0, 0.0])
