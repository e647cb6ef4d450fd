"""Several bodies (MultiBody), the deformable master (BodySurface), the mortar gap and their refusals."""

import numpy as np
import pytest

from alcontact.contact import BodySurface, Boundary, ContactPair, ContactProblem, Master, Pressure, Support, solve
from alcontact.errors import InputError, MeshError
from alcontact.fem import LinearElasticity, Material, MultiBody, meshes
from alcontact.problems import two_body


def _blocks(n_base=2, n_top=3):
    base = LinearElasticity(meshes.rectangle(0, 1, 0, 1, n_base, n_base), Material(E=1000.0, nu=0.3))
    top = LinearElasticity(meshes.rectangle(0, 1, 1, 2, n_top, n_top), Material(E=500.0, nu=0.2))
    return base, top


# ------------------------------------------------------------------------------------------ MultiBody
def test_multibody_stacks_dofs_and_names_boundaries():
    base, top = _blocks()
    both = MultiBody([base, top], names=["base", "lid"])
    assert both.ndofs == base.ndofs + top.ndofs and both.offsets.tolist() == [0, base.ndofs, both.ndofs]
    assert "base/top" in both.boundary_names and "lid/bottom" in both.boundary_names
    pts, dofs = both.node_dofs("lid/bottom")
    p0, d0 = top.node_dofs("bottom")
    np.testing.assert_array_equal(pts, p0)
    np.testing.assert_array_equal(dofs, d0 + base.ndofs)
    K = both.stiffness()
    assert abs(K[: base.ndofs, base.ndofs:]).sum() == 0.0  # no coupling without contact
    u = np.arange(both.ndofs, dtype=float)
    np.testing.assert_array_equal(both.split(u)[1], u[base.ndofs:])


def test_multibody_boundary_names_are_checked():
    base, top = _blocks()
    both = MultiBody([base, top])
    with pytest.raises(MeshError, match="several bodies.*body0/top"):
        both.facets("top")
    with pytest.raises(MeshError, match="not found; known: body0/bottom"):
        both.facets("body2/top")


def test_multibody_loads_and_supports_act_on_their_body():
    base, top = _blocks()
    both = MultiBody([base, top])
    f = both.pressure_load("body1/top", 2.0)
    assert np.all(f[: base.ndofs] == 0.0)
    np.testing.assert_allclose(f[base.ndofs:], top.pressure_load("top", 2.0))
    dofs, vals = both.dirichlet("body1/left", [0], 0.5)
    assert dofs.min() >= base.ndofs and np.all(vals == 0.5)


def test_multibody_names_the_body_left_free():
    base, top = _blocks()
    both = MultiBody([base, top], names=["base", "lid"])
    fixed, _ = both.dirichlet("base/bottom")
    with pytest.raises(InputError, match="body 'lid'.*rigid-body motion"):
        both.check_restrained(fixed)


def test_multibody_refuses_mixed_dimensions():
    base, _ = _blocks()
    cube = LinearElasticity(meshes.box(0, 1, 0, 1, 0, 1, 1, 1, 1), Material(E=1.0, nu=0.3))
    with pytest.raises(InputError, match="different dimensions"):
        MultiBody([base, cube])


# ------------------------------------------------------------------------------------------ BodySurface
def test_body_surface_is_a_deformable_master():
    base, _ = _blocks()
    surface = BodySurface(base, "top")
    assert isinstance(surface, Master) and surface.rigid is False
    g, nu = surface.evaluate([[0.3, 1.2], [0.7, 0.9]])
    np.testing.assert_allclose(g, [-0.2, 0.1], atol=1e-12)  # 0.2 above (free), 0.1 inside (penetration)
    np.testing.assert_allclose(nu, [[0.0, 1.0], [0.0, 1.0]], atol=1e-12)
    lo, hi = surface.bounding_box(2)
    np.testing.assert_allclose([lo, hi], [[0.0, 1.0], [1.0, 1.0]])
    with pytest.raises(InputError, match="2D"):
        surface.check_dim(3)


def test_body_surface_of_p2_and_3d_bodies():
    body = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1.0, nu=0.3), order=2)
    seg = BodySurface(body, "top").segments
    assert seg.nodes.shape == (2, 3)  # two edges: their ends and midpoints
    np.testing.assert_allclose(seg.points[seg.nodes[:, 2], 0], [0.25, 0.75])
    cube = LinearElasticity(meshes.box(0, 1, 0, 1, 0, 1, 1, 1, 1), Material(E=1.0, nu=0.3))
    with pytest.raises(InputError, match="2D"):
        BodySurface(cube, "top")


# ------------------------------------------------------------------------------------------ mortar gap
def test_mortar_gap_is_invariant_under_a_common_translation():
    prob = two_body.hertz_cylinders(0)
    sol = solve(prob, "ssn")
    from alcontact.contact.kinematics._mortar import mortar_gap  # the kinematics itself, no public name yet

    pair = prob.pairs[0]
    mg = mortar_gap(prob.model, pair.slave.body, pair.slave.name, pair.master)
    t = np.zeros(prob.model.ndofs)
    _, dofs = prob.model.all_node_dofs()
    t[dofs[:, 0]], t[dofs[:, 1]] = 0.3, -0.7  # both bodies moved together
    covered = mg.covered
    np.testing.assert_allclose((mg.B @ t)[covered], 0.0, atol=1e-12)
    # the slave weights are the tributary lengths (the dual basis keeps D diagonal)
    np.testing.assert_allclose(mg.weights, pair.slave.body.boundary_weights(pair.slave.name), rtol=1e-12)
    assert sol.result.success


# ------------------------------------------------------------------------------------------ refusals
def test_same_boundary_as_slave_and_master_is_refused():
    base, _ = _blocks()
    with pytest.raises(InputError, match="both slave and master"):
        ContactProblem(bodies=[base], pairs=[ContactPair(Boundary(base, "top"), BodySurface(base, "top"))],
                       supports=[Support("bottom")])


def test_master_body_missing_from_bodies_is_refused():
    base, top = _blocks()
    with pytest.raises(InputError, match="BodySurface.*in bodies"):
        ContactProblem(bodies=[top], pairs=[ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))],
                       supports=[Support("top")])


def test_friction_between_bodies_is_refused():
    base, top = _blocks()
    with pytest.raises(InputError, match="friction between two deformable bodies is not supported yet"):
        ContactProblem(bodies=[base, top], pairs=[ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"),
                                                              friction=0.2)],
                       supports=[Support("body0/bottom"), Support("body1/top")])


def test_finite_deformation_between_bodies_is_refused():
    prob = two_body.stacked_blocks(2, 3)
    with pytest.raises(InputError, match="finite"):
        ContactProblem(bodies=list(prob.bodies), pairs=list(prob.pairs), supports=prob.supports,
                       loads=prob.loads, kinematics="finite")


def test_unqualified_boundary_of_several_bodies_is_refused():
    base, top = _blocks()
    with pytest.raises(MeshError, match="several bodies"):
        ContactProblem(bodies=[base, top], pairs=[ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))],
                       supports=[Support("bottom")], loads=[Pressure("body1/top", 1.0)])


# ------------------------------------------------------------------------------------------ outputs
def test_outputs_of_two_bodies(tmp_path):
    import meshio

    from alcontact.app.summary import summarize
    from alcontact.app.writer import write_results

    prob = two_body.stacked_blocks(2, 3)
    sol = solve(prob, "ssn")
    base, top = prob.bodies
    # per-body displacement: the stack split body by body
    u_base, u_top = prob.model.split(sol.u)
    assert u_base.size == base.ndofs and u_top.size == top.ndofs
    summary = summarize(prob, sol)
    assert summary["contact_force_balance"] <= 1e-10
    np.testing.assert_allclose(np.add(summary["slave_contact_force"], summary["master_contact_force"]), 0.0,
                               atol=1e-10 * 10.0)
    assert summary["equilibrium_residual"] <= 1e-10  # the master's contact forces are in the balance
    paths = write_results(tmp_path, prob, sol, summary)
    grid = meshio.read(paths["solution.vtu"])
    body = grid.point_data["body"]
    assert grid.points.shape[0] == base.mesh.nvertices + top.mesh.nvertices
    assert np.count_nonzero(body == 0) == base.mesh.nvertices and np.count_nonzero(body == 1) == top.mesh.nvertices
    p = grid.point_data["contact_pressure"]
    # the master side: the pressure carried to the base's 3 top vertices by the mortar weights, 0 elsewhere
    on_top = np.isclose(grid.points[body == 0][:, 1], 1.0)
    np.testing.assert_allclose(p[body == 0][on_top], 10.0, rtol=1e-10)
    assert np.all(p[body == 0][~on_top] == 0.0)
    np.testing.assert_allclose(np.sort(p[body == 1])[-4:], 10.0, rtol=1e-8)  # the 4 slave nodes
    np.testing.assert_allclose(grid.point_data["displacement"][body == 1][:, :2].ravel(),
                               u_top[top.dof_map].ravel(), rtol=1e-12, atol=1e-15)


def test_pair_out_of_reach_and_overlap_are_named(caplog):
    import logging

    base, _ = _blocks()
    far = LinearElasticity(meshes.rectangle(0, 1, 5, 6, 2, 2), Material(E=500.0, nu=0.2))
    prob = ContactProblem(bodies=[base, far], pairs=[ContactPair(Boundary(far, "bottom"),
                                                                 BodySurface(base, "top", search_distance=1.0))],
                          supports=[Support("body0/bottom"), Support("body1/top")])
    with caplog.at_level(logging.WARNING):
        sol = solve(prob, "ssn")
    assert "no slave node has a master segment within the search distance" in caplog.text
    assert sol.result.status.label == "no-contact"  # not a silent success
    caplog.clear()
    inside = LinearElasticity(meshes.rectangle(0, 1, 0.9, 1.9, 3, 3), Material(E=500.0, nu=0.2))
    prob = ContactProblem(bodies=[base, inside], pairs=[ContactPair(Boundary(inside, "bottom"),
                                                                    BodySurface(base, "top"))],
                          supports=[Support("body0/bottom"), Support("body1/top")])
    with caplog.at_level(logging.WARNING):
        solve(prob, "ssn")
    assert "overlap at the start by 0.1" in caplog.text


def test_load_steps_reuse_the_stack_and_its_factorization():
    import dataclasses

    prob = two_body.hertz_cylinders(0)
    assert dataclasses.replace(prob, name="again").model is prob.model  # the same stack of the same bodies
    sol = solve(prob, "ssn", steps=3)
    assert sol.result.success and len(sol.frames) == 3
    assert prob.model.factorization_count == 1  # one factorization for the three steps, as for one body


def test_friction_override_between_bodies_is_refused():
    prob = two_body.stacked_blocks(2, 3)
    with pytest.raises(InputError, match="friction between two deformable bodies is not supported yet"):
        solve(prob, "simo-laursen", friction=0.3)


def test_mortar_gap_is_a_contact_kinematics_and_gives_the_constraint_rows():
    """The mortar gap plugs in as a third ContactKinematics (not pointwise, reference configuration)."""
    from alcontact.contact.kinematics import ContactKinematics, MortarKinematics
    from alcontact.contact.kinematics._mortar import mortar_gap  # the pair's weighted gaps, no public name yet

    prob = two_body.stacked_blocks(2, 3)
    pair = prob.pairs[0]
    mg = mortar_gap(prob.model, pair.slave.body, pair.slave.name, pair.master)
    pts, dofs = prob.model.node_dofs(prob.contact_boundary)
    free = np.arange(prob.model.ndofs)
    kin = MortarKinematics(mg, pts, dofs, dofs, pair.master, free)
    assert isinstance(kin, ContactKinematics) and not kin.pointwise and kin.configuration == "reference"
    u = np.random.default_rng(1).normal(size=prob.model.ndofs)
    ev = kin.evaluate(u)
    np.testing.assert_allclose(ev.g, mg.gap0 + mg.B @ u, rtol=0, atol=1e-14)
    np.testing.assert_allclose(ev.gradient().toarray(), mg.B.toarray(), rtol=0, atol=0)
    assert kin.gaps(u, np.array([1])) == pytest.approx(ev.g[1], abs=1e-14)
