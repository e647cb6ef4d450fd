"""A geometrically nonlinear body at kinematics='small' is refused up front.

The small-deformation solvers take the body's stiffness as constant. With a hyperelastic body
every such solve ended NOT_VERIFIED on equilibrium after the whole run (status -8, in plane
strain and axisymmetric alike): the problem now refuses the combination with the way out.
"""

import pytest

from alcontact.contact import ContactProblem
from alcontact.errors import InputError
from alcontact.problems.half_cylinder import half_cylinder


def test_hyperelastic_body_at_small_kinematics_is_refused_with_the_way_out():
    p = half_cylinder(4, order=1)
    with pytest.raises(InputError, match=r"kinematics='small'.*Hyperelastic.*kinematics='finite'"):
        ContactProblem(p.model, p.obstacle, p.contact_boundary, supports=p.supports, loads=p.loads,
                       kinematics="small")
    # the same body at finite deformation is accepted (the refusal is about the combination)
    ContactProblem(p.model, p.obstacle, p.contact_boundary, supports=p.supports, loads=p.loads, kinematics="finite")
