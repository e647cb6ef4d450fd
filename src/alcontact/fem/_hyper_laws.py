r"""The usual rubber laws: Mooney-Rivlin, Yeoh, Gent, Arruda-Boyce, Ogden, and a user energy.

Every law here is written in the isochoric/volumetric split of a compressible
solid,

.. math::
    W(F) = \bar W(\bar I_1, \bar I_2) + U(J), \qquad
    \bar I_1 = J^{-2/3} I_1,\quad \bar I_2 = J^{-4/3} I_2,\quad
    U(J) = \tfrac{K}{2}(J - 1)^2,

with :math:`C = F^TF`, :math:`I_1 = \operatorname{tr}C`,
:math:`I_2 = \tfrac12(I_1^2 - \operatorname{tr}C^2)`, :math:`J = \det F`, and
the bulk modulus :math:`K = \lambda + 2\mu/3` of the :class:`~alcontact.fem.Material`
(the volumetric term of Abaqus, :math:`U = (J-1)^2/D_1` with :math:`D_1 = 2/K`).
The isochoric parts (dissertation chapter 3 leaves :math:`W` open; the forms
are those of Holzapfel, *Nonlinear Solid Mechanics*, 2000, section 6.5, and of
the cited authors):

``"mooney-rivlin"`` (parameters ``c10``, ``c01``)
    :math:`\bar W = c_{10}(\bar I_1 - 3) + c_{01}(\bar I_2 - 3)`, :math:`\mu_0 = 2(c_{10} + c_{01})`.
    Stable at the reference for :math:`c_{10} + c_{01} > 0` (checked); polyconvex for
    :math:`c_{10}, c_{01} \ge 0` (a warning is logged otherwise).
``"yeoh"`` (``c10``, ``c20``, ``c30``)
    :math:`\bar W = \sum_{i=1}^3 c_{i0}(\bar I_1 - 3)^i`, :math:`\mu_0 = 2 c_{10}`. Checked:
    :math:`\partial\bar W/\partial\bar I_1 = c_{10} + 2c_{20}x + 3c_{30}x^2 > 0` for every
    :math:`x = \bar I_1 - 3 \ge 0` (positive shear stiffness at every stretch), i.e.
    :math:`c_{10} > 0`, :math:`c_{30} \ge 0` and (:math:`c_{20} \ge 0` or :math:`c_{20}^2 < 3c_{10}c_{30}`).
``"gent"`` (``Jm``)
    :math:`\bar W = -\tfrac{\mu J_m}{2}\ln\bigl(1 - (\bar I_1 - 3)/J_m\bigr)`, :math:`\mu_0 = \mu`,
    :math:`J_m > 0` (the limiting value of :math:`\bar I_1 - 3`; the energy is infinite there).
``"arruda-boyce"`` (``lambda_m``)
    Eight-chain model, five terms of the inverse Langevin series (Arruda and Boyce 1993, as in
    Abaqus): :math:`\bar W = \mu_c\sum_{i=1}^5 \frac{C_i}{\lambda_m^{2i-2}}(\bar I_1^i - 3^i)`,
    :math:`C = (\tfrac12, \tfrac1{20}, \tfrac{11}{1050}, \tfrac{19}{7000}, \tfrac{519}{673750})`,
    with :math:`\mu_c` chosen so that :math:`\mu_0 = \mu`:
    :math:`\mu_c = \mu/(1 + \tfrac{3}{5\lambda_m^2} + \tfrac{99}{175\lambda_m^4}
    + \tfrac{513}{875\lambda_m^6} + \tfrac{42039}{67375\lambda_m^8})`; locking stretch :math:`\lambda_m > 1`.
``"ogden"`` (``mu``, ``alpha``: lists of N = 1..6 terms)
    :math:`\bar W = \sum_p \frac{\mu_p}{\alpha_p}(\bar\lambda_1^{\alpha_p} + \bar\lambda_2^{\alpha_p}
    + \bar\lambda_3^{\alpha_p} - 3)` in the isochoric principal stretches
    :math:`\bar\lambda_a = J^{-1/3}\lambda_a`, :math:`\mu_0 = \tfrac12\sum_p \mu_p\alpha_p`.
    Checked: :math:`\alpha_p \ne 0` and :math:`\sum_p \mu_p\alpha_p > 0`; every
    :math:`\mu_p\alpha_p > 0` (sufficient for stability) is advised by a logged warning.

Consistency with linear elasticity: at :math:`F = I` the tangent is
:math:`\mathbb{A} = K\,I\otimes I + \mu_0(\mathbb{I} + \bar{\mathbb{I}} - \tfrac23 I\otimes I)`, the
isotropic elasticity tensor with shear modulus :math:`\mu_0` and bulk modulus :math:`K`: a body
requires :math:`\mu_0` equal to the material's :math:`\mu = E/(2(1+\nu))`
(:meth:`~alcontact.fem.HyperelasticLaw.reference_moduli`). Mooney-Rivlin, Yeoh and Ogden fix
:math:`\mu_0` by their parameters, so a problem file may omit ``E`` (it is :math:`2\mu_0(1+\nu)`).

Invariant laws (all but Ogden) evaluate :math:`P` and :math:`\mathbb{A}` by the chain rule
through :math:`(I_1, I_2, J)`,

.. math::
    P = \sum_a W_a \frac{\partial I_a}{\partial F}, \qquad
    \mathbb{A} = \sum_{a,b} W_{ab}\,\frac{\partial I_a}{\partial F}\otimes\frac{\partial I_b}{\partial F}
    + \sum_a W_a \frac{\partial^2 I_a}{\partial F\,\partial F},

with the derivatives :math:`W_a, W_{ab}` of :math:`W(I_1, I_2, J)` taken by SymPy (three scalar
variables, compiled once per law with :func:`sympy.lambdify`) and
:math:`\partial I_1/\partial F = 2F`, :math:`\partial I_2/\partial F = 2(I_1F - FC)`,
:math:`\partial J/\partial F = J F^{-T}`. Ogden uses the spectral form of the stress
:math:`S = \sum_a S_a N_a\otimes N_a` and of its tangent (Holzapfel eq. 6.196, with the
l'Hopital limit of eq. 6.197 for equal stretches). In 2D (plane strain) the 3D law is evaluated
with :math:`F_{33} = 1` and its in-plane block returned.

A user law is an energy expression of the invariants (:class:`EnergyExpression`), parsed
from text without ``eval`` (:mod:`alcontact.fem._energy_expression`).

Examples
--------
>>> import numpy as np
>>> law = MooneyRivlin(c10=0.4, c01=0.1)
>>> law.fixed_moduli()
(1.0, None)
>>> lam0, mu0 = law.reference_moduli(lam=2.0, mu=1.0)
>>> round(lam0, 12), round(mu0, 12)
(2.0, 1.0)
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from alcontact._options import REQUIRED, Option
from alcontact.errors import InputError
from alcontact.fem._hyper_materials import (
    HyperelasticLaw,
    _assemble_terms,
    _weighted_outer,
    det,
    inv,
    material_parameters,
    register_material,
)

__all__ = ["InvariantLaw", "MooneyRivlin", "Yeoh", "Gent", "ArrudaBoyce", "Ogden", "EnergyExpression",
           "check_material_parameters"]

logger = logging.getLogger(__name__)


def _check_parameters(cls, params: dict[str, Any] | None, name: str, *,
                      api: bool = False) -> tuple[dict[str, Any], list[tuple[str, str]]]:
    """:func:`check_material_parameters` on the declarations of the law class ``cls``."""
    import difflib

    from alcontact._options import BAD, check_value

    decl = tuple(getattr(cls, "PARAMETERS", ()))
    known = [o.name for o in decl]
    if params is not None and not isinstance(params, Mapping):
        raise InputError(f"material {name!r}: parameters = {params!r} ({type(params).__name__}): expected a dict "
                         f"of parameter names to values, e.g. {dict(getattr(cls, 'EXAMPLE_PARAMETERS', {}))!r}.")
    params = dict(params or {})
    issues: list[tuple[str, str]] = []
    values: dict[str, Any] = {}
    for key, value in params.items():
        opt = next((o for o in decl if o.name == key), None)
        if opt is None:
            close = difflib.get_close_matches(str(key), known, n=1, cutoff=0.6)
            mean = f" Did you mean {close[0]!r}?" if close else ""
            allowed = ", ".join(known) if known else "none (it takes its constants from E and nu)"
            issues.append((str(key), f"= {value!r}: not a parameter of material {name!r}.{mean} "
                                     f"Its parameters: {allowed}."))
            continue
        v, found = check_value(opt, value, api=api)
        issues.extend((key + suffix, msg) for suffix, msg in found)
        if v is not BAD:
            values[key] = v
    for opt in decl:
        if opt.name not in params:
            if opt.required:
                issues.append((opt.name, f"missing (required by material {name!r}): {opt.doc}"))
            else:
                values[opt.name] = opt.default
    if not issues:
        check = getattr(cls, "parameter_issues", None)
        if check is not None:
            issues.extend(check(values))
    return values, issues


def check_material_parameters(name: str, params: dict[str, Any] | None, *,
                              api: bool = False) -> tuple[dict[str, Any], list[tuple[str, str]]]:
    """Check ``params`` against the declarations of the law registered as ``name``.

    Returns
    -------
    values, issues
        The converted values (declared defaults filled in), and ``(parameter, message)``
        pairs for unknown, missing or out-of-range parameters and for violated
        stability conditions (:meth:`~alcontact.fem.HyperelasticLaw.parameter_issues`);
        each message starts with ``"= value: "`` or says what is missing, and the fix.

    Examples
    --------
    >>> check_material_parameters("gent", {"Jm": 0.0})[1]
    [('Jm', '= 0.0: out of range, must be > 0.')]
    """
    from alcontact.fem._hyper_materials import _REGISTRY

    material_parameters(name)  # the name check
    return _check_parameters(_REGISTRY[name], params, name, api=api)


def _raise_issues(name: str, issues) -> None:
    if issues:
        raise InputError(f"material {name!r}: " + " ".join(f"{k} {m}" if m.startswith("= ") else f"{k}: {m}"
                                                           for k, m in issues))


class _Parametrized:
    """Mixin of the laws with declared parameters: checked construction from a dict (registry)."""

    @classmethod
    def from_parameters(cls, params: dict[str, Any], *, name: str | None = None):
        """The law built from ``params`` after the full check (unknown, missing, ranges, stability)."""
        name = cls.name if name is None else name
        values, issues = _check_parameters(cls, params, name, api=True)
        _raise_issues(name, issues)
        return cls(**values)

    def _checked(self, **values) -> dict[str, Any]:
        out, issues = _check_parameters(type(self), values, self.name, api=True)
        _raise_issues(self.name, issues)
        return out


#: compiled (energy, gradient, Hessian) functions of W(I1, I2, J), per law class (or per user expression)
_COMPILED: dict[Any, tuple[Callable, Callable, Callable]] = {}


def _embed(F: np.ndarray) -> np.ndarray:
    """A 2x2 (plane strain) deformation gradient as the 3x3 one with ``F33 = 1``; 3x3 unchanged."""
    if F.shape[-1] == 3:
        return F
    F3 = np.zeros(F.shape[:-2] + (3, 3))
    F3[..., :2, :2] = F
    F3[..., 2, 2] = 1.0
    return F3


def _eye4():
    e = np.eye(3)
    return np.einsum("ik,JL->iJkL", e, e)


class InvariantLaw(HyperelasticLaw):
    r"""A law :math:`W(I_1, I_2, J)` of the invariants, stress and tangent by the chain rule.

    Subclasses implement :meth:`energy_expression` returning a SymPy expression
    of the symbols ``I1, I2, J`` and ``lam, mu`` (the material's Lamé constants).
    """

    def energy_expression(self, I1, I2, J, lam, mu, p):  # pragma: no cover - abstract in spirit
        """SymPy expression of :math:`W` in the invariants, the Lamé constants and the parameter symbols ``p``."""
        raise InputError(f"{type(self).__name__} does not define its energy.")

    def parameter_values(self) -> dict[str, float]:
        """Values of the scalar parameters, by name (symbols of :meth:`energy_expression`)."""
        return {o.name: float(getattr(self, o.name)) for o in self.PARAMETERS}

    def _cache_key(self) -> Any:
        return type(self)

    def _compiled(self) -> tuple[Callable, Callable, Callable]:
        # parameters stay symbols (values passed at evaluation): one compilation per law class, and
        # SymPy does not distribute numeric coefficients (W(I) = 0 exactly, no cancelling constants)
        key = self._cache_key()
        if key in _COMPILED:
            return _COMPILED[key]
        import sympy

        I1, I2, J = sympy.symbols("I1 I2 J", positive=True)
        lam, mu = sympy.symbols("lam mu", positive=True)
        names = list(self.parameter_values())
        p = {n: sympy.Symbol(f"p_{n}", real=True) for n in names}
        W = sympy.sympify(self.energy_expression(I1, I2, J, lam, mu, p))
        x = (I1, I2, J)
        grad = [sympy.diff(W, v) for v in x]
        hess = [sympy.diff(grad[a], x[b]) for a, b in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))]
        args = [I1, I2, J, lam, mu, *(p[n] for n in names)]
        funs = (sympy.lambdify(args, W, modules="numpy"),
                sympy.lambdify(args, grad, modules="numpy", cse=True),
                sympy.lambdify(args, hess, modules="numpy", cse=True))
        _COMPILED[key] = funs
        return funs

    def _args(self, I1, I2, J, lam, mu) -> tuple:
        return (I1, I2, J, float(lam), float(mu), *self.parameter_values().values())

    @staticmethod
    def _invariants(F3: np.ndarray):
        C = np.swapaxes(F3, -1, -2) @ F3
        I1 = np.trace(C, axis1=-2, axis2=-1)
        I2 = 0.5 * (I1**2 - np.einsum("...IJ,...JI->...", C, C))
        return C, I1, I2, det(F3)

    @staticmethod
    def _values(fun: Callable, shape: tuple, *args) -> list[np.ndarray]:
        res = fun(*args)
        res = res if isinstance(res, list) else [res]
        return [np.broadcast_to(np.asarray(r, dtype=float), shape) for r in res]

    def energy(self, F, lam, mu):
        _, I1, I2, J = self._invariants(_embed(F))
        return self._values(self._compiled()[0], J.shape, *self._args(I1, I2, J, lam, mu))[0].copy()

    def _stress3(self, F3, lam, mu):
        C, I1, I2, J = self._invariants(F3)
        W1, W2, WJ = self._values(self._compiled()[1], J.shape, *self._args(I1, I2, J, lam, mu))
        dJ = J[..., None, None] * np.swapaxes(inv(F3, J), -1, -2)
        dI1 = 2.0 * F3
        dI2 = 2.0 * (I1[..., None, None] * F3 - F3 @ C)
        P = W1[..., None, None] * dI1 + W2[..., None, None] * dI2 + WJ[..., None, None] * dJ
        return P, (C, I1, I2, J, dI1, dI2, dJ)

    def stress(self, F, lam, mu):
        d = F.shape[-1]
        return self._stress3(_embed(F), lam, mu)[0][..., :d, :d].copy()

    def stress_zz(self, F, lam, mu):
        if F.shape[-1] != 2:
            raise InputError("stress_zz is the plane-strain out-of-plane stress; F must be 2x2.")
        return self._stress3(_embed(F), lam, mu)[0][..., 2, 2].copy()

    def tangent(self, F, lam, mu):
        d = F.shape[-1]
        F3 = _embed(F)
        C, I1, I2, J = self._invariants(F3)
        args = self._args(I1, I2, J, lam, mu)
        W1, W2, WJ = self._values(self._compiled()[1], J.shape, *args)
        W11, W12, W1J, W22, W2J, WJJ = self._values(self._compiled()[2], J.shape, *args)
        Fi = inv(F3, J)
        FiT = np.swapaxes(Fi, -1, -2)
        dI = (2.0 * F3, 2.0 * (I1[..., None, None] * F3 - F3 @ C), J[..., None, None] * FiT)
        Wab = ((W11, W12, W1J), (W12, W22, W2J), (W1J, W2J, WJJ))
        A = np.zeros(F3.shape[:-2] + (3, 3, 3, 3))
        for a in range(3):
            for b in range(3):
                A += Wab[a][b][..., None, None, None, None] * np.einsum("...iJ,...kL->...iJkL", dI[a], dI[b])
        e = np.eye(3)
        I4 = _eye4()
        b_ = F3 @ np.swapaxes(F3, -1, -2)
        d2I2 = 2.0 * (2.0 * np.einsum("...iJ,...kL->...iJkL", F3, F3) + I1[..., None, None, None, None] * I4
                      - np.einsum("ik,...LJ->...iJkL", e, C) - np.einsum("...iL,...kJ->...iJkL", F3, F3)
                      - np.einsum("...ik,JL->...iJkL", b_, e))
        d2J = J[..., None, None, None, None] * (np.einsum("...iJ,...kL->...iJkL", FiT, FiT)
                                                - np.einsum("...iL,...kJ->...iJkL", FiT, FiT))
        A += 2.0 * W1[..., None, None, None, None] * I4 + W2[..., None, None, None, None] * d2I2
        A += WJ[..., None, None, None, None] * d2J
        return A[..., :d, :d, :d, :d].copy()


    def element_tangent(self, F, G, dx, lam, mu):
        r"""Integrated element tangents by the chain-rule terms, without forming :math:`\mathbb{A}`.

        With :math:`v^\alpha_a = G_a \cdot (\partial I_\alpha/\partial F)^T`, :math:`h_a = F G_a`,
        :math:`g_a = F^{-T} G_a` (3D, plane strain padded with :math:`G_{a3} = 0`):

        .. math::
            K_{aibk} = \sum_q w_q\Bigl[\sum_{\alpha\beta} W_{\alpha\beta} v^\alpha_{ai} v^\beta_{bk}
            + 2W_2(2 h_{ai}h_{bk} - h_{ak}h_{bi} - b_{ik}\,G_a\cdot G_b)
            + W_J J (g_{ai}g_{bk} - g_{ak}g_{bi})
            + \delta_{ik}\bigl((2W_1 + 2W_2I_1)\,G_a\cdot G_b - 2W_2\,G_a C G_b\bigr)\Bigr].
        """
        nel, nqp, nloc, d = G.shape
        F3 = _embed(F)
        G3 = G if d == 3 else np.concatenate([G, np.zeros(G.shape[:-1] + (1,))], axis=-1)
        C, I1, I2, J = self._invariants(F3)
        args = self._args(I1, I2, J, lam, mu)
        W1, W2, WJ = self._values(self._compiled()[1], J.shape, *args)
        W11, W12, W1J, W22, W2J, WJJ = self._values(self._compiled()[2], J.shape, *args)
        FiT = np.swapaxes(inv(F3, J), -1, -2)
        FT = np.swapaxes(F3, -1, -2)
        dI = (2.0 * F3, 2.0 * (I1[..., None, None] * F3 - F3 @ C), J[..., None, None] * FiT)
        m = 3 * nloc
        V = np.stack([(G3 @ np.swapaxes(D, -1, -2)).reshape(nel, nqp, m) for D in dI], axis=2)  # (e, q, 3, m)
        Wm = np.stack([np.stack(r, axis=-1) for r in ((W11, W12, W1J), (W12, W22, W2J), (W1J, W2J, WJJ))],
                      axis=-2) * dx[..., None, None]
        WV = Wm @ V
        K = np.matmul(np.swapaxes(V.reshape(nel, nqp * 3, m), 1, 2), WV.reshape(nel, nqp * 3, m))
        K = K.reshape(nel, nloc, 3, nloc, 3)
        h = G3 @ FT  # h_ai = F_iJ G_aJ
        K += _assemble_terms(h, 4.0 * W2 * dx, -2.0 * W2 * dx, G3, (2.0 * W1 + 2.0 * W2 * I1) * dx)
        g = G3 @ inv(F3, J)  # g_ai = G_aJ Fi_Ji
        K += _assemble_terms(g, WJ * J * dx, -WJ * J * dx, G3 @ C, -2.0 * W2 * dx, G3)
        b = (F3 @ FT).reshape(nel, nqp, 9)
        GG = (G3 @ np.swapaxes(G3, -1, -2)).reshape(nel, nqp, nloc * nloc)
        K += _weighted_outer(GG, b, -2.0 * W2 * dx).reshape(nel, nloc, nloc, 3, 3).transpose(0, 1, 3, 2, 4)
        return np.ascontiguousarray(K[:, :, :d, :, :d]) if d == 2 else K


def _volumetric(J, lam, mu):
    r""":math:`U(J) = \frac{K}{2}(J-1)^2` with :math:`K = \lambda + 2\mu/3`."""
    return (lam + 2 * mu / 3) / 2 * (J - 1) ** 2


def _isochoric(I1, I2, J):
    import sympy

    return I1 * J ** sympy.Rational(-2, 3), I2 * J ** sympy.Rational(-4, 3)


class MooneyRivlin(_Parametrized, InvariantLaw):
    r"""Mooney-Rivlin: :math:`W = c_{10}(\bar I_1 - 3) + c_{01}(\bar I_2 - 3) + \frac{K}{2}(J-1)^2` (module doc).

    Examples
    --------
    >>> MooneyRivlin(c10=0.3, c01=0.05).fixed_moduli()
    (0.7, None)
    """

    name = "mooney-rivlin"
    SUMMARY = 'W = c10 (I1b - 3) + c01 (I2b - 3) + K/2 (J - 1)^2; initial shear modulus mu0 = 2 (c10 + c01).'
    EXAMPLE_PARAMETERS = {"c10": 0.35, "c01": 0.1}
    PARAMETERS = (
        Option("c10", "float", REQUIRED, "Mooney-Rivlin: coefficient of (I1b - 3), stress units; c10 + c01 > 0 "
               "(initial shear modulus 2 (c10 + c01))."),
        Option("c01", "float", 0.0, "Mooney-Rivlin: coefficient of (I2b - 3), stress units (0: neo-Hookean)."),
    )

    def __init__(self, c10: float, c01: float = 0.0):
        v = self._checked(c10=c10, c01=c01)
        self.c10, self.c01 = v["c10"], v["c01"]

    @classmethod
    def parameter_issues(cls, values):
        c10, c01 = values["c10"], values["c01"]
        if not c10 + c01 > 0:
            return [("c01", f"= {c01!r}: c10 + c01 = {c10 + c01:g} must be > 0 (the initial shear modulus is "
                            "2 (c10 + c01)); e.g. c10 = 0.4, c01 = 0.1.")]
        if c10 < 0 or c01 < 0:
            logger.warning("mooney-rivlin with c10=%g, c01=%g: not polyconvex (c10, c01 >= 0 is); the law may "
                           "lose stability at large strains", c10, c01)
        return []

    def fixed_moduli(self):
        return 2.0 * (self.c10 + self.c01), None

    def energy_expression(self, I1, I2, J, lam, mu, p):
        I1b, I2b = _isochoric(I1, I2, J)
        return p["c10"] * (I1b - 3) + p["c01"] * (I2b - 3) + _volumetric(J, lam, mu)


class Yeoh(_Parametrized, InvariantLaw):
    r"""Yeoh: :math:`W = \sum_{i=1}^3 c_{i0}(\bar I_1 - 3)^i + \frac{K}{2}(J-1)^2` (module doc)."""

    name = "yeoh"
    SUMMARY = 'W = c10 (I1b - 3) + c20 (I1b - 3)^2 + c30 (I1b - 3)^3 + K/2 (J - 1)^2; mu0 = 2 c10; checked: dW/dI1b > 0 at every stretch.'
    EXAMPLE_PARAMETERS = {"c10": 0.45, "c20": -0.02, "c30": 0.005}
    PARAMETERS = (
        Option("c10", "float", REQUIRED, "Yeoh: coefficient of (I1b - 3), stress units; initial shear modulus "
               "2 c10.", low=0, low_open=True),
        Option("c20", "float", 0.0, "Yeoh: coefficient of (I1b - 3)^2; negative allowed while c20^2 < 3 c10 c30."),
        Option("c30", "float", 0.0, "Yeoh: coefficient of (I1b - 3)^3.", low=0),
    )

    def __init__(self, c10: float, c20: float = 0.0, c30: float = 0.0):
        v = self._checked(c10=c10, c20=c20, c30=c30)
        self.c10, self.c20, self.c30 = v["c10"], v["c20"], v["c30"]

    @classmethod
    def parameter_issues(cls, values):
        c10, c20, c30 = values["c10"], values["c20"], values["c30"]
        # min over x >= 0 of c10 + 2 c20 x + 3 c30 x^2 > 0
        if c20 < 0 and not c20 * c20 < 3.0 * c10 * c30:
            return [("c20", f"= {c20!r}: with c10 = {c10:g}, c30 = {c30:g} the shear stiffness "
                            "dW/dI1b = c10 + 2 c20 x + 3 c30 x^2 (x = I1b - 3) turns negative at large stretch; "
                            "a negative c20 needs c20^2 < 3 c10 c30 (raise c30 or make c20 smaller in magnitude).")]
        return []

    def fixed_moduli(self):
        return 2.0 * self.c10, None

    def energy_expression(self, I1, I2, J, lam, mu, p):
        x = _isochoric(I1, I2, J)[0] - 3
        return p["c10"] * x + p["c20"] * x**2 + p["c30"] * x**3 + _volumetric(J, lam, mu)


class Gent(_Parametrized, InvariantLaw):
    r"""Gent: :math:`W = -\frac{\mu J_m}{2}\ln(1 - (\bar I_1 - 3)/J_m) + \frac{K}{2}(J-1)^2` (module doc).

    Outside :math:`\bar I_1 < 3 + J_m` the energy is undefined (NaN; the solver
    reports non-finite values and cuts the load step back).
    """

    name = "gent"
    SUMMARY = 'W = -mu Jm/2 ln(1 - (I1b - 3)/Jm) + K/2 (J - 1)^2; mu0 = mu of E and nu; I1b - 3 must stay below Jm.'
    EXAMPLE_PARAMETERS = {"Jm": 20.0}
    PARAMETERS = (
        Option("Jm", "float", REQUIRED, "Gent: limiting value of I1b - 3 (chain extensibility; rubber about "
               "30-100); the shear modulus is the material's mu.", low=0, low_open=True),
    )

    def __init__(self, Jm: float):
        self.Jm = self._checked(Jm=Jm)["Jm"]

    def domain_violation(self, F):
        r"""Points at or beyond the locking, :math:`\bar I_1 - 3 \ge J_m` (the energy is infinite there)."""
        _, I1, _, J = self._invariants(_embed(F))
        return ~(I1 * J ** (-2.0 / 3.0) - 3.0 < self.Jm)

    def energy_expression(self, I1, I2, J, lam, mu, p):
        import sympy

        I1b, Jm = _isochoric(I1, I2, J)[0], p["Jm"]
        return -mu * Jm / 2 * sympy.log(1 - (I1b - 3) / Jm) + _volumetric(J, lam, mu)


#: coefficients C_i of the Arruda-Boyce series (numerators, denominators)
_AB_C = ((1, 2), (1, 20), (11, 1050), (19, 7000), (519, 673750))


class ArrudaBoyce(_Parametrized, InvariantLaw):
    r"""Arruda-Boyce eight-chain model, five-term series (module doc)."""

    name = "arruda-boyce"
    SUMMARY = 'Eight-chain model, five-term series in I1b (Arruda and Boyce 1993, as in Abaqus) + K/2 (J - 1)^2, scaled so that mu0 = mu of E and nu.'
    EXAMPLE_PARAMETERS = {"lambda_m": 3.0}
    PARAMETERS = (
        Option("lambda_m", "float", REQUIRED, "Arruda-Boyce: locking chain stretch (> 1; rubber about 3-7); the "
               "initial shear modulus is the material's mu.", low=1, low_open=True),
    )

    def __init__(self, lambda_m: float):
        self.lambda_m = self._checked(lambda_m=lambda_m)["lambda_m"]

    @staticmethod
    def shear_factor(lambda_m):
        r""":math:`\mu_0/\mu_c = 2\sum_i i\,C_i\,3^{i-1}/\lambda_m^{2i-2}` (a number or a SymPy expression)."""
        import sympy

        return 2 * sum(i * sympy.Rational(*_AB_C[i - 1]) * 3 ** (i - 1) / lambda_m ** (2 * i - 2) for i in range(1, 6))

    def energy_expression(self, I1, I2, J, lam, mu, p):
        I1b, lm = _isochoric(I1, I2, J)[0], p["lambda_m"]
        import sympy

        W = sum(sympy.Rational(*_AB_C[i - 1]) / lm ** (2 * i - 2) * (I1b**i - 3**i) for i in range(1, 6))
        return mu / self.shear_factor(lm) * W + _volumetric(J, lam, mu)


class Ogden(_Parametrized, HyperelasticLaw):
    r"""Ogden law of N terms in the isochoric principal stretches (module doc).

    Parameters
    ----------
    mu, alpha : sequence of float
        :math:`\mu_p` (stress units) and :math:`\alpha_p` (nonzero), same length N.

    Notes
    -----
    With :math:`\beta_a = \lambda_a\,\partial W/\partial\lambda_a
    = \sum_p \mu_p(\bar\lambda_a^{\alpha_p} - \frac13\sum_c\bar\lambda_c^{\alpha_p}) + J U'(J)`,
    the principal PK2 stresses are :math:`S_a = \beta_a/\lambda_a^2`; the tangent uses
    :math:`\gamma_{ab} = \lambda_b\,\partial\beta_a/\partial\lambda_b`.
    """

    name = "ogden"
    SUMMARY = 'W = sum_p mu_p/alpha_p (l1b^alpha_p + l2b^alpha_p + l3b^alpha_p - 3) + K/2 (J - 1)^2 in the isochoric principal stretches; mu0 = sum(mu_p alpha_p)/2.'
    EXAMPLE_PARAMETERS = {"mu": [0.88, 0.004, -0.01], "alpha": [2.0, 5.0, -2.0]}
    PARAMETERS = (
        Option("mu", "floats", REQUIRED, "Ogden: moduli mu_p of the N terms (stress units); the initial shear "
               "modulus is sum(mu_p alpha_p) / 2 > 0.", lengths=(1, 2, 3, 4, 5, 6)),
        Option("alpha", "floats", REQUIRED, "Ogden: exponents alpha_p (nonzero), as many as mu.", low=-100,
               high=100, lengths=(1, 2, 3, 4, 5, 6)),
    )

    def __init__(self, mu, alpha):
        as_list = (lambda v: [float(x) for x in np.ravel(v)] if isinstance(v, np.ndarray) else v)  # noqa: E731
        v = self._checked(mu=as_list(mu), alpha=as_list(alpha))
        self.mu = np.asarray(v["mu"], dtype=float)
        self.alpha = np.asarray(v["alpha"], dtype=float)

    @classmethod
    def parameter_issues(cls, values):
        mu, alpha = list(values["mu"]), list(values["alpha"])
        if len(mu) != len(alpha) or not mu:
            return [("alpha", f"= {alpha!r}: needs as many exponents as mu has terms ({len(mu)}).")]
        zero = [i for i, a in enumerate(alpha) if a == 0]
        if zero:
            return [(f"alpha[{zero[0]}]", "= 0: an Ogden exponent must be nonzero (the term is mu/alpha ...).")]
        s = sum(m * a for m, a in zip(mu, alpha))
        if not s > 0:
            return [("mu", f"= {mu!r}: sum(mu_p alpha_p) = {s:g} must be > 0 (twice the initial shear "
                           "modulus); e.g. mu = [0.63, 0.0012, -0.01], alpha = [1.3, 5.0, -2.0] (Treloar).")]
        if any(m * a <= 0 for m, a in zip(mu, alpha)):
            logger.warning("ogden with mu=%s, alpha=%s: some mu_p alpha_p <= 0; stability is then not "
                           "guaranteed at every stretch (mu_p alpha_p > 0 for all p is sufficient)", mu, alpha)
        return []

    def fixed_moduli(self):
        return 0.5 * float(np.sum(self.mu * self.alpha)), None

    def _principal(self, F3, lam, mu):
        C = np.swapaxes(F3, -1, -2) @ F3
        ev, N = np.linalg.eigh(C)
        ls = np.sqrt(ev)
        J = det(F3)
        lb = ls * np.cbrt(J)[..., None] ** -1  # isochoric stretches
        K = lam + 2.0 * mu / 3.0
        JU1 = K * (J - 1.0) * J  # J U'(J)
        JU2 = JU1 + K * J * J  # J U' + J^2 U''
        beta = np.zeros(ls.shape)
        gamma = np.zeros(ls.shape + (3,))
        third = np.eye(3) - 1.0 / 3.0
        for m, a in zip(self.mu, self.alpha):
            la = lb**a
            s = la.sum(axis=-1, keepdims=True)
            beta += m * (la - s / 3.0)
            gamma += m * a * (la[..., :, None] * third - la[..., None, :] / 3.0 + s[..., None] / 9.0)
        beta += JU1[..., None]
        gamma += JU2[..., None, None]
        return ev, N, beta, gamma

    def energy(self, F, lam, mu):
        F3 = _embed(F)
        C = np.swapaxes(F3, -1, -2) @ F3
        ls = np.sqrt(np.linalg.eigvalsh(C))
        J = det(F3)
        lb = ls / np.cbrt(J)[..., None]
        W = sum(m / a * ((lb**a).sum(axis=-1) - 3.0) for m, a in zip(self.mu, self.alpha))
        return W + 0.5 * (lam + 2.0 * mu / 3.0) * (J - 1.0) ** 2

    def _stress3(self, F3, lam, mu):
        ev, N, beta, _ = self._principal(F3, lam, mu)
        S = np.einsum("...Ia,...a,...Ja->...IJ", N, beta / ev, N)
        return F3 @ S

    def stress(self, F, lam, mu):
        d = F.shape[-1]
        return self._stress3(_embed(F), lam, mu)[..., :d, :d].copy()

    def stress_zz(self, F, lam, mu):
        if F.shape[-1] != 2:
            raise InputError("stress_zz is the plane-strain out-of-plane stress; F must be 2x2.")
        return self._stress3(_embed(F), lam, mu)[..., 2, 2].copy()

    def tangent(self, F, lam, mu):
        d = F.shape[-1]
        F3 = _embed(F)
        ev, N, beta, gamma = self._principal(F3, lam, mu)
        Sa = beta / ev
        M = (gamma - 2.0 * np.eye(3) * beta[..., None]) / (ev[..., :, None] * ev[..., None, :])
        # H_ab = (S_b - S_a) / (C_b - C_a), a != b; its limit for equal eigenvalues (l'Hopital, Holzapfel 6.197)
        dS = Sa[..., None, :] - Sa[..., :, None]
        dC = ev[..., None, :] - ev[..., :, None]
        Md = np.diagonal(M, axis1=-2, axis2=-1)
        limit = 0.25 * (Md[..., :, None] + Md[..., None, :] - M - np.swapaxes(M, -1, -2))
        close = np.abs(dC) <= 1e-6 * np.abs(ev).max(axis=-1)[..., None, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            H = np.where(close, limit, dS / np.where(close, 1.0, dC))
        H = H * (1.0 - np.eye(3))
        NN = np.einsum("...Ia,...Ja->...aIJ", N, N)
        X = np.einsum("...Ia,...Jb->...abIJ", N, N)
        CC = np.einsum("...ab,...aIJ,...bKL->...IJKL", M, NN, NN, optimize=True)
        CC += np.einsum("...ab,...abIJ,...abKL->...IJKL", H, X, X + np.swapaxes(X, -3, -4), optimize=True)
        S = np.einsum("...Ia,...a,...Ja->...IJ", N, Sa, N)
        A = np.einsum("ik,...JL->...iJkL", np.eye(3), S)
        A = A + np.einsum("...iI,...IJKL,...kK->...iJkL", F3, CC, F3, optimize=True)
        return A[..., :d, :d, :d, :d].copy()


class EnergyExpression(InvariantLaw):
    r"""A user law given as a strain-energy expression of the invariants.

    Parameters
    ----------
    text : str
        The energy, e.g. ``"c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2"``: numbers,
        the parameter names, the invariants ``I1, I2, I3, J, I1b, I2b``, ``+ - * / **``,
        unary minus and ``log``, ``exp``, ``sqrt`` (:func:`~alcontact.fem._energy_expression.parse_energy`).
    parameters : dict of str to float
        Values of the names used in ``text``.
    key : str
        Where the text came from, for messages (``material.energy`` in a problem file).

    Notes
    -----
    The expression is the whole energy, volumetric part included (the material's
    :math:`\lambda, \mu` are not used). At load it must be stress free at :math:`F = I`
    and have positive initial shear and bulk moduli :math:`\mu_0, K_0` read from its
    tangent; :meth:`fixed_moduli` returns them, and a problem file may omit ``E`` and
    ``nu`` (they follow from :math:`\mu_0, K_0`).

    Examples
    --------
    >>> law = EnergyExpression("c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2", {"c10": 0.4, "c01": 0.1, "K": 50.0})
    >>> tuple(round(m, 10) for m in law.fixed_moduli())
    (1.0, 50.0)
    """

    name = "energy-expression"

    def __init__(self, text: str, parameters: dict[str, float] | None = None, *, key: str = "energy",
                 params_key: str = "parameters"):
        from alcontact.fem._energy_expression import parse_energy

        if parameters is not None and not isinstance(parameters, Mapping):
            raise InputError(f"{params_key} = {parameters!r} ({type(parameters).__name__}): expected a dict of "
                             "parameter names to numbers, e.g. {'c10': 0.4, 'K': 50.0}.")
        self.text = text
        self.parameters = dict(parameters or {})
        self._expr = parse_energy(text, self.parameters, key=key, params_key=params_key)
        lam0, mu0 = self.reference_moduli(0.0, 0.0)
        K0 = lam0 + 2.0 * mu0 / 3.0
        P0 = self.stress(np.eye(3)[None], 0.0, 0.0)[0]
        scale = max(abs(mu0), abs(K0), 1e-300)
        if not np.all(np.isfinite(P0)) or np.abs(P0).max() > 1e-10 * scale:
            raise InputError(f"{key} = {text!r}: the energy is not stress free at F = I (P = {P0[0, 0]:.6g} I); "
                             "a reference state needs dW/dF = 0 there. Write it in the isochoric invariants I1b, "
                             "I2b with a volumetric term of J that is flat at J = 1, e.g. K/2*(J-1)**2.")
        if not (math.isfinite(mu0) and mu0 > 0 and math.isfinite(K0) and K0 > 1e-9 * mu0):  # K0 = 0 up to round-off
            raise InputError(f"{key} = {text!r}: initial shear modulus mu0 = {mu0:g} and bulk modulus K0 = {K0:g} "
                             "(from the tangent at F = I) must both be > 0 for a stable solid; check the signs "
                             "of the parameters and include a volumetric term such as K/2*(J-1)**2.")
        self._moduli = (float(mu0), float(K0))

    def fixed_moduli(self):
        return self._moduli

    def parameter_values(self) -> dict[str, float]:
        return {n: float(v) for n, v in sorted(self.parameters.items())}

    def _cache_key(self) -> Any:
        return ("energy-expression", self.text, tuple(sorted(self.parameters)))

    def energy_expression(self, I1, I2, J, lam, mu, p):
        from alcontact.fem._energy_expression import SYMBOLS

        s = SYMBOLS(self.parameters)
        subs = {s["I1"]: I1, s["I2"]: I2, s["J"]: J, **{s[n]: p[n] for n in self.parameters}}
        return self._expr.subs(subs, simultaneous=True)

    def __repr__(self) -> str:
        return f"EnergyExpression({self.text!r}, {self.parameters!r})"


for _law in (MooneyRivlin, Yeoh, Gent, ArrudaBoyce, Ogden):
    register_material(_law.name, _law, overwrite=True)
