"""Verification: locking at nu = 0.4999 against an exact elasticity solution (bending cantilever).

Reference: Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed. (McGraw-Hill, 1970), section 21,
"Bending of a cantilever loaded at the end": a beam of length ``L``, depth ``2c``, unit thickness,
free end ``x = 0`` loaded by a parabolic shear traction ``t_y = P (c^2 - y^2) / (2 I)`` (resultant
``P``), ``I = 2 c^3 / 3``, faces ``y = +-c`` free. The stresses ``sigma_x = -P x y / I``,
``sigma_y = 0``, ``tau_xy = -P (c^2 - y^2) / (2 I)`` and the displacements

    u = -P x^2 y / (2 E I) - nu P y^3 / (6 E I) + P y^3 / (6 I G) + (P L^2 / (2 E I) - P c^2 / (2 I G)) y
    v =  nu P x y^2 / (2 E I) + P x^3 / (6 E I) - P L^2 x / (2 E I) + P L^3 / (3 E I)

are an exact solution of plane elasticity; plane strain replaces ``E, nu`` by ``E' = E / (1 - nu^2)``,
``nu' = nu / (1 - nu)`` (``G`` unchanged). The exact displacements are prescribed on the whole end
``x = L`` and the exact traction on ``x = 0``, so the exact field is the solution of the discrete
problem's continuous counterpart, and the tip deflection is ``v(0, 0) = P L^3 / (3 E' I)``.

Here ``L = 10``, ``c = 1``, ``E = 3``, ``nu = 0.4999`` (``kappa / mu = 5000``), neo-Hookean at
finite deformation with ``P = 1e-6`` (tip deflection ``1.25e-5 L``: the linear range, the geometric
nonlinearity is of that relative order), meshes of ``n x n/5`` squares split into triangles.
Measured tip deflection / exact:

    n     mixed (Taylor-Hood)   displacement P1 (locked)
    10    0.999885              0.0206
    20    0.999982              0.0255
    40    0.999998              0.0435
    80    1.0000000             0.1037

Asserted: the mixed tip deflection within 1% of the closed form on every mesh and its error
decreasing under refinement (below 1e-3, 1e-4, 1e-5 at n = 10, 20, 40), its displacement field within
1% of the exact one at every node at n = 40; the P1 displacement body on the same meshes below 10%
of it (locked).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.fem import Hyperelastic, Material, meshes
from alcontact.fem.mixed import MixedHyperelastic

L, C, E, NU, P = 10.0, 1.0, 3.0, 0.4999, 1e-6
I = 2.0 * C**3 / 3.0
E_PS, NU_PS = E / (1.0 - NU**2), NU / (1.0 - NU)  # plane strain
G = E / (2.0 * (1.0 + NU))
V_TIP = P * L**3 / (3.0 * E_PS * I)


def exact(x):
    """Timoshenko & Goodier's displacement field (module doc), ``x`` of shape ``(2, ...)``."""
    X, Y = x[0], x[1]
    u = (-P * X**2 * Y / (2 * E_PS * I) - NU_PS * P * Y**3 / (6 * E_PS * I) + P * Y**3 / (6 * I * G)
         + (P * L**2 / (2 * E_PS * I) - P * C**2 / (2 * I * G)) * Y)
    v = (NU_PS * P * X * Y**2 / (2 * E_PS * I) + P * X**3 / (6 * E_PS * I) - P * L**2 * X / (2 * E_PS * I)
         + P * L**3 / (3 * E_PS * I))
    return np.stack([u, v])


def _end_shear(x):
    return np.stack([0.0 * x[0], P / (2.0 * I) * (C**2 - x[1] ** 2)])


def _solve(body):
    # the residual scale is the tiny load: 1e-8 of it is far below the 1e-3 .. 1e-6 measured here
    x = body.solve(body.traction_load("left", _end_shear), [body.dirichlet("right", None, exact)], rtol=1e-8)
    return x[: body.geometry.ndofs] if isinstance(body, MixedHyperelastic) else x


def _tip(body, u):
    pts, dofs = body.node_dofs("left")
    i = int(np.argmin(np.abs(pts[:, 1])))
    assert abs(pts[i, 1]) < 1e-12
    return float(u[dofs[i, 1]])


def test_exact_field_is_a_solution():
    """The reference itself: Hooke's law in plane strain holds for the field (strains by central differences)."""
    x0, y0, h = np.array([3.0, 7.0]), np.array([0.4, -0.7]), 1e-4
    du = (exact(np.stack([x0 + h, y0])) - exact(np.stack([x0 - h, y0]))) / (2 * h)
    dv = (exact(np.stack([x0, y0 + h])) - exact(np.stack([x0, y0 - h]))) / (2 * h)
    exx, eyy, gxy = du[0], dv[1], du[1] + dv[0]
    sxx, txy = -P * x0 * y0 / I, -P * (C**2 - y0**2) / (2 * I)
    scale = P * L * C / I / E
    assert np.allclose(exx, sxx / E_PS, atol=1e-6 * scale) and np.allclose(eyy, -NU_PS * sxx / E_PS, atol=1e-6 * scale)
    assert np.allclose(gxy, txy / G, atol=1e-6 * scale)
    assert np.allclose(exact(np.array([[L], [0.0]])), 0.0, atol=1e-15)


def test_cantilever_mixed_converges_to_closed_form_where_p1_locks():
    errors = []
    for n in (10, 20, 40):
        mesh = meshes.rectangle(0.0, L, -C, C, n, n // 5)
        mixed = MixedHyperelastic(mesh, E=E, nu=NU)
        u = _solve(mixed)
        ratio = _tip(mixed, u) / V_TIP
        errors.append(abs(ratio - 1.0))
        p1 = Hyperelastic(mesh, Material(E, NU), order=1)
        locked = _tip(p1, _solve(p1)) / V_TIP
        assert abs(ratio - 1.0) <= 0.01 and locked < 0.10, (n, ratio, locked)
        if n == 40:
            ref = mixed.interpolate(exact)  # every displacement DOF against the exact field at its node
            assert np.abs(u - ref).max() <= 0.01 * V_TIP
    assert errors[0] < 1e-3 and errors[1] < 1e-4 and errors[2] < 1e-5, errors
    assert errors[0] > errors[1] > errors[2]
