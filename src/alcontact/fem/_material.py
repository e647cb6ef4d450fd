"""Isotropic linear elastic material."""

from __future__ import annotations

import math
from dataclasses import dataclass

from alcontact._options import VALUE_RANGE, is_real, show
from alcontact.errors import InputError

__all__ = ["Material", "material_issues"]

_PLANES = ("strain", "stress")


def _as_float(x):
    """A real number as a float (a huge int becomes inf); anything else unchanged."""
    if not is_real(x):
        return x
    try:
        return float(x)
    except OverflowError:
        return math.inf if x > 0 else -math.inf


def material_issues(E, nu, plane: str = "strain") -> list[tuple[str, str]]:
    """What is wrong with the constants of a :class:`Material`, as ``(key, message)`` pairs.

    ``message`` starts with ``"= value: "`` and says the allowed range and the
    fix; the caller prefixes the key (``Material E`` in Python, ``material.E`` in
    a problem file). Young's modulus must lie in :data:`~alcontact._options.VALUE_RANGE`
    (the magnitudes double precision carries through the stiffness and its squares),
    Poisson's ratio in ``(-1, 0.5)``.

    Examples
    --------
    >>> material_issues(1e3, 0.3)
    []
    >>> material_issues(1e308, 0.3)[0][1][:40]
    '= 1e+308: outside 1e-100 .. 1e+100, wher'
    """
    lo, hi = VALUE_RANGE
    out = []
    E0, nu0 = E, nu
    E, nu = _as_float(E), _as_float(nu)
    if not is_real(E):
        hint = " Pass a number, not a string." if isinstance(E, str) else ""
        out.append(("E", f"= {show(E)}: expected a number in [{lo:g}, {hi:g}] (Young's modulus, stress units, e.g. "
                         f"MPa), got {type(E).__name__}; material constants must be numbers.{hint}"))
    elif not (math.isfinite(E) and E > 0):
        out.append(("E", f"= {show(E0)}: out of range; Young's modulus must be finite and > 0 (in [{lo:g}, {hi:g}]), "
                         "e.g. E=210e3 (steel in MPa)."))
    elif not lo <= E <= hi:
        out.append(("E", f"= {float(E):g}: outside {lo:g} .. {hi:g}, where the solver's double precision stays "
                         "finite (stiffness entries scale with E and the solver squares them: E = 1e308 overflows "
                         "to infinity, E = 1e-300 underflows). Express E in other units, e.g. MPa or GPa instead "
                         "of Pa (and the loads alike)."))
    if not is_real(nu):
        hint = " Pass a number, not a string." if isinstance(nu, str) else ""
        out.append(("nu", f"= {show(nu)}: expected a number in (-1, 0.5) (Poisson's ratio), got "
                          f"{type(nu).__name__}; material constants must be numbers.{hint}"))
    elif not (math.isfinite(nu) and -1.0 < nu < 0.5):
        out.append(("nu", f"= {show(nu0)}: out of range; Poisson's ratio must satisfy -1 < nu < 0.5 (nu = 0.5, "
                          "incompressible, is not supported for a compressible law: use nu <= 0.49 (e.g. nu=0.49) "
                          "for a nearly incompressible solid such as rubber)."))
    if not isinstance(plane, str) or plane not in _PLANES:
        out.append(("plane", f"= {show(plane)}: not allowed; use one of {', '.join(map(repr, _PLANES))} (the 2D "
                             "assumption; ignored in 3D)."))
    return out


@dataclass(frozen=True)
class Material:
    r"""Isotropic linear elastic material.

    Parameters
    ----------
    E : float
        Young's modulus, finite and ``> 0``.
    nu : float
        Poisson's ratio, ``-1 < nu < 0.5``.
    plane : {"strain", "stress"}
        2D assumption (ignored in 3D).

    Examples
    --------
    >>> mat = Material(E=1.0e3, nu=0.25)
    >>> lam, mu = mat.lame(2)
    >>> round(lam, 6), round(mu, 6)
    (400.0, 400.0)
    >>> round(mat.plane_strain_modulus, 6)
    1066.666667
    """

    E: float
    nu: float
    plane: str = "strain"

    def __post_init__(self) -> None:
        issues = material_issues(self.E, self.nu, self.plane)
        if issues:
            raise InputError(" ".join(f"Material {key}={msg[2:]}" for key, msg in issues))  # "E=0.0: ..."
        object.__setattr__(self, "E", float(self.E))
        object.__setattr__(self, "nu", float(self.nu))

    def lame(self, dim: int) -> tuple[float, float]:
        r"""Lamé constants :math:`(\lambda, \mu)` for a ``dim``-dimensional model.

        .. math::
            \lambda = \frac{E\nu}{(1+\nu)(1-2\nu)}, \quad \mu = \frac{E}{2(1+\nu)},

        and in 2D plane stress :math:`\lambda^* = 2\lambda\mu/(\lambda + 2\mu) = E\nu/(1-\nu^2)`.
        """
        if dim not in (1, 2, 3):
            raise InputError(f"dim={dim!r} must be 1, 2 or 3.")
        E, nu = self.E, self.nu
        mu = E / (2.0 * (1.0 + nu))
        if dim == 2 and self.plane == "stress":
            return E * nu / (1.0 - nu * nu), mu
        return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu

    @property
    def plane_strain_modulus(self) -> float:
        r"""Plane-strain modulus :math:`E^* = E / (1 - \nu^2)` (used by Hertz theory)."""
        return self.E / (1.0 - self.nu**2)

    @property
    def shear_modulus(self) -> float:
        r""":math:`\mu = E / (2(1+\nu))`."""
        return self.E / (2.0 * (1.0 + self.nu))
