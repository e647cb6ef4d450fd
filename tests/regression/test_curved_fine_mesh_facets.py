"""Fine curved P2 meshes: facet bases and probes are built (the inverse element map stops at round-off).

scikit-fem's inverse of the isoparametric map asks every Newton step to fall below an absolute
1e-12. On the curved half-cylinder with 80 (51,842 DOFs) and 112 (101,250 DOFs, the 2d-100k
preset of ``benchmarks/finite.py``) elements per radius, round-off keeps some steps at 1-5e-12,
and building the contact boundary's facet basis raised "Newton iteration didn't converge".

Reference: the contact boundary is the quarter circle of radius 1, whose length pi/2 the
boundary weights (integrals of a partition of unity) must sum to; the curved P2 map is exact to
O(h^4), so 1e-9 at 80 elements per radius (measured 1.0e-11).
"""

import numpy as np

from alcontact.fem.quality import CurvedMapping, element_mapping
from alcontact.problems.half_cylinder import half_cylinder


def test_fine_curved_half_cylinder_builds_its_contact_weights():
    problem = half_cylinder(80, order=2)
    w = problem.model.boundary_weights(problem.contact_boundary)
    assert abs(w.sum() - np.pi / 2) < 1e-9
    assert isinstance(element_mapping(problem.model.mesh), CurvedMapping)


def test_inverse_map_recovers_reference_points():
    mesh = half_cylinder(80, order=2).model.mesh
    mapping = element_mapping(mesh)
    lam = np.random.default_rng(0).dirichlet(np.ones(3), size=(mesh.t.shape[1], 4))  # barycentric
    X = np.moveaxis(lam[..., 1:], -1, 0)  # (2, nelems, npoints) reference coordinates
    tind = np.arange(mesh.t.shape[1])
    assert np.max(np.abs(mapping.invF(mapping.F(X, tind), tind=tind) - X)) < 1e-9
