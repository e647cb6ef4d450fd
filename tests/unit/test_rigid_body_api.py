"""``contact.RigidBody`` and ``contact.RigidLoad``: what they accept, the gap rows, the errors for bad input."""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import (Boundary, ContactPair, ContactProblem, Master, RigidBody, RigidLoad, Support,
                               obstacles)
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, MultiBody, meshes


def _punch():
    return RigidBody(obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, -1.0]), [0.5, 0.0])


def test_a_rigid_body_is_a_master_and_a_body_of_three_dofs():
    body = _punch()
    assert isinstance(body, Master) and body.rigid is False and body.body is body
    assert body.ndofs == 3 and body.dof_names == ["u_x", "u_y", "rot_z"] and body.boundary_names == ["reference"]
    assert body.stiffness().shape == (3, 3) and body.stiffness().nnz == 0
    dofs, vals = body.dirichlet("reference", [1, 2], [-0.01, 0.002])
    assert dofs.tolist() == [1, 2] and vals.tolist() == [-0.01, 0.002]
    dofs, vals = body.dirichlet("reference", [2], [0.0, -0.01, 0.3])  # the whole pose, component 2 taken
    assert vals.tolist() == [0.3]
    np.testing.assert_array_equal(body.traction_load("reference", [1.0, 2.0, 3.0]), [1.0, 2.0, 3.0])
    assert body.gap([[0.0, 0.05]])[0] == pytest.approx(0.05)  # inside the punch (y > 0) by 0.05
    moved = body.placed([0.0, 0.1, 0.0])  # the punch lifted by 0.1: the point is 0.05 below it
    assert moved.gap([[0.0, 0.05]])[0] == pytest.approx(-0.05)


def test_the_gap_rows_couple_the_slave_points_and_the_pose():
    """Against a flat punch face y = 0 (normal -y), a slave point at (x, 0) moving up by v and the punch lifted by
    c_y and turned by theta: g = v - c_y - theta (x - x0) (the linearized (6.15) against the moved face)."""
    block = LinearElasticity(meshes.rectangle(0.0, 1.0, -1.0, 0.0, 2, 2), Material(E=1.0, nu=0.3))
    punch = _punch()
    prob = ContactProblem(bodies=[block, punch], pairs=[ContactPair(Boundary(block, "top"), punch)],
                          supports=[Support("body0/bottom"), Support("body1")])
    from alcontact.contact import pair_start

    st = pair_start(prob)
    model = prob.model
    assert isinstance(model, MultiBody) and model.ndofs == block.ndofs + 3
    pts, dofs = block.node_dofs("top")
    u = np.zeros(model.ndofs)
    u[dofs[:, 1]] = 0.01
    u[-3:] = [0.0, 0.004, 0.02]
    g = st.B @ u + st.gaps
    np.testing.assert_allclose(g, 0.01 - 0.004 - 0.02 * (pts[:, 0] - 0.5), atol=1e-15)


@pytest.mark.parametrize("args, match", [
    (("not a shape", [0.0, 0.0]), "expected a rigid obstacle"),
    ((obstacles.make("circle", center=[0.0, 0.0], radius=1.0), [0.0, "a"]), "reference point"),
    ((obstacles.make("circle", center=[0.0, 0.0], radius=1.0), [0.0, 0.0, 0.0]), "2D"),
])
def test_bad_rigid_body_arguments_are_named(args, match):
    with pytest.raises(InputError, match=match):
        RigidBody(*args)


def test_bad_components_and_values_are_named():
    body = _punch()
    with pytest.raises(InputError, match=r"0\.\.2 \(0 = u_x, 1 = u_y, 2 = rot_z\)"):
        body.dirichlet("reference", [3])
    with pytest.raises(InputError, match="3 numbers"):
        body.dirichlet("reference", None, [1.0, 2.0])
    with pytest.raises(InputError, match="3 finite numbers"):
        body.traction_load("reference", [1.0, 2.0])
    with pytest.raises(InputError, match="RigidLoad"):
        body.pressure_load("reference", 1.0)
    with pytest.raises(Exception, match="reference"):
        body.facets("top")


@pytest.mark.parametrize("kwargs, match", [
    (dict(force=[1.0]), "force"),
    (dict(force=[1.0, 2.0], moment=[1.0, 2.0]), "moment"),
    (dict(vector=[1.0, 2.0, 3.0], force=[1.0, 2.0]), "not both"),
])
def test_bad_rigid_loads_are_named(kwargs, match):
    with pytest.raises(InputError, match=match):
        RigidLoad("body1", **kwargs)


def test_a_rigid_body_is_never_a_slave_and_takes_no_friction():
    from alcontact.contact import pair_start

    block = LinearElasticity(meshes.rectangle(0.0, 1.0, -1.0, 0.0, 2, 2), Material(E=1.0, nu=0.3))
    punch = _punch()
    bad = ContactProblem(bodies=[block, punch], pairs=[ContactPair(Boundary(punch, "reference"), punch)],
                         supports=[Support("body0/bottom"), Support("body1")])
    with pytest.raises(InputError, match="a rigid body .* is a master"):
        pair_start(bad)
    with pytest.raises(InputError, match="friction"):
        ContactProblem(bodies=[block, punch], pairs=[ContactPair(Boundary(block, "top"), punch, friction=0.3)],
                       supports=[Support("body0/bottom"), Support("body1")])
