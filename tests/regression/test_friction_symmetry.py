"""Regression (issue 9): frictional contact points on symmetry planes.

Before the fix, :class:`FrictionalContact` took only points with *all* DOFs free
as contact candidates, so a point on a symmetry plane (``u_x = 0``) never carried
pressure: it penetrated the obstacle and the status still said ``converged``
(2D Hertz half model: 6 % of h, peak pressure 52 % above Hertz; 3D quarter model:
every symmetry-plane point penetrated).

Reference: the full model, whose mesh is the half (quarter) model's mesh
mirrored at the symmetry planes, so both are the same discrete problem and the
symmetric solution of the full one restricted to ``x (, y) >= 0`` *is* the
solution of the reduced one. Asserted for every frictional algorithm (family-p
with every contact penalty in 2D), with :math:`\\mu = 10^{-9}` and
:math:`\\mu = 0.3`:

- total normal force: symmetry factor x reduced model = full model, relative
  difference <= 1e-6;
- pressure at every reduced-model point = full-model pressure at the same
  point, <= 1e-6 of the peak pressure;
- no penetration beyond the solver tolerance ``tol_penetration * h`` (1e-8 h)
  at the symmetry-plane points, which carry pressure (they are in the centre of
  the contact zone).

The 1e-6 bound leaves room above the solver tolerances (multiplier change 1e-8,
Newton 1e-11) for the different conditioning of the two models.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Support, contact_penalties, solve_friction
from alcontact.contact.systems import FrictionalContact
from alcontact.contact.problem import LoadHistory
from alcontact.contact.obstacles import Circle, Sphere
from alcontact.fem import LinearElasticity, Material, meshes

TOL = 1e-6
TOL_PENETRATION = 1e-8
RADIUS = 10.0


def _mirror(mesh, axis: int):
    """The mesh and its mirror image at the plane ``x_axis = 0`` (points on the plane shared)."""
    p, t = mesh.p, mesh.t
    on = np.abs(p[axis]) <= 1e-12
    q = p.copy()
    q[axis] *= -1.0
    idx = np.arange(p.shape[1])
    new = np.cumsum(~on) - 1 + p.shape[1]
    image = np.where(on, idx, new)
    p2 = np.concatenate([p, q[:, ~on]], axis=1)
    t2 = image[t]
    t2[[0, 1]] = t2[[1, 0]]  # keep the orientation of the mirrored elements
    return type(mesh)(p2, np.concatenate([t, t2], axis=1))


def _named(mesh, top_axis: int):
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    lo, hi = mesh.p[top_axis].min(), mesh.p[top_axis].max()
    return mesh.with_boundaries({"top": bf[np.abs(mid[top_axis] - hi) <= 1e-9],
                                 "bottom": bf[np.abs(mid[top_axis] - lo) <= 1e-9]})


def _models(dim: int):
    """(reduced, full, symmetry factor): cylinder half model (2D) or sphere quarter model (3D)."""
    if dim == 2:
        mesh = meshes.rectangle(0.0, 8.0, -8.0, 0.0, 6, 6,
                                refine=dict(center=(0.0, 0.0), h_min=0.125, width=1.6, depth=1.0, growth=1.3))
        mat = Material(E=200e3, nu=0.3, plane="strain")
        obstacle = Circle(center=(0.0, RADIUS - 0.1), radius=RADIUS)
        sym = (Support("left", components=(0,)),)
        full_mesh = _named(_mirror(mesh, 0), 1)
        factor = 2.0
    else:
        mesh = meshes.box(0.0, 4.0, 0.0, 4.0, -4.0, 0.0, 3, 3, 3,
                          refine=dict(center=(0.0, 0.0, 0.0), h_min=0.35, width=1.4, depth=1.0, growth=1.4))
        mat = Material(E=200e3, nu=0.3)
        obstacle = Sphere(center=(0.0, 0.0, RADIUS - 0.1), radius=RADIUS)
        sym = (Support("left", components=(0,)), Support("front", components=(1,)))
        full_mesh = _named(_mirror(_mirror(mesh, 0), 1), 2)
        factor = 4.0
    reduced = ContactProblem(model=LinearElasticity(mesh, mat), obstacle=obstacle, contact_boundary="top",
                             supports=(Support("bottom"),) + sym)
    full = ContactProblem(model=LinearElasticity(full_mesh, mat), obstacle=obstacle, contact_boundary="top",
                          supports=(Support("bottom"),))
    return reduced, full, factor


_CASES = [(2, "simo-laursen", None), (2, "ssn", None)] + [(2, "family-p", p) for p in contact_penalties()] + [
    (3, "simo-laursen", None), (3, "family-p", None), (3, "ssn", None)]
_CACHE: dict = {}


def _solve(dim, which, algorithm, penalty, mu):
    key = (dim, which, algorithm, penalty, mu)
    if key not in _CACHE:
        if ("models", dim) not in _CACHE:
            _CACHE["models", dim] = _models(dim)
        reduced, full, factor = _CACHE["models", dim]
        prob = reduced if which == "reduced" else full
        _CACHE[key] = solve_friction(prob, LoadHistory((), (1.0,)), algorithm, penalty, friction=mu,
                                     tol_penetration=TOL_PENETRATION)
    return _CACHE[key]


@pytest.mark.parametrize("mu", [1e-9, 0.3])
@pytest.mark.parametrize("dim, algorithm, penalty", _CASES)
def test_reduced_model_matches_full_model(dim, algorithm, penalty, mu):
    factor = 2.0 if dim == 2 else 4.0
    red = _solve(dim, "reduced", algorithm, penalty, mu)
    full = _solve(dim, "full", algorithm, penalty, mu)
    assert red.success, red.message
    assert full.success, full.message
    fr, ff = red.final, full.final

    n_red, n_full = factor * fr.normal_force, ff.normal_force
    assert abs(n_red - n_full) <= TOL * n_full, (n_red, n_full)

    # pressure profile: the same points in both models
    key = {tuple(np.round(x, 9)): i for i, x in enumerate(full.points)}
    idx = np.array([key[tuple(np.round(x, 9))] for x in red.points])
    peak = ff.pressure.max()
    err = np.max(np.abs(fr.pressure - ff.pressure[idx])) / peak
    assert err <= TOL, err

    # symmetry-plane points carry pressure and do not penetrate
    on_plane = np.any(np.abs(red.points[:, : dim - 1]) <= 1e-12, axis=1) & (fr.pressure > 0)
    assert np.count_nonzero(on_plane) >= (1 if dim == 2 else 3)
    assert np.max(fr.gap[on_plane]) <= TOL_PENETRATION * red.h
    assert fr.pressure[np.argmin(np.linalg.norm(red.points[:, : dim - 1], axis=1))] >= 0.9 * peak


@pytest.mark.parametrize("dim", [2, 3])
def test_symmetry_points_hold_no_friction_force(dim):
    """The friction force on a held tangent direction goes into the support reaction: zero traction there."""
    sol = _solve(dim, "reduced", "ssn", None, 0.3)
    held = ~FrictionalContact(_CACHE["models", dim][0], LoadHistory((), (1.0,))).tfree
    assert np.any(held)
    assert np.all(sol.final.traction_t[held] == 0.0)
