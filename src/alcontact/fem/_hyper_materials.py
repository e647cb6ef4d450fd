r"""Hyperelastic material laws :math:`W(F)` and their registry.

A law gives, at many quadrature points at once, the strain energy density
:math:`W(F)`, the first Piola-Kirchhoff stress :math:`P = \partial W/\partial F`
and the material tangent :math:`\mathbb{A} = \partial P/\partial F`
(:math:`\mathbb{A}_{iJkL} = \partial P_{iJ}/\partial F_{kL}`), for deformation
gradients of shape ``(..., d, d)`` with ``d = 3`` (3D) or ``d = 2`` (plane
strain, :math:`F_{33} = 1`, :math:`F_{\alpha 3} = F_{3\alpha} = 0`: the in-plane
block of the 3D law). Every law is evaluated with the Lamé constants
:math:`(\lambda, \mu)` of an :class:`~alcontact.fem.Material`.

Built-in laws (hand-written closed forms, vectorized over NumPy arrays):

``"neo-hookean"`` (compressible)
    .. math::
        W = \tfrac{\mu}{2}(\operatorname{tr} C - 3) - \mu \ln J + \tfrac{\lambda}{2}(\ln J)^2,
        \qquad P = \mu (F - F^{-T}) + \lambda \ln J\, F^{-T},

        \mathbb{A}_{iJkL} = \mu\,\delta_{ik}\delta_{JL} + (\mu - \lambda\ln J)\,F^{-1}_{Li}F^{-1}_{Jk}
        + \lambda\,F^{-1}_{Ji}F^{-1}_{Lk}.

``"saint-venant-kirchhoff"``
    .. math::
        W = \mu\, E:E + \tfrac{\lambda}{2}(\operatorname{tr} E)^2, \quad E = \tfrac12(F^TF - I),
        \quad S = \lambda \operatorname{tr}E\, I + 2\mu E, \quad P = F S,

        \mathbb{A}_{iJkL} = \delta_{ik} S_{JL} + \lambda F_{iJ}F_{kL}
        + \mu\,(\delta_{JL}(FF^T)_{ik} + F_{iL}F_{kJ}).

A user law is given by its energy alone: :class:`SymbolicMaterial` takes
``W(F, lam, mu)`` written with SymPy operations on a symbolic 3x3 matrix and
derives :math:`P` and :math:`\mathbb{A}` by symbolic differentiation, compiled to
vectorized NumPy with :func:`sympy.lambdify` (common subexpressions shared).
Register it with :func:`register_material` to use it by name.

Both laws reduce to linear elasticity for small strains: at :math:`F = I`,
:math:`\mathbb{A}_{iJkL} = \lambda\delta_{iJ}\delta_{kL} + \mu(\delta_{ik}\delta_{JL}
+ \delta_{iL}\delta_{Jk})`.

Examples
--------
>>> import numpy as np
>>> law = make_material("neo-hookean")
>>> F = np.eye(3)[None]
>>> float(law.energy(F, 1.0, 1.0)[0]), float(np.abs(law.stress(F, 1.0, 1.0)).max())
(0.0, 0.0)
>>> sorted(available_materials())[:4]
['arruda-boyce', 'gent', 'mooney-rivlin', 'neo-hookean']
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any

import numpy as np

from alcontact.errors import InputError, UnknownNameError

__all__ = [
    "HyperelasticLaw",
    "NeoHookean",
    "SaintVenantKirchhoff",
    "SymbolicMaterial",
    "available_materials",
    "make_material",
    "register_material",
    "material_parameters",
    "example_material_parameters",
    "det",
    "inv",
]


# ---------------------------------------------------------------- small-matrix helpers
def det(F: np.ndarray) -> np.ndarray:
    """Determinant of a stack of 2x2 or 3x3 matrices ``(..., d, d)`` (closed form)."""
    if F.shape[-1] == 2:
        return F[..., 0, 0] * F[..., 1, 1] - F[..., 0, 1] * F[..., 1, 0]
    return (F[..., 0, 0] * (F[..., 1, 1] * F[..., 2, 2] - F[..., 1, 2] * F[..., 2, 1])
            - F[..., 0, 1] * (F[..., 1, 0] * F[..., 2, 2] - F[..., 1, 2] * F[..., 2, 0])
            + F[..., 0, 2] * (F[..., 1, 0] * F[..., 2, 1] - F[..., 1, 1] * F[..., 2, 0]))


def inv(F: np.ndarray, J: np.ndarray | None = None) -> np.ndarray:
    """Inverse of a stack of 2x2 or 3x3 matrices by the adjugate (``J = det F`` if known)."""
    J = det(F) if J is None else J
    out = np.empty_like(F)
    if F.shape[-1] == 2:
        out[..., 0, 0] = F[..., 1, 1]
        out[..., 1, 1] = F[..., 0, 0]
        out[..., 0, 1] = -F[..., 0, 1]
        out[..., 1, 0] = -F[..., 1, 0]
    else:
        for i in range(3):
            i1, i2 = (i + 1) % 3, (i + 2) % 3
            for j in range(3):
                j1, j2 = (j + 1) % 3, (j + 2) % 3
                # adj(F)[j, i] = cofactor(F)[i, j]
                out[..., j, i] = F[..., i1, j1] * F[..., i2, j2] - F[..., i1, j2] * F[..., i2, j1]
    return out / J[..., None, None]


def _weighted_outer(x: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``sum_q w[e, q] x[e, q, :] y[e, q, :]^T`` for ``x, y`` of shape ``(nel, nqp, n)``."""
    if x.shape[1] == 1:  # one point: a broadcast product beats a batched matmul
        return (x[:, 0, :] * w[:, 0, None])[:, :, None] * y[:, 0, None, :]
    return np.matmul(np.swapaxes(x * w[:, :, None], 1, 2), y)


def _assemble_terms(g, w1, w2, G, w3, G2=None) -> np.ndarray:
    r"""Integrated element tangent of the common isotropic form

    .. math::
        K_{aibk} = \sum_q w_1\, g_{ai} g_{bk} + w_2\, g_{ak} g_{bi} + w_3\, (G_a \cdot G'_b)\,\delta_{ik}

    with ``g``, ``G`` and ``G' = G2`` (default ``G``) of shape ``(nel, nqp, nloc, d)`` and
    weights of shape ``(nel, nqp)``; returns ``(nel, nloc, d, nloc, d)``.
    """
    nel, nqp, nloc, d = g.shape
    G2 = G if G2 is None else G2
    gf = g.reshape(nel, nqp, nloc * d)
    K = _weighted_outer(gf, gf, w1).reshape(nel, nloc, d, nloc, d)
    K += _weighted_outer(gf, gf, w2).reshape(nel, nloc, d, nloc, d).transpose(0, 1, 4, 3, 2)
    GG = _weighted_outer(G[..., 0], G2[..., 0], w3)
    for J in range(1, d):
        GG += _weighted_outer(G[..., J], G2[..., J], w3)
    for i in range(d):
        K[:, :, i, :, i] += GG
    return K


# ------------------------------------------------------------------------- protocol
class HyperelasticLaw(ABC):
    r"""Base class of a hyperelastic law :math:`W(F)` (see module doc).

    Subclasses implement :meth:`energy`, :meth:`stress`, :meth:`tangent` and
    :meth:`stress_zz`; :meth:`element_tangent` has a generic implementation
    through :meth:`tangent` that a law may replace by a faster contraction.
    All arrays are evaluated where :math:`J = \det F > 0` (the body checks).

    Attributes
    ----------
    name : str
        Registry name.
    """

    name: str = ""

    #: Declared parameters of the law (type, range, one line of doc), checked by
    #: :func:`~alcontact.fem.check_material_parameters` (:func:`make_material`, the constructors of the
    #: parametrized laws and the problem-file loader, ``material.parameters``).
    PARAMETERS: tuple = ()

    #: One line of plain text: the energy and where its moduli come from (generated docs).
    SUMMARY: str = ""

    #: Values of :attr:`PARAMETERS` of a documented example (initial shear modulus 0.9): the
    #: generated tests and docs build the law with them, so a newly registered law is covered.
    EXAMPLE_PARAMETERS: dict = {}

    @classmethod
    def parameter_issues(cls, values: dict[str, Any]) -> list[tuple[str, str]]:
        """Conditions between declared parameters (stability ranges), as ``(name, message)`` pairs.

        Called with the values that passed their own declarations; ``message``
        starts with ``"= value: "`` and says the allowed range and the fix.
        """
        return []

    def fixed_moduli(self) -> tuple[float | None, float | None]:
        r"""Initial shear and bulk moduli :math:`(\mu_0, K_0)` fixed by the law's own parameters.

        ``None`` where the law takes the modulus from the :class:`~alcontact.fem.Material`
        (:math:`\mu` and :math:`K = \lambda + 2\mu/3`). A body checks that the
        material's constants agree with the fixed ones (:meth:`reference_moduli`).
        """
        return None, None

    def reference_moduli(self, lam: float, mu: float) -> tuple[float, float]:
        r"""Lamé constants :math:`(\lambda_0, \mu_0)` of the linearization at :math:`F = I`.

        Read from :math:`\mathbb{A}(I) = \lambda_0\,\delta_{iJ}\delta_{kL}
        + \mu_0(\delta_{ik}\delta_{JL} + \delta_{iL}\delta_{Jk})` in 3D: the consistency
        condition to linear elasticity is :math:`(\lambda_0, \mu_0) = (\lambda, \mu)`.
        """
        A = self.tangent(np.eye(3)[None], lam, mu)[0]
        return float(A[0, 0, 1, 1]), float(A[0, 1, 0, 1])

    def domain_violation(self, F: np.ndarray) -> np.ndarray | None:
        """Where ``F`` (with :math:`J > 0`) lies outside the law's domain: a boolean array of shape
        ``F.shape[:-2]``, or ``None`` when the law is defined for every :math:`J > 0`."""
        return None

    @abstractmethod
    def energy(self, F: np.ndarray, lam: float, mu: float) -> np.ndarray:
        """Strain energy density :math:`W(F)`, shape ``F.shape[:-2]``."""

    @abstractmethod
    def stress(self, F: np.ndarray, lam: float, mu: float) -> np.ndarray:
        r"""First Piola-Kirchhoff stress :math:`P = \partial W/\partial F`, shape of ``F``."""

    @abstractmethod
    def tangent(self, F: np.ndarray, lam: float, mu: float) -> np.ndarray:
        r""":math:`\mathbb{A}_{iJkL} = \partial P_{iJ}/\partial F_{kL}`, shape ``F.shape[:-2] + (d, d, d, d)``."""

    @abstractmethod
    def stress_zz(self, F: np.ndarray, lam: float, mu: float) -> np.ndarray:
        r"""Plane strain only (``d = 2``): the out-of-plane stress :math:`P_{33} = \sigma_{33} J`."""

    def element_tangent(self, F: np.ndarray, G: np.ndarray, dx: np.ndarray, lam: float, mu: float) -> np.ndarray:
        r"""Integrated element tangents :math:`K^e_{aibk} = \sum_q w_q\, G_{aJ}\,\mathbb{A}_{iJkL}\,G_{bL}`.

        Parameters
        ----------
        F : numpy.ndarray, shape (nel, nqp, d, d)
        G : numpy.ndarray, shape (nel, nqp, nloc, d)
            Reference gradients :math:`\partial N_a/\partial X_J` of the scalar shape functions.
        dx : numpy.ndarray, shape (nel, nqp)
            Quadrature weights times the reference Jacobian.

        Returns
        -------
        numpy.ndarray, shape (nel, nloc, d, nloc, d)
            Index order ``(a, i, b, k)``: node ``a`` component ``i``, node ``b`` component ``k``.
        """
        nel, nqp, nloc, d = G.shape
        A = self.tangent(F, lam, mu) * dx[:, :, None, None, None, None]
        # X[a, i, k, L] = G_aJ A_iJkL, then K[a, i, k, b] = X[a, i, k, L] G_bL, summed over q
        X = np.stack([G @ A[:, :, i].reshape(nel, nqp, d, d * d) for i in range(d)], axis=3)
        X = X.reshape(nel, nqp, nloc * d * d, d) @ np.swapaxes(G, -1, -2)
        return X.sum(axis=1).reshape(nel, nloc, d, d, nloc).transpose(0, 1, 2, 4, 3)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r})"


class NeoHookean(HyperelasticLaw):
    r"""Compressible neo-Hookean law (module doc): :math:`W = \frac{\mu}{2}(\operatorname{tr}C - 3) - \mu\ln J + \frac{\lambda}{2}\ln^2 J`."""

    name = "neo-hookean"
    SUMMARY = "W = mu/2 (I1 - 3) - mu ln J + lam/2 (ln J)^2 with the Lame constants of E and nu."

    def energy(self, F, lam, mu):
        d = F.shape[-1]
        lnJ = np.log(det(F))
        trC = np.einsum("...iJ,...iJ->...", F, F)
        return 0.5 * mu * (trC - d) - mu * lnJ + 0.5 * lam * lnJ**2

    def stress(self, F, lam, mu):
        J = det(F)
        FiT = np.swapaxes(inv(F, J), -1, -2)
        return mu * F + (lam * np.log(J) - mu)[..., None, None] * FiT

    def tangent(self, F, lam, mu):
        d = F.shape[-1]
        J = det(F)
        Fi = inv(F, J)
        c1 = (mu - lam * np.log(J))[..., None, None, None, None]
        eye = np.eye(d)
        A = mu * np.einsum("ik,JL->iJkL", eye, eye) + c1 * np.einsum("...Li,...Jk->...iJkL", Fi, Fi)
        A = A + lam * np.einsum("...Ji,...Lk->...iJkL", Fi, Fi)
        return A

    def stress_zz(self, F, lam, mu):
        return lam * np.log(det(F))

    def element_tangent(self, F, G, dx, lam, mu):
        # with the spatial gradients g_a = G_a F^{-1}:
        # K_aibk = sum_q dx [mu (G_a . G_b) d_ik + (mu - lam lnJ) g_ak g_bi + lam g_ai g_bk]
        J = det(F)
        g = G @ inv(F, J)
        return _assemble_terms(g, lam * dx, (mu - lam * np.log(J)) * dx, G, mu * dx)


class SaintVenantKirchhoff(HyperelasticLaw):
    r"""St Venant-Kirchhoff law (module doc): :math:`W = \mu E:E + \frac{\lambda}{2}(\operatorname{tr}E)^2`."""

    name = "saint-venant-kirchhoff"
    SUMMARY = "W = mu E:E + lam/2 (tr E)^2, E = (C - I)/2, with the Lame constants of E and nu."

    @staticmethod
    def _green(F):
        d = F.shape[-1]
        return 0.5 * (np.einsum("...kI,...kJ->...IJ", F, F) - np.eye(d))

    def _pk2(self, F, lam, mu):
        E = self._green(F)
        trE = np.trace(E, axis1=-2, axis2=-1)
        return lam * trE[..., None, None] * np.eye(F.shape[-1]) + 2.0 * mu * E, trE

    def energy(self, F, lam, mu):
        E = self._green(F)
        trE = np.trace(E, axis1=-2, axis2=-1)
        return mu * np.einsum("...IJ,...IJ->...", E, E) + 0.5 * lam * trE**2

    def stress(self, F, lam, mu):
        S, _ = self._pk2(F, lam, mu)
        return F @ S

    def tangent(self, F, lam, mu):
        d = F.shape[-1]
        S, _ = self._pk2(F, lam, mu)
        eye = np.eye(d)
        b = F @ np.swapaxes(F, -1, -2)
        A = np.einsum("ik,...JL->...iJkL", eye, S)
        A = A + lam * np.einsum("...iJ,...kL->...iJkL", F, F)
        A = A + mu * (np.einsum("JL,...ik->...iJkL", eye, b) + np.einsum("...iL,...kJ->...iJkL", F, F))
        return A

    def stress_zz(self, F, lam, mu):
        return lam * np.trace(self._green(F), axis1=-2, axis2=-1)

    def element_tangent(self, F, G, dx, lam, mu):
        # h_a = F G_a: K_aibk = sum_q dx [(G_a S G_b) d_ik + lam h_ai h_bk + mu (h_ak h_bi + b_ik G_a.G_b)]
        S, _ = self._pk2(F, lam, mu)
        h = G @ np.swapaxes(F, -1, -2)
        K = _assemble_terms(h, lam * dx, mu * dx, G @ S, dx, G)
        nel, nqp, nloc, d = G.shape
        b = (F @ np.swapaxes(F, -1, -2)).reshape(nel, nqp, d * d)
        GG = (G @ np.swapaxes(G, -1, -2)).reshape(nel, nqp, nloc * nloc)
        K += _weighted_outer(GG, b, mu * dx).reshape(nel, nloc, nloc, d, d).transpose(0, 1, 3, 2, 4)
        return K


# ------------------------------------------------------------------ symbolic laws
def _flatten(nested):
    """Leaves of the nested lists ``lambdify`` returns, row-major."""
    if isinstance(nested, (list, tuple)):
        for item in nested:
            yield from _flatten(item)
    else:
        yield nested


class SymbolicMaterial(HyperelasticLaw):
    r"""A law defined by its strain energy alone; stress and tangent by SymPy.

    Parameters
    ----------
    W : callable
        ``W(F, lam, mu) -> sympy expression``, with ``F`` a symbolic 3x3
        :class:`sympy.Matrix` and ``lam, mu`` SymPy symbols. Use SymPy
        functions (``sympy.log``, ``F.det()``, ``(F.T * F).trace()``, ...).
    name : str
        Name used in messages and for :func:`register_material`.

    Notes
    -----
    :math:`P = \partial W/\partial F` and :math:`\mathbb{A} = \partial^2 W/\partial F^2`
    are differentiated symbolically, once per dimension (3D, and plane strain
    with :math:`F_{33} = 1` substituted after differentiation), and compiled by
    :func:`sympy.lambdify` to NumPy with common-subexpression elimination.

    Examples
    --------
    >>> import numpy as np, sympy
    >>> def W(F, lam, mu):
    ...     J = F.det()
    ...     return mu / 2 * ((F.T * F).trace() - 3) - mu * sympy.log(J) + lam / 2 * sympy.log(J) ** 2
    >>> law = SymbolicMaterial(W, name="my-neo-hookean")
    >>> F = np.array([[[1.1, 0.2], [0.0, 0.9]]])
    >>> bool(np.allclose(law.stress(F, 2.0, 1.0), NeoHookean().stress(F, 2.0, 1.0)))
    True
    """

    def __init__(self, W: Callable[..., Any], name: str = "symbolic"):
        if not callable(W):
            raise InputError(f"W must be a callable W(F, lam, mu) returning a SymPy expression; got {W!r}.")
        self.W = W
        self.name = str(name)
        self._compiled: dict[int, dict[str, Callable]] = {}

    def _compile(self, d: int) -> dict[str, Callable]:
        if d in self._compiled:
            return self._compiled[d]
        import sympy

        Fs = sympy.Matrix(3, 3, lambda i, j: sympy.Symbol(f"F{i}{j}", real=True))
        lam, mu = sympy.symbols("lam mu", positive=True)
        try:
            W = sympy.sympify(self.W(Fs, lam, mu))
        except Exception as exc:  # a user callable: report what failed and how to write it
            raise InputError(
                f"material {self.name!r}: W(F, lam, mu) failed on a symbolic 3x3 matrix ({exc}); "
                "write W with SymPy operations (F.det(), (F.T * F).trace(), sympy.log, ...)."
            ) from exc
        if not isinstance(W, sympy.Expr) or not W.free_symbols <= set(Fs) | {lam, mu}:
            raise InputError(
                f"material {self.name!r}: W must be a scalar SymPy expression of F, lam and mu; got {W!r}."
            )
        plane = {}
        if d == 2:
            plane = {Fs[2, 2]: 1, Fs[0, 2]: 0, Fs[1, 2]: 0, Fs[2, 0]: 0, Fs[2, 1]: 0}
        free = [Fs[i, j] for i in range(d) for j in range(d)]
        P = [[sympy.diff(W, Fs[i, j]) for j in range(d)] for i in range(d)]
        A = [[[[sympy.diff(P[i][j], Fs[k, m]).subs(plane) for m in range(d)] for k in range(d)]
               for j in range(d)] for i in range(d)]
        exprs = {
            "energy": [W.subs(plane)],
            "stress": [p.subs(plane) for row in P for p in row],
            "tangent": list(_flatten(A)),
        }
        if d == 2:
            exprs["stress_zz"] = [sympy.diff(W, Fs[2, 2]).subs(plane)]
        args = [*free, lam, mu]
        # flat lists: lambdify's common-subexpression elimination only applies to flat sequences
        out = {key: sympy.lambdify(args, e, modules="numpy", cse=True) for key, e in exprs.items()}
        self._compiled[d] = out
        return out

    def _eval(self, key: str, F: np.ndarray, lam: float, mu: float, tail: tuple[int, ...]) -> np.ndarray:
        d = F.shape[-1]
        fun = self._compile(d)[key]
        comps = [F[..., i, j] for i in range(d) for j in range(d)]
        res = fun(*comps, float(lam), float(mu))
        shape = F.shape[:-2]
        out = np.empty(shape + (len(res),))
        for k, v in enumerate(res):
            out[..., k] = v  # broadcasts the constant entries
        return out.reshape(shape + tail)

    def energy(self, F, lam, mu):
        return self._eval("energy", F, lam, mu, ())

    def stress(self, F, lam, mu):
        d = F.shape[-1]
        return self._eval("stress", F, lam, mu, (d, d))

    def tangent(self, F, lam, mu):
        d = F.shape[-1]
        return self._eval("tangent", F, lam, mu, (d, d, d, d))

    def stress_zz(self, F, lam, mu):
        if F.shape[-1] != 2:
            raise InputError("stress_zz is the plane-strain out-of-plane stress; F must be 2x2.")
        return self._eval("stress_zz", F, lam, mu, ())


# ------------------------------------------------------------------------ registry
_REGISTRY: dict[str, Callable[[], HyperelasticLaw]] = {
    "neo-hookean": NeoHookean,
    "saint-venant-kirchhoff": SaintVenantKirchhoff,
}


def available_materials() -> list[str]:
    """Names of the registered hyperelastic laws."""
    return sorted(_REGISTRY)


def material_parameters(name: str) -> tuple:
    """Declared parameters (:class:`~alcontact._options.Option`) of the law registered as ``name``."""
    if not isinstance(name, str) or name not in _REGISTRY:
        raise UnknownNameError("hyperelastic material", str(name), list(_REGISTRY))
    return tuple(getattr(_REGISTRY[name], "PARAMETERS", ()))


def example_material_parameters(name: str) -> dict[str, Any]:
    """Parameters of the documented example of law ``name`` (``{}`` for a law without parameters)."""
    material_parameters(name)  # the name check
    return dict(getattr(_REGISTRY[name], "EXAMPLE_PARAMETERS", {}))


def make_material(name: str | HyperelasticLaw, **params: Any) -> HyperelasticLaw:
    """The hyperelastic law registered as ``name`` (a law instance is returned as is).

    Parameters
    ----------
    name : str or HyperelasticLaw
    **params
        The law's declared parameters (:func:`material_parameters`), e.g.
        ``make_material("mooney-rivlin", c10=0.4, c01=0.1)``.

    Raises
    ------
    alcontact.errors.UnknownNameError
        If no law has that name (the message lists the known ones).
    alcontact.errors.InputError
        If a parameter is unknown, missing or out of its stable range.
    """
    if isinstance(name, HyperelasticLaw):
        if params:
            raise InputError(f"make_material: parameters {sorted(params)} given with a law instance {name!r}; "
                             "pass the parameters when building the instance.")
        return name
    if not isinstance(name, str) or name not in _REGISTRY:
        raise UnknownNameError("hyperelastic material", str(name), list(_REGISTRY))
    factory = _REGISTRY[name]
    build = getattr(factory, "from_parameters", None)  # a law with declared parameters checks them
    if build is not None:
        law = build(params, name=name)
    elif params:
        raise InputError(f"material {name!r} takes no parameters (its constants are E and nu); got "
                         f"{', '.join(sorted(params))}.")
    else:
        law = factory()
    if not isinstance(law, HyperelasticLaw):
        raise InputError(f"the factory registered as material {name!r} returned {law!r}, not a HyperelasticLaw; "
                         "register a HyperelasticLaw instance or a factory that returns one.")
    return law


def register_material(name: str, law: HyperelasticLaw | Callable[[], HyperelasticLaw], *,
                      overwrite: bool = False) -> None:
    """Register a law (an instance, or a factory returning one) under ``name``.

    A law defined by its energy alone is a :class:`SymbolicMaterial`, e.g.
    ``register_material("my-law", SymbolicMaterial(W, name="my-law"))``; then
    ``Hyperelastic(mesh, material, model="my-law")`` uses it.

    Raises
    ------
    alcontact.errors.InputError
        If ``name`` is taken (pass ``overwrite=True``) or ``law`` is neither a law nor callable.
    """
    name = str(name)
    if not name:
        raise InputError("material name must be a non-empty string.")
    if name in _REGISTRY and not overwrite:
        raise InputError(f"material {name!r} is already registered; pass overwrite=True to replace it.")
    if isinstance(law, HyperelasticLaw):
        instance = law
        _REGISTRY[name] = lambda: instance
    elif callable(law):
        _REGISTRY[name] = law
    else:
        raise InputError(f"law must be a HyperelasticLaw or a factory returning one; got {law!r}.")
