"""3D mortar geometry: polygon clipping, the dual basis of the triangle, the face-pair integrals, the search.

References: the intersection area of two convex polygons against a plain Sutherland-Hodgman clip
(Sutherland & Hodgman, 1974) written here loop by loop; the dual basis property
int Phi_i N_k = delta_ik int N_i (Wohlmuth 2000); sum_j Phi_j = 1 and sum_k N_k = 1, so where the
master covers the slave the rows of M sum to D_j and its columns to the master's int N_k.
"""

import dataclasses

import numpy as np
import pytest
import skfem

from alcontact.contact import BodySurface, Boundary, ContactPair, ContactProblem, Support
from alcontact.contact.kinematics._clipping import TRIANGLE_RULES, clip_convex, fan_quadrature, signed_area
from alcontact.contact.kinematics._mortar3d import (dual_coefficients_triangle, face_pairs, mortar_gap_3d,
                                                     mortar_matrix, pair_integrals)
from alcontact.contact.masters._faces import boundary_faces
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.problems import two_body_3d


def _sutherland_hodgman(subject, clip):
    """Reference: clip polygon ``subject`` by the convex counter-clockwise ``clip``, edge by edge."""
    out = [np.asarray(p, float) for p in subject]
    for i in range(len(clip)):
        a, b = np.asarray(clip[i], float), np.asarray(clip[(i + 1) % len(clip)], float)
        inside = lambda p: (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0  # noqa: E731
        src, out = out, []
        for j in range(len(src)):
            p, q = src[j], src[(j + 1) % len(src)]
            if inside(q):
                if not inside(p):
                    out.append(_cross_point(p, q, a, b))
                out.append(q)
            elif inside(p):
                out.append(_cross_point(p, q, a, b))
        if not out:
            return np.zeros((0, 2))
    return np.array(out)


def _cross_point(p, q, a, b):
    d1, d2 = q - p, b - a
    t = ((a[0] - p[0]) * d2[1] - (a[1] - p[1]) * d2[0]) / (d1[0] * d2[1] - d1[1] * d2[0])
    return p + t * d1


def _area(poly):
    return 0.0 if len(poly) < 3 else float(signed_area(poly[None])[0])


def _ccw(tri):
    return tri if signed_area(tri[None])[0] > 0 else tri[::-1]


def test_clipping_equals_sutherland_hodgman_on_random_triangles():
    rng = np.random.default_rng(3)
    a = np.array([_ccw(t) for t in rng.uniform(0, 1, (300, 3, 2))])
    b = np.array([_ccw(t) for t in rng.uniform(0, 1, (300, 3, 2))])
    poly, valid = clip_convex(a, b)
    _, w = fan_quadrature(poly, valid, degree=1)
    ref = np.array([_area(_sutherland_hodgman(a[i], b[i])) for i in range(a.shape[0])])
    assert np.count_nonzero(ref > 1e-6) > 100 and np.count_nonzero(ref == 0.0) > 10  # both cases occur
    np.testing.assert_allclose(w.sum(axis=1), ref, atol=1e-13)


def test_clipping_of_coincident_and_touching_polygons():
    sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    cases = [(tri, tri, 0.5), (sq, sq, 1.0), (tri, tri + [1.0, 0.0], 0.0), (sq, sq + [1.0, 1.0], 0.0),
             (sq, 0.5 * sq + 0.25, 0.25), (tri, sq, 0.5)]
    for a, b, area in cases:
        n = max(len(a), len(b))
        pad = lambda p: np.vstack([p, np.repeat(p[-1:], n - len(p), axis=0)])  # noqa: E731 (repeated vertex)
        poly, valid = clip_convex(pad(a)[None], pad(b)[None])
        _, w = fan_quadrature(poly, valid)
        assert w.sum() == pytest.approx(area, abs=1e-14), (a, b)


def test_triangle_rules_are_exact_to_their_degree():
    tri = np.array([[0.1, 0.2], [1.3, 0.1], [0.4, 0.9]])
    area = signed_area(tri[None])[0]
    for degree, (bary, w) in TRIANGLE_RULES.items():
        x = bary @ tri
        for i in range(degree + 1):  # x^i y^(degree-i) against a fine rule
            f = lambda p: p[..., 0] ** i * p[..., 1] ** (degree - i)  # noqa: E731
            fine_b, fine_w = TRIANGLE_RULES[4]
            assert area * np.dot(w, f(x)) == pytest.approx(area * np.dot(fine_w, f(fine_b @ tri)), rel=1e-12)


def test_dual_basis_of_the_triangle_is_biorthogonal():
    A = dual_coefficients_triangle()
    np.testing.assert_allclose(A, 4.0 * np.eye(3) - 1.0, atol=1e-13)  # Phi_i = 4 N_i - 1
    bary, w = TRIANGLE_RULES[2]  # exact for Phi_i N_k (degree 2)
    phi = bary @ A.T
    np.testing.assert_allclose((phi * w[:, None]).T @ bary, np.eye(3) / 3.0, atol=1e-14)
    np.testing.assert_allclose(phi.sum(axis=1), 1.0, atol=1e-14)


def _flat_square(n, z, *, seed=None, outward_up=True):
    """A block whose face at height ``z`` is a flat unit square of ``n`` x ``n`` cells (perturbed in its plane)."""
    lo, hi = (z - 1.0, z) if outward_up else (z, z + 1.0)
    mesh = skfem.MeshTet.init_tensor(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), np.linspace(lo, hi, 3))
    if seed is not None:
        p = np.array(mesh.p)
        face = (np.abs(p[2] - z) < 1e-12) & (p[0] > 1e-9) & (p[0] < 1 - 1e-9) & (p[1] > 1e-9) & (p[1] < 1 - 1e-9)
        p[:2, face] += 0.3 / n * np.random.default_rng(seed).uniform(-1, 1, (2, int(face.sum())))
        mesh = dataclasses.replace(mesh, doflocs=p)
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    mesh = mesh.with_boundaries({"face": bf[np.abs(mid[2] - z) < 1e-12]})
    return LinearElasticity(mesh, Material(E=1.0, nu=0.3))


@pytest.mark.parametrize("ns,nm", [(2, 2), (2, 3), (3, 7), (7, 3)])
def test_mortar_matrix_rows_and_columns_sum_to_the_integrals(ns, nm):
    slave = boundary_faces(_flat_square(ns, 0.0, seed=1, outward_up=False), "face")
    master = boundary_faces(_flat_square(nm, 0.0, seed=2, outward_up=True), "face")
    s, m = face_pairs(slave, master, 0.1)
    M = mortar_matrix(slave, master, s, m)
    np.testing.assert_allclose(np.asarray(M.sum(axis=1)).ravel(), slave.integrals(), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.asarray(M.sum(axis=0)).ravel(), master.integrals(), rtol=1e-12, atol=1e-15)
    assert M.sum() == pytest.approx(1.0, rel=1e-13)  # the common area


def test_candidate_search_finds_every_overlapping_pair():
    """Against all pairs clipped (brute force): on the curved bottom of the sphere model and its block."""
    prob = two_body_3d.sphere_on_block(0)
    pair = prob.pairs[0]
    slave, master = boundary_faces(pair.slave.body, pair.slave.name), pair.master.faces
    near_s = np.flatnonzero(np.linalg.norm(slave.centroids[:, :2], axis=1) < 2.0)
    s_all = np.repeat(near_s, master.nodes.shape[0])
    m_all = np.tile(np.arange(master.nodes.shape[0]), near_s.size)
    keep = np.einsum("ij,ij->i", slave.normals[s_all], master.normals[m_all]) < 0
    brute = pair_integrals(slave, master, s_all[keep], m_all[keep])
    overlap = np.abs(brute).sum(axis=(1, 2)) > 0
    wanted = set(zip(s_all[keep][overlap].tolist(), m_all[keep][overlap].tolist()))
    s, m = face_pairs(slave, master, 1.0)  # every face near the centre is within 1.0 of the block
    found = set(zip(s.tolist(), m.tolist()))
    assert len(wanted) > 100 and wanted <= found
    assert len(found) < 20 * slave.nodes.shape[0]  # a handful of candidates per slave face


def test_flat_master_gap_is_the_distance_to_the_plane():
    """Rigid limit of the kinematics: against a flat master the weighted gap is the node's distance to it."""
    prob = two_body_3d.stacked_blocks_3d(3, 7)
    pair = prob.pairs[0]
    mg = mortar_gap_3d(prob.model, pair.slave.body, pair.slave.name, pair.master)
    assert mg.covered.all()
    np.testing.assert_allclose(mg.gap0, 0.0, atol=1e-14)
    np.testing.assert_allclose(mg.normals, np.tile([0.0, 0.0, 1.0], (mg.gap0.size, 1)), atol=1e-14)
    np.testing.assert_allclose(mg.weights, pair.slave.body.boundary_weights(pair.slave.name), rtol=1e-12)
    u = np.zeros(prob.model.ndofs)  # lift the top block by 0.01 and shift it sideways: the gap opens by 0.01
    _, dofs = prob.model.node_dofs("body1/bottom")
    off = prob.model.offsets[1]
    u[off:][2::3], u[off:][0::3] = 0.01, 0.3
    np.testing.assert_allclose(mg.gap0 + mg.B @ u, -0.01, atol=1e-14)
    t = np.zeros(prob.model.ndofs)  # both bodies translated together: no gap changes
    t[0::3], t[1::3], t[2::3] = 0.2, -0.4, 0.7
    np.testing.assert_allclose(mg.B @ t, 0.0, atol=1e-14)


def test_body_surface_point_queries_in_3d():
    block = LinearElasticity(meshes.box(0, 1, 0, 1, 0, 1, 2, 2, 2), Material(E=1.0, nu=0.3))
    surface = BodySurface(block, "top")
    assert surface.dim == 3 and "triangles" in surface.describe()
    g, nu = surface.evaluate([[0.3, 0.4, 1.2], [0.6, 0.7, 0.9]])
    np.testing.assert_allclose(g, [-0.2, 0.1], atol=1e-12)
    np.testing.assert_allclose(nu, [[0, 0, 1.0], [0, 0, 1.0]], atol=1e-12)
    np.testing.assert_allclose(surface.project([[0.3, 0.4, 1.2]]), [[0.3, 0.4, 1.0]], atol=1e-12)
    assert surface.gap_hessian([[0.3, 0.4, 1.2]]).shape == (1, 3, 3)
    with pytest.raises(InputError, match="3D; the slave body is 2D"):
        surface.check_dim(2)


def test_3d_refusals_name_the_way_out():
    block = LinearElasticity(meshes.box(0, 1, 0, 1, 0, 1, 1, 1, 1), Material(E=1.0, nu=0.3))
    with pytest.raises(InputError, match="method='mortar'"):
        BodySurface(block, "top", method="node-to-segment")
    p2 = LinearElasticity(meshes.box(0, 1, 0, 1, 1, 2, 1, 1, 1), Material(E=1.0, nu=0.3), order=2)
    with pytest.raises(InputError, match="order=1"):
        BodySurface(p2, "bottom")
    flat = LinearElasticity(meshes.rectangle(0, 1, 1, 2, 2, 2), Material(E=1.0, nu=0.3))
    with pytest.raises(InputError, match="dimension"):
        ContactProblem(bodies=[block, flat], pairs=[ContactPair(Boundary(flat, "bottom"), BodySurface(block, "top"))],
                       supports=[Support("body0/bottom")])


def test_bodies_out_of_reach_warn_naming_the_pair(caplog):
    """A pair whose surfaces never come within the search distance: a warning naming it, not a silent no-contact."""
    from alcontact.contact import BodySurface, solve

    prob = two_body_3d.stacked_blocks_3d(2, 3)
    base, top = prob.model.bodies
    far = LinearElasticity(dataclasses.replace(top.mesh, doflocs=top.mesh.p + np.array([[0.0], [0.0], [5.0]])),
                           top.material)
    pair = ContactPair(Boundary(far, "bottom"), BodySurface(base, "top", search_distance=0.5))
    lifted = ContactProblem(bodies=[base, far], pairs=[pair], supports=list(prob.supports)
                            + [Support("body1/top", components=[2])])
    with caplog.at_level("WARNING"):
        sol = solve(lifted, "ssn")
    assert "no slave node has a master segment or face within the search distance" in caplog.text
    assert "'body1/bottom'" in caplog.text
    assert sol.result.status.label == "no-contact" and not sol.result.success  # never silent


def test_contact_plane_of_a_curved_boundary_comes_from_the_loaded_points():
    from alcontact.contact.solution._estimators import normal_coordinate

    rng = np.random.default_rng(0)
    xy = rng.uniform(0.0, 10.0, (400, 2))
    z = 10.0 - np.sqrt(np.maximum(100.0 - (xy ** 2).sum(axis=1), 0.0))  # a sphere's lower cap: every coordinate spreads
    pts = np.column_stack([xy, z])
    assert normal_coordinate(pts, np.hypot(xy[:, 0], xy[:, 1]) < 1.0) == 2
    flat = np.column_stack([xy, np.zeros(400)])
    assert normal_coordinate(flat, np.zeros(400, bool)) == 2  # nothing loaded: the flat direction of all points
