"""Isotropic linear elastic material."""

from __future__ import annotations

import math
from dataclasses import dataclass

from alcontact.errors import InputError

__all__ = ["Material"]

_PLANES = ("strain", "stress")


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
        try:
            E = float(self.E)
            nu = float(self.nu)
        except (TypeError, ValueError) as exc:
            raise InputError(
                f"material constants must be numbers; got E={self.E!r}, nu={self.nu!r}."
            ) from exc
        if not (math.isfinite(E) and E > 0.0):
            raise InputError(f"Young's modulus E={self.E!r} is out of range; it must be finite and > 0.")
        if not (math.isfinite(nu) and -1.0 < nu < 0.5):
            raise InputError(
                f"Poisson's ratio nu={self.nu!r} is out of range; it must satisfy -1 < nu < 0.5 "
                "(nu = 0.5, incompressible, is not supported: use nu <= 0.49 for a nearly "
                "incompressible solid such as rubber)."
            )
        if self.plane not in _PLANES:
            raise InputError(f"plane={self.plane!r} is not allowed; use one of {', '.join(map(repr, _PLANES))}.")
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "nu", nu)

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
