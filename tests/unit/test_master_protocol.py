"""Every rigid obstacle is a :class:`alcontact.contact.Master`: the members exist and mean what the protocol says.

Generated from the obstacle registry (a newly registered obstacle must add its sample
parameters to :data:`SAMPLES`), plus the placed obstacles of the load stepping
(``translate``, ``move``). References: the protocol's own definitions, checked
numerically — the normal is minus the gradient of the gap (central differences,
relative 1e-6), the Hessian is minus the derivative of the normal (central differences,
relative 1e-5), the projection lies on the surface (gap 0 to 1e-9) at
``x + gap * normal``, and the bounding box contains every projection.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import Master, obstacles
from alcontact.errors import InputError

CUBE = [[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.5, 0.5)]

def _wavy_surface() -> dict:
    """A non-convex triangulated surface over [-3, 3]^2 (beyond the sampled box), free side up."""
    n = 9
    x = np.linspace(-3.0, 3.0, n)
    X, Y = np.meshgrid(x, x, indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), 0.4 * np.sin(X.ravel()) * np.cos(0.8 * Y.ravel())])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return dict(vertices=V.tolist(), facets=F.tolist())


#: a non-convex polyline (a W) from x = -3 to 3, free side up
W_POLYLINE = dict(vertices=[[3.0, 1.0], [1.5, -0.5], [0.0, 0.3], [-1.5, -0.5], [-3.0, 1.0]],
                  facets=[[0, 1], [1, 2], [2, 3], [3, 4]])

#: name -> keyword parameters of :func:`obstacles.make` (surfaces pass within ~1 of the origin)
SAMPLES = {
    "half-space": dict(point=[0.1, -0.2], normal=[0.3, 1.0]),
    "sphere": dict(center=[0.1, 0.0, 1.2], radius=1.0),
    "sphere-cavity": dict(center=[0.0, 0.1, 0.0], radius=1.0),
    "circle": dict(center=[0.0, 1.1], radius=1.0),
    "circle-cavity": dict(center=[0.1, 0.0], radius=1.0),
    "cylinder": dict(center=[0.0, 0.0, 1.2], axis=[1.0, 0.0, 0.0], radius=1.0),
    "cylinder-cavity": dict(center=[0.0, 0.1, 0.0], axis=[0.0, 0.0, 1.0], radius=1.0),
    "convex-polygon": dict(vertices=[[-1.0, -1.5], [1.0, -1.0], [0.5, 0.5], [-0.8, 0.2]]),
    "convex-polyhedron": dict(vertices=CUBE),
    "convex-polygon-cavity": dict(vertices=[[-1.0, -1.5], [1.0, -1.0], [0.5, 0.5], [-0.8, 0.2]]),
    "convex-polyhedron-cavity": dict(vertices=CUBE),
    "user": dict(gap=lambda x: x[:, 1] - 0.3, dim=2),
    "surface": _wavy_surface(),
}


def _placed() -> dict:
    circle = obstacles.make("circle", **SAMPLES["circle"])
    sphere = obstacles.make("sphere", **SAMPLES["sphere"])
    return {
        "translated circle": obstacles.translate(circle, [0.2, -0.1]),
        "moved sphere": obstacles.move(sphere, obstacles.RigidMotion.about([0.0, 0.0, 0.5], 0.4, [0.0, 1.0, 0.0])),
        "moved half-space": obstacles.move(obstacles.make("half-space", **SAMPLES["half-space"]),
                                           obstacles.RigidMotion.about([0.0, 0.0], -0.3)),
        "surface (2D polyline)": obstacles.make("surface", **W_POLYLINE),
    }


def _all() -> dict:
    return {**{name: obstacles.make(name, **kw) for name, kw in SAMPLES.items()}, **_placed()}


def _free_points(ob, d: int, rng) -> np.ndarray:
    """Points on the free side close to the surface (-0.6 < gap < -0.05): the signed distance is smooth there."""
    x = rng.uniform(-2.0, 2.0, size=(4000, d))
    g = ob.gap(x)
    x = x[(g < -0.05) & (g > -0.6)][:40]
    assert x.shape[0] >= 10, "sample parameters leave too few points near the surface"
    return x


def test_every_registered_obstacle_has_sample_parameters():
    assert set(obstacles.available()) <= set(SAMPLES), (
        f"add sample parameters of {sorted(set(obstacles.available()) - set(SAMPLES))} to SAMPLES")


@pytest.mark.parametrize("name", sorted(_all()))
def test_obstacle_satisfies_the_master_protocol(name):
    ob = _all()[name]
    assert isinstance(ob, Master)
    assert ob.rigid is True
    assert isinstance(ob.name, str) and ob.name and isinstance(ob.describe(), str)
    d = ob.dim if ob.dim is not None else 2
    ob.check_dim(d)
    if ob.dim is not None:
        with pytest.raises(InputError, match="body is"):
            ob.check_dim(5 - d)

    x = _free_points(ob, d, np.random.default_rng(7))
    m = x.shape[0]
    g, nu = ob.evaluate(x)
    assert g.shape == (m,) and nu.shape == (m, d)
    np.testing.assert_array_equal(ob.gap(x), g)
    np.testing.assert_array_equal(ob.normal(x), nu)
    # unit (1e-9: a user gap's default normal is central differences, error ~ eps^(2/3) ~ 4e-11)
    np.testing.assert_allclose(np.linalg.norm(nu, axis=1), 1.0, rtol=1e-9)

    # closest point: on the surface, at x + gap * normal
    y = ob.project(x)
    assert y.shape == (m, d)
    np.testing.assert_allclose(y, x + g[:, None] * nu, atol=1e-12)
    np.testing.assert_allclose(ob.gap(y), 0.0, atol=1e-9)

    # normal = -grad gap, H = grad^2 gap = -d normal / dx (central differences)
    h = 1e-6
    eye = np.eye(d)
    grad = np.stack([(ob.gap(x + h * eye[k]) - ob.gap(x - h * eye[k])) / (2 * h) for k in range(d)], axis=1)
    np.testing.assert_allclose(-grad, nu, atol=1e-6)
    H = ob.gap_hessian(x)
    assert H.shape == (m, d, d)
    dnu = np.stack([(ob.normal(x + h * eye[k]) - ob.normal(x - h * eye[k])) / (2 * h) for k in range(d)], axis=2)
    np.testing.assert_allclose(H, -dnu, atol=1e-5 * max(1.0, float(np.abs(H).max())))

    # slip on the surface from the closest point of a nearby earlier position
    slip, jac = ob.surface_slip(x, ob.project(x + 0.01))
    assert slip.shape == (m, d) and jac.shape == (m, d, d)
    np.testing.assert_allclose(np.einsum("ij,ij->i", slip, nu), 0.0, atol=1e-10)  # tangent (user normal: FD)

    # bounding box: contains every closest point
    lo, hi = ob.bounding_box(d)
    assert lo.shape == (d,) and hi.shape == (d,) and np.all(lo <= hi)
    tol = 1e-9
    assert np.all(y >= lo - tol) and np.all(y <= hi + tol)


@pytest.mark.parametrize("name, lo, hi", [
    ("circle", [-1.0, 0.1], [1.0, 2.1]),
    ("sphere-cavity", [-1.0, -0.9, -1.0], [1.0, 1.1, 1.0]),
    ("cylinder", [-np.inf, -1.0, 0.2], [np.inf, 1.0, 2.2]),
    ("convex-polygon", [-1.0, -1.5], [1.0, 0.5]),
    ("half-space", [-np.inf, -np.inf], [np.inf, np.inf]),
    ("user", [-np.inf, -np.inf], [np.inf, np.inf]),
])
def test_bounding_box_values(name, lo, hi):
    """Exact boxes: a ball's centre +- R, a cylinder's unbounded along its axis, a polygon's vertex range."""
    ob = obstacles.make(name, **SAMPLES[name])
    box = ob.bounding_box(len(lo))
    np.testing.assert_allclose(box[0], lo, rtol=1e-12)
    np.testing.assert_allclose(box[1], hi, rtol=1e-12)


def test_bounding_box_of_an_axis_normal_plane_is_flat_along_that_axis():
    ob = obstacles.make("half-space", point=[0.0, 0.5, 0.0], normal=[0.0, 1.0, 0.0])
    lo, hi = ob.bounding_box(3)
    np.testing.assert_array_equal(lo, [-np.inf, 0.5, -np.inf])
    np.testing.assert_array_equal(hi, [np.inf, 0.5, np.inf])
    lo, hi = obstacles.translate(ob, [1.0, 2.0, 3.0]).bounding_box(3)
    np.testing.assert_array_equal(lo, [-np.inf, 2.5, -np.inf])


@pytest.mark.parametrize("d", [4, "2", None, 2.5])
def test_bounding_box_bad_dimension_is_an_input_error(d):
    with pytest.raises(InputError, match="bounding_box: d ="):
        obstacles.make("circle", center=[0.0, 0.0], radius=1.0).bounding_box(d)


@pytest.mark.parametrize("d, kw", [(2, SAMPLES["convex-polygon-cavity"]), (3, SAMPLES["convex-polyhedron-cavity"])])
def test_cavity_is_the_complement_of_the_polytope(d, kw):
    """A polytope cavity (body inside) has minus the polytope's signed distance, normal and Hessian
    everywhere: inside (free, gap <= 0) and outside (penetration, the exact distance to the polytope)."""
    base = "convex-polygon" if d == 2 else "convex-polyhedron"
    solid, cavity = obstacles.make(base, **kw), obstacles.make(f"{base}-cavity", **kw)
    assert cavity.name == f"{base}-cavity" and "body inside" in cavity.describe()
    x = np.random.default_rng(3).uniform(-2.5, 2.5, size=(500, d))
    g, n = cavity.evaluate(x)
    g0, n0 = solid.evaluate(x)
    assert np.any(g < 0) and np.any(g > 0)
    np.testing.assert_array_equal(g, -g0)
    np.testing.assert_array_equal(n, -n0)
    np.testing.assert_array_equal(cavity.gap_hessian(x), -solid.gap_hessian(x))
    np.testing.assert_array_equal(cavity.bounding_box(d)[0], solid.bounding_box(d)[0])
