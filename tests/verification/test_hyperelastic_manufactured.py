"""Verification: manufactured finite-deformation solution, L2 convergence rates of P1 and P2.

Reference: on the unit square (plane strain) the displacement

    u*(X, Y) = A (sin(pi X / 2) Y,  X^2 Y - X Y / 2),   A = 0.15,

(principal stretches 0.85 to 1.24, J between 0.99 and 1.23) is the exact solution of
Div P(F) + f = 0 with the body force f = -Div P(I + grad u*) per reference volume,
derived with SymPy from the same strain energy, and u = u* on the whole boundary.

Assertion: the L2 error ||u_h - u*|| on three meshes (h = 1/4, 1/8, 1/16) decreases at the
observed rate >= p + 1 - 0.15 for P1 (rate 2) and P2 (rate 3), for the neo-Hookean and
St Venant-Kirchhoff laws, and the finest P2 error is below 1e-4 times ||u*||.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy
from skfem import Functional

from alcontact.fem import Hyperelastic, Material, meshes

A = 0.15
E, NU = 10.0, 0.3


def _energy(name, F, lam, mu):
    if name == "neo-hookean":
        J = F.det()
        return mu / 2 * ((F.T * F).trace() - 3) - mu * sympy.log(J) + lam / 2 * sympy.log(J) ** 2
    Eg = (F.T * F - sympy.eye(3)) / 2
    return mu * (Eg.T * Eg).trace() + lam / 2 * Eg.trace() ** 2


def _manufactured(name, lam, mu):
    """Exact displacement and body force as NumPy callables of x with shape (2, ...)."""
    X, Y = sympy.symbols("X Y", real=True)
    u = sympy.Matrix([A * sympy.sin(sympy.pi * X / 2) * Y, A * (X**2 * Y - X * Y / 2)])
    grad = u.jacobian([X, Y])
    F = sympy.eye(3)
    F[:2, :2] += grad
    Fs = sympy.Matrix(3, 3, lambda i, j: sympy.Symbol(f"F{i}{j}", real=True))
    W = _energy(name, Fs, sympy.Float(lam), sympy.Float(mu))
    subs = {Fs[i, j]: F[i, j] for i in range(3) for j in range(3)}
    P = [[sympy.diff(W, Fs[i, j]).subs(subs) for j in range(2)] for i in range(2)]
    f = [-(sympy.diff(P[i][0], X) + sympy.diff(P[i][1], Y)) for i in range(2)]
    u_num = sympy.lambdify((X, Y), list(u), "numpy")
    f_num = sympy.lambdify((X, Y), f, "numpy")

    def as_field(fun):
        return lambda x: np.stack([np.broadcast_to(np.asarray(c, dtype=float), x[0].shape)
                                   for c in fun(x[0], x[1])])

    return as_field(u_num), as_field(f_num)


def _l2_error(body, uh, exact):
    @Functional
    def err2(w):
        ue = exact(w.x)
        return (w.uh[0] - ue[0]) ** 2 + (w.uh[1] - ue[1]) ** 2

    @Functional
    def norm2(w):
        ue = exact(w.x)
        return ue[0] ** 2 + ue[1] ** 2

    return np.sqrt(err2.assemble(body.basis, uh=body.basis.interpolate(uh))), np.sqrt(norm2.assemble(body.basis))


@pytest.mark.parametrize("name", ["neo-hookean", "saint-venant-kirchhoff"])
@pytest.mark.parametrize("order", [1, 2])
def test_manufactured_solution_converges_at_optimal_rate(name, order):
    """L2 rates >= p + 1 - 0.15 over h = 1/4, 1/8, 1/16 (see module doc)."""
    mat = Material(E=E, nu=NU)
    lam, mu = mat.lame(3)
    exact, force = _manufactured(name, lam, mu)
    errors = []
    for n in (4, 8, 16):
        body = Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, n, n), mat, order=order, model=name)
        bc = [body.dirichlet(b, value=exact) for b in ("left", "right", "bottom", "top")]
        u = body.solve(body.body_load(force), dirichlet=bc, steps=2)
        err, ref = _l2_error(body, u, exact)
        errors.append(err / ref)
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates >= order + 1 - 0.15), (errors, rates)
    if order == 2:
        assert errors[-1] < 1e-4, errors
