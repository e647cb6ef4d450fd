"""Property-based tests (Hypothesis) for half-space, ball and polytope obstacles.

A signed distance is 1-Lipschitz, its projection lies on the surface and reconstructs
the point, and moving along the normal changes the gap at unit rate.

The Lipschitz check allows 1e-12 absolute: coordinates are at most 10 in size and gaps at
most about 20, so rounding in a gap is a few 1e-15; a larger difference is a defect.
"""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from alcontact.contact import obstacles as obs

coord = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
radius = st.floats(0.05, 5.0, allow_nan=False, allow_infinity=False)


def vec(d):
    return st.lists(coord, min_size=d, max_size=d).map(lambda v: np.array(v, dtype=float))


def unit_like(d):
    return vec(d).filter(lambda v: np.linalg.norm(v) > 1e-3)


dims = st.sampled_from([2, 3])


@st.composite
def half_space_and_points(draw):
    d = draw(dims)
    ob = obs.make("half-space", point=draw(vec(d)), normal=draw(unit_like(d)))
    return ob, draw(vec(d)), draw(vec(d))


@st.composite
def ball_and_points(draw):
    d = draw(dims)
    names = ["sphere", "sphere-cavity"] if d == 3 else ["circle", "circle-cavity"]
    name = draw(st.sampled_from(names))
    ob = obs.make(name, center=draw(vec(d)), radius=draw(radius))
    return ob, draw(vec(d)), draw(vec(d))


_POLY = obs.make("convex-polyhedron", A=[[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0],
                                         [0, 0, 1], [0, 0, -1], [1, 1, 1]],
                 b=[1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 2.2])


@st.composite
def polytope_and_points(draw):
    return _POLY, draw(vec(3)), draw(vec(3))


_PENTAGON = obs.make("convex-polygon", vertices=[[0, 0], [2, 0], [2.5, 1.5], [1, 2.5], [-0.5, 1.2]])

# Offsets from a vertex, edge or face point: 0, +-m 10^e (e = -16..-8) and the smallest
# subnormal, so that points fall inside the feasibility tolerances of the projection.
_tiny = (st.just(0.0) | st.sampled_from([5e-324, -5e-324])
         | st.builds(lambda m, e, sg: sg * m * 10.0**e, st.floats(1.0, 9.99), st.integers(-16, -8),
                     st.sampled_from([-1.0, 1.0])))


@st.composite
def polytope_and_near_boundary_points(draw):
    """A point within ~1e-7 of a vertex, an edge or a chord of the polytope, and a second
    point within ~1e-7 of it (uniform draws almost never come this close to an edge)."""
    ob = draw(st.sampled_from([_POLY, _PENTAGON]))
    v = ob.vertices
    i, j = draw(st.integers(0, len(v) - 1)), draw(st.integers(0, len(v) - 1))
    w = draw(st.sampled_from([0.0, 0.5, 1.0]) | st.floats(0.0, 1.0))
    x = (1.0 - w) * v[i] + w * v[j] + np.array([draw(_tiny) for _ in range(ob.dim)])
    return ob, x, x + np.array([draw(_tiny) for _ in range(ob.dim)])


any_obstacle = st.one_of(half_space_and_points(), ball_and_points(), polytope_and_points())


@settings(max_examples=150, deadline=None)
@given(any_obstacle | polytope_and_near_boundary_points())
# Outside two faces of the cube corner at distances 3e-11 and 5e-324 (below the former
# 1e-10 feasibility tolerance of the face feet): the gap was -5e-324 instead of -3e-11.
@example(case=(_POLY, np.array([-3e-11, -5e-324, 0.5]), np.array([-3e-11, 0.0, 0.5])))
@example(case=(_POLY, np.array([1 + 5e-11, -1e-13, 0.5]), np.array([1 + 5e-11, 0.0, 0.5])))
# On a face plane of the pentagon: x @ A.T - b of the pair rounds the plane's entry > 0,
# that of x alone to 0, so the face was dropped and the gap was the distance to the
# nearest vertex (-1.98e-5) instead of 0.
@example(case=(_PENTAGON, np.array([-0.499985, 1.2000130000000002]),
               np.array([-0.499985, 1.2000129900000003])))
def test_gap_is_1_lipschitz(case):
    ob, x, y = case
    g = ob.gap(np.stack([x, y]))
    assert abs(g[0] - g[1]) <= np.linalg.norm(x - y) * (1 + 1e-12) + 1e-12


@settings(max_examples=150, deadline=None)
@given(any_obstacle | polytope_and_near_boundary_points())
def test_projection_on_surface_and_reconstruction(case):
    ob, x, _ = case
    xs = x[None]
    g, n = ob.evaluate(xs)
    p = ob.project(xs)
    scale = 1.0 + np.linalg.norm(x)
    assert np.isclose(np.linalg.norm(n), 1.0)
    assert abs(ob.gap(p)[0]) <= 1e-12 * scale * 10
    np.testing.assert_allclose(p - g[:, None] * n, xs, atol=1e-12 * scale * 10)
    # |x - project(x)| = |gap(x)|
    assert np.isclose(np.linalg.norm(x - p[0]), abs(g[0]), atol=1e-12 * scale * 10)


@settings(max_examples=100, deadline=None)
@given(half_space_and_points(), st.floats(-5.0, 5.0))
def test_half_space_gap_is_affine_along_normal(case, t):
    ob, x, _ = case
    g, n = ob.evaluate(x[None])
    assert np.isclose(ob.gap(x[None] + t * n)[0], g[0] - t, atol=1e-10)


@settings(max_examples=100, deadline=None)
@given(ball_and_points(), st.floats(0.0, 1.0))
def test_ball_gap_along_normal_ray(case, frac):
    """Moving along n by t changes the gap by -t while the ray stays on the same side
    of the centre (indenter: any t >= 0; cavity: t <= distance to the centre)."""
    ob, x, _ = case
    g, n = ob.evaluate(x[None])
    r = np.linalg.norm(x - ob.center)
    t = frac * (r if ob.inside else 5.0)
    assert np.isclose(ob.gap(x[None] + t * n)[0], g[0] - t, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(ball_and_points())
def test_ball_gap_depends_only_on_radius(case):
    ob, x, _ = case
    r = np.linalg.norm(x - ob.center)
    expected = r - ob.radius if ob.inside else ob.radius - r
    assert np.isclose(ob.gap(x[None])[0], expected, atol=1e-12 * (1 + r))
    h = ob.gap_hessian(x[None])[0]
    np.testing.assert_allclose(h, h.T, atol=1e-14)
    # normal is an eigenvector with eigenvalue 0 (the gap is linear along it)
    np.testing.assert_allclose(h @ ob.normal(x[None])[0], 0.0, atol=1e-9 / max(r, 1e-3))
