r"""Chapter 4 model problems with exact (manufactured) solutions, for verification.

* :func:`solve_1d` — the 1D model (4.1)-(4.2),

  .. math:: -u'' + u = x \ \text{on } (0, 1), \qquad u(0) = u(1) = 0,

  exact :math:`u = x - \sinh x / \sinh 1`, linear elements (stiffness (4.16),
  load (4.17)).

* :func:`solve_two_material` — the 2D model (4.30)-(4.33),

  .. math::
      -\nabla\cdot(k\nabla u) + b u = f \ \text{in } \Omega_a \cup \Omega_b,\quad
      u = \hat u \ \text{on } \Gamma_D,\quad
      -k\,\partial u/\partial n = p\,(u - \hat u) \ \text{on } \Gamma_R,

  with flux continuity across the interface. The weak form is the corrected
  (4.45):

  .. math::
      \int_\Omega k\nabla u\cdot\nabla v + b u v\,dx + \int_{\Gamma_R} p u v\,ds
      = \int_\Omega f v\,dx + \int_{\Gamma_R} p \hat u v\,ds .

  **Erratum:** the printed (4.42) has the Robin terms with a minus sign;
  ``robin_sign=-1`` reproduces it (it solves a different boundary value
  problem and does not converge to the manufactured solution).

Notation: the text writes :math:`\partial\Omega_1` / :math:`\partial\Omega_2` for
the Dirichlet / Robin parts of the boundary; here they are :math:`\Gamma_D`
(left and right sides) and :math:`\Gamma_R` (bottom and top), and the two
materials occupy :math:`\Omega_a = (0, 1/2)\times(0,1)` (``k_a``) and
:math:`\Omega_b = (1/2, 1)\times(0,1)` (``k_b``).

Manufactured solution: :math:`u = \varphi(x)\psi(y)/k(x)` with
:math:`\varphi(x) = (x - 1/2)e^x` and :math:`\psi(y) = 1 + y + \tfrac12\sin\pi y`.
Because :math:`\varphi(1/2) = 0`, :math:`u` is continuous, and the flux
:math:`k\,\partial_x u = \varphi'\psi` is continuous across :math:`x = 1/2`;
:math:`f = -(\varphi''\psi + \varphi\psi'') + b u` in both materials.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import skfem
from skfem import Basis, BilinearForm, FacetBasis, Functional, LinearForm, asm, condense, solve
from skfem.helpers import dot, grad

from alcontact.errors import InputError
from alcontact.fem import meshes

__all__ = [
    "ModelResult",
    "exact_1d",
    "solve_1d",
    "TwoMaterialProblem",
    "solve_two_material",
    "observed_rates",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class ModelResult:
    """Discrete solution of a model problem and its errors against the exact solution.

    Attributes
    ----------
    h : float
        Largest element size.
    ndofs : int
    u : numpy.ndarray
        Nodal values.
    error_l2 : float
        :math:`\\|u - u_h\\|_{L^2}`.
    error_h1 : float
        :math:`|u - u_h|_{H^1}` (seminorm).
    """

    h: float
    ndofs: int
    u: np.ndarray
    error_l2: float
    error_h1: float


def observed_rates(h, errors) -> np.ndarray:
    r"""Observed orders :math:`\log(e_{i}/e_{i+1}) / \log(h_{i}/h_{i+1})`."""
    h, e = np.asarray(h, dtype=float), np.asarray(errors, dtype=float)
    return np.log(e[:-1] / e[1:]) / np.log(h[:-1] / h[1:])


# --------------------------------------------------------------------------- 1D
def exact_1d(x):
    r"""Exact solution :math:`u(x) = x - \sinh x/\sinh 1` of (4.1)-(4.2) and its derivative."""
    x = np.asarray(x, dtype=float)
    return x - np.sinh(x) / np.sinh(1.0), 1.0 - np.cosh(x) / np.sinh(1.0)


def solve_1d(n: int) -> ModelResult:
    """Solve (4.1)-(4.2) with ``n`` linear elements on a uniform mesh of (0, 1).

    Examples
    --------
    >>> r = solve_1d(16)
    >>> bool(r.error_l2 < 2e-4)
    True
    """
    if int(n) != n or n < 1:
        raise InputError(f"number of elements n={n!r} must be an integer >= 1.")
    mesh = meshes.interval(0.0, 1.0, int(n))
    basis = Basis(mesh, skfem.ElementLineP1(), intorder=6)

    @BilinearForm
    def a(u, v, w):  # (4.16): stiffness + mass
        return dot(grad(u), grad(v)) + u * v

    @LinearForm
    def rhs(v, w):  # (4.17)
        return w.x[0] * v

    A, b = asm(a, basis), asm(rhs, basis)
    D = basis.get_dofs().flatten()
    u = solve(*condense(A, b, D=D))
    return _errors_1d(basis, u, 1.0 / n)


def _errors_1d(basis, u, h) -> ModelResult:
    @Functional
    def l2(w):
        return (w.uh - exact_1d(w.x[0])[0]) ** 2

    @Functional
    def h1(w):
        return (w.uh.grad[0] - exact_1d(w.x[0])[1]) ** 2

    uh = basis.interpolate(u)
    return ModelResult(
        h=float(h), ndofs=int(basis.N), u=u,
        error_l2=float(np.sqrt(l2.assemble(basis, uh=uh))),
        error_h1=float(np.sqrt(h1.assemble(basis, uh=uh))),
    )


# --------------------------------------------------------------------------- 2D
@dataclass(frozen=True)
class TwoMaterialProblem:
    """Data of the two-material model problem (4.30)-(4.33).

    Parameters
    ----------
    k_a, k_b : float
        Conductivities of the left half and right half (> 0).
    b : float
        Reaction coefficient (>= 0).
    p : float
        Robin coefficient (> 0).
    """

    k_a: float = 1.0
    k_b: float = 10.0
    b: float = 1.0
    p: float = 2.0

    def __post_init__(self):
        for name, val, ok, rng in (("k_a", self.k_a, self.k_a > 0, "> 0"), ("k_b", self.k_b, self.k_b > 0, "> 0"),
                                   ("b", self.b, self.b >= 0, ">= 0"), ("p", self.p, self.p > 0, "> 0")):
            if not (np.isfinite(val) and ok):
                raise InputError(f"{name}={val!r} is out of range; it must be finite and {rng}.")

    def k(self, x):
        """Piecewise-constant conductivity at points ``x`` (dim, ...)."""
        return np.where(x[0] < 0.5, self.k_a, self.k_b)

    @staticmethod
    def _phi(x):
        e = np.exp(x)
        return (x - 0.5) * e, (x + 0.5) * e, (x + 1.5) * e

    @staticmethod
    def _psi(y):
        return (1.0 + y + 0.5 * np.sin(np.pi * y),
                1.0 + 0.5 * np.pi * np.cos(np.pi * y),
                -0.5 * np.pi**2 * np.sin(np.pi * y))

    def exact(self, x):
        """Manufactured solution ``u`` and its gradient ``(2, ...)`` at ``x``."""
        f0, f1, _ = self._phi(x[0])
        g0, g1, _ = self._psi(x[1])
        k = self.k(x)
        return f0 * g0 / k, np.array([f1 * g0 / k, f0 * g1 / k])

    def source(self, x):
        """Right-hand side ``f`` (same expression in both materials)."""
        f0, _, f2 = self._phi(x[0])
        g0, _, g2 = self._psi(x[1])
        return -(f2 * g0 + f0 * g2) + self.b * self.exact(x)[0]

    def robin_data(self, x, n):
        r""":math:`\hat u = u + (k/p)\,\partial u/\partial n` on the Robin part (outward ``n``)."""
        u, g = self.exact(x)
        return u + self.k(x) / self.p * (g[0] * n[0] + g[1] * n[1])


def solve_two_material(n: int, problem: TwoMaterialProblem | None = None, *, robin_sign: int = 1) -> ModelResult:
    """Solve the two-material problem with P1 triangles on an ``n x n`` grid of the unit square.

    Parameters
    ----------
    n : int
        Cells per side; even, so that the interface ``x = 1/2`` is a mesh line.
    problem : TwoMaterialProblem, optional
    robin_sign : {1, -1}
        ``+1`` the corrected weak form (4.45); ``-1`` the misprinted (4.42).

    Examples
    --------
    >>> r = solve_two_material(8)
    >>> bool(r.error_l2 < 1e-2)
    True
    """
    if int(n) != n or n < 2 or n % 2:
        raise InputError(f"n={n!r} must be an even integer >= 2 so that the interface x = 1/2 is a mesh line.")
    if robin_sign not in (1, -1):
        raise InputError(f"robin_sign={robin_sign!r} must be +1 (corrected (4.45)) or -1 (printed (4.42)).")
    prob = problem or TwoMaterialProblem()
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, int(n), int(n))
    elem = skfem.ElementTriP1()
    basis = Basis(mesh, elem, intorder=4)
    robin = np.concatenate([mesh.boundaries["bottom"], mesh.boundaries["top"]])
    fbasis = FacetBasis(mesh, elem, facets=robin, intorder=4)

    @BilinearForm
    def a(u, v, w):
        return prob.k(w.x) * dot(grad(u), grad(v)) + prob.b * u * v

    @BilinearForm
    def a_robin(u, v, w):
        return prob.p * u * v

    @LinearForm
    def l(v, w):
        return prob.source(w.x) * v

    @LinearForm
    def l_robin(v, w):
        return prob.p * prob.robin_data(w.x, w.n) * v

    A = asm(a, basis) + robin_sign * asm(a_robin, fbasis)
    rhs = asm(l, basis) + robin_sign * asm(l_robin, fbasis)
    D = basis.get_dofs(np.concatenate([mesh.boundaries["left"], mesh.boundaries["right"]])).flatten()
    x = np.zeros(basis.N)
    x[D] = prob.exact(basis.doflocs[:, D])[0]
    u = solve(*condense(A, rhs, x=x, D=D))

    @Functional
    def l2(w):
        return (w.uh - prob.exact(w.x)[0]) ** 2

    @Functional
    def h1(w):
        g = prob.exact(w.x)[1]
        return (w.uh.grad[0] - g[0]) ** 2 + (w.uh.grad[1] - g[1]) ** 2

    uh = basis.interpolate(u)
    return ModelResult(
        h=float(np.sqrt(2.0) / n), ndofs=int(basis.N), u=u,
        error_l2=float(np.sqrt(l2.assemble(basis, uh=uh))),
        error_h1=float(np.sqrt(h1.assemble(basis, uh=uh))),
    )
