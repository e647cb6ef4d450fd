r"""Local frictional contact law: normal traction plus the Coulomb return mapping.

For one load step :math:`n \to n+1` and multipliers :math:`(\lambda_N, \lambda_T)`,
at every candidate point

.. math::

    t_N &= t_N(g; \lambda_N) \quad (\langle\lambda_N + \varepsilon_N g\rangle \text{ (6.52) or }
           p'(g/\eta, \lambda_N) \text{ (Alg. 6.4)}),\\
    z &= \lambda_T + \varepsilon_T (u_T - u_{T,n}) \quad\text{(trial, (6.47) in AL form)},\\
    t_T &= \operatorname{proj}_{\{|t|\le \mu t_N\}}(z)
        = z - \varepsilon_T\Delta\xi\, \frac{z}{|z|}, \quad
        \Delta\xi = \frac{\langle |z| - \mu t_N\rangle}{\varepsilon_T}
        \quad\text{((6.48)-(6.50), corrected (6.49))}.

:math:`\lambda_T = t_{T,n} + \Delta\lambda_T` is the total tangential multiplier of
(6.2c). Three cases, never dividing by a zero norm: *open* (:math:`\mu t_N \le 0`):
:math:`t_T = 0`; *stick* (:math:`|z| \le \mu t_N`): :math:`t_T = z`; *slip*
(:math:`|z| > \mu t_N > 0`, so :math:`|z| > 0`): :math:`t_T = \mu t_N z/|z|`.

Consistent tangent (derivatives with respect to :math:`y = (g, u_T)` and to the
multipliers), with :math:`n = z/|z|`:

- stick: :math:`\partial t_T/\partial u_T = \varepsilon_T I`;
- slip: :math:`\partial t_T/\partial u_T = \varepsilon_T \frac{\mu t_N}{|z|}(I - n n^T)`,
  :math:`\partial t_T/\partial g = \mu\, \frac{dt_N}{dg}\, n` (coupling to the normal
  traction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError


OPEN, STICK, SLIP = 0, 1, 2


@dataclass(frozen=True)
class Macaulay:
    """:math:`t_N = \\max(0, \\lambda_N + c\\, g)` with both partial derivatives (for the SSN reference)."""

    c: float

    def traction(self, g, lam):
        return np.maximum(0.0, lam + self.c * g)

    def stiffness(self, g, lam):
        return np.where(lam + self.c * g > 0, self.c, 0.0)

    def dlam(self, g, lam):
        return np.where(lam + self.c * g > 0, 1.0, 0.0)


#: radii of the Coulomb disc: ``"traction"`` :math:`\\mu t_N` (coupled to the normal law), ``"multiplier"``
#: :math:`\\mu\\langle\\lambda_N\\rangle` (fixed within a subproblem)
RADII = ("traction", "multiplier")


@dataclass(frozen=True)
class CoulombLaw:
    r"""Coulomb's law as a return mapping (6.47)-(6.50): the tangential part of a contact law.

    Parameters
    ----------
    mu : float
        Friction coefficient :math:`\mu \ge 0`.
    eps_t : float
        Tangential penalty :math:`\varepsilon_T` of the trial traction
        :math:`z = \lambda_T + \varepsilon_T \Delta u_T` (module doc).
    radius : {"traction", "multiplier"}
        Radius of the disc the trial traction is projected on: :math:`\mu t_N` (coupled to
        the normal traction: the slip tangent has the :math:`\partial t_T/\partial g` term of the
        module doc) or :math:`\mu\langle\lambda_N\rangle` (fixed within a subproblem of Algorithm 6.2).

    Examples
    --------
    >>> law = CoulombLaw(mu=0.5, eps_t=100.0)
    >>> law.disc_radius(tN=np.array([2.0, 0.0]), lamN=np.array([1.0, 1.0]))
    array([1., 0.])
    >>> law.with_radius("multiplier").disc_radius(tN=np.array([2.0, 0.0]), lamN=np.array([1.0, -1.0]))
    array([0.5, 0. ])
    """

    mu: float
    eps_t: float
    radius: str = "traction"

    def __post_init__(self):
        if self.radius not in RADII:
            raise InputError(f"radius = {self.radius!r:.40}: the Coulomb disc radius is one of {', '.join(RADII)} "
                             "(option radius).")
        object.__setattr__(self, "mu", float(self.mu))
        object.__setattr__(self, "eps_t", float(self.eps_t))

    @property
    def coupled(self) -> bool:
        """Whether the disc radius is :math:`\\mu t_N` (it moves with the normal traction)."""
        return self.radius == "traction"

    def disc_radius(self, tN: np.ndarray, lamN: np.ndarray) -> np.ndarray:
        """Radius :math:`\\rho` of the Coulomb disc per point: :math:`\\mu t_N` or :math:`\\mu\\langle\\lambda_N\\rangle`."""
        return self.mu * (tN if self.coupled else np.maximum(lamN, 0.0))

    def with_radius(self, radius: str, eps_t: float | None = None) -> "CoulombLaw":
        """The same law with another disc ``radius`` (and tangential penalty ``eps_t``)."""
        return CoulombLaw(self.mu, self.eps_t if eps_t is None else eps_t, radius)


def return_mapping(z: np.ndarray, rho: np.ndarray):
    r"""Return mapping (6.47)-(6.50), corrected (6.49), of trial tractions onto the Coulomb discs.

    :math:`t_T = z` where :math:`|z| \le \rho` (stick), else :math:`\rho\, z/|z|` (slip);
    a point with :math:`\rho \le 0` is open (:math:`t_T = 0`).

    Parameters
    ----------
    z : ndarray (c, k)
        Trial tangential tractions (``k`` tangent components, or ambient vectors in the
        tangent plane at finite deformation).
    rho : ndarray (c,)
        Disc radii (:math:`\mu \lambda_N` or :math:`\mu t_N`).

    Returns
    -------
    tT : ndarray (c, k)
    opened, stick, slip : ndarray (c,) of bool
    n : ndarray (c, k)
        Unit trial direction at slipping points (``z`` elsewhere).
    dproj : ndarray (c, k, k)
        :math:`\partial t_T/\partial z` at fixed radius: identity at stick points,
        :math:`(\rho/|z|)(I - n n^T)` at slip points, zero at open points.
    """
    nz = np.linalg.norm(z, axis=1)
    opened = ~(rho > 0)
    stick = ~opened & (nz <= rho)
    slip = ~opened & ~stick
    safe = np.where(slip, nz, 1.0)
    n = z / safe[:, None]
    tT = np.where(stick[:, None], z, 0.0) + np.where(slip[:, None], rho[:, None] * n, 0.0)
    eye = np.eye(z.shape[1])[None]
    proj = (rho / safe)[:, None, None] * (eye - n[:, :, None] * n[:, None, :])
    dproj = np.where(stick[:, None, None], eye, 0.0) + np.where(slip[:, None, None], proj, 0.0)
    return tT, opened, stick, slip, n, dproj


def local_law(normal, lamN, lamT, y, uTn, eps_t, mu, *, with_lam=False, rho=None, tfree=None, drho=None):
    """Tractions ``t`` (c, d) and their derivatives at all candidate points.

    Parameters
    ----------
    normal : object with ``traction(g, lam)``, ``stiffness(g, lam)`` (and ``dlam`` if ``with_lam``)
    lamN : (c,), lamT : (c, d-1)
        Multipliers.
    y : (c, d)
        Local kinematics, column 0 the gap, then :math:`u_T`.
    uTn : (c, d-1)
        Tangential displacement at the previous step.
    eps_t : float
    mu : float or (c,)
        Coulomb coefficient (one per point when the contact pairs have their own).
    rho : (c,), optional
        Fixed radius of the Coulomb disc (e.g. :math:`\\mu\\lambda_N`); default
        :math:`\\mu t_N(g)`, coupled to the normal traction.
    tfree : (c, d-1) bool, optional
        Tangent directions in which the point can move (default all). A held
        direction (supported DOF) carries no contact traction: its friction force
        is part of the support reaction, and the Coulomb disc acts on the free
        directions (:mod:`alcontact.contact.systems._condensed`).
    drho : (c,), optional
        :math:`\\partial\\rho/\\partial\\lambda_N` of a fixed radius (e.g. :math:`\\mu` for
        :math:`\\rho = \\mu\\lambda_N`); enters ``Dl`` at slip points (default 0).

    Returns
    -------
    t : (c, d)
        ``(t_N, t_T)``.
    Dy : (c, d, d)
        :math:`\\partial t/\\partial y`.
    Dl : (c, d, d) or None
        :math:`\\partial t/\\partial(\\lambda_N, \\lambda_T)` when ``with_lam``.
    state : (c,) int
        OPEN / STICK / SLIP of the return mapping.
    """
    c, d = y.shape
    g, uT = y[:, 0], y[:, 1:]
    tN = np.asarray(normal.traction(g, lamN), dtype=float)
    kN = np.asarray(normal.stiffness(g, lamN), dtype=float)
    z = _trial(lamT, uT, uTn, eps_t, tfree)
    coupled = rho is None
    rho = mu * tN if coupled else np.asarray(rho, dtype=float)
    tT, opened, stick, slip, nvec, dz = return_mapping(z, rho)
    t = np.concatenate([tN[:, None], tT], axis=1)
    if tfree is not None:
        mask = np.asarray(tfree, dtype=float)
        dz = dz * mask[:, :, None] * mask[:, None, :]
    Dy = np.zeros((c, d, d))
    Dy[:, 0, 0] = kN
    Dy[:, 1:, 1:] = eps_t * dz
    if coupled:
        Dy[:, 1:, 0] = np.where(slip[:, None], (mu * kN)[:, None] * nvec, 0.0)
    Dl = None
    if with_lam:
        kl = np.asarray(normal.dlam(g, lamN), dtype=float)
        Dl = np.zeros((c, d, d))
        Dl[:, 0, 0] = kl
        Dl[:, 1:, 1:] = dz
        if coupled:
            Dl[:, 1:, 0] = np.where(slip[:, None], (mu * kl)[:, None] * nvec, 0.0)
        elif drho is not None:
            Dl[:, 1:, 0] = np.where(slip[:, None], np.asarray(drho, dtype=float)[:, None] * nvec, 0.0)
    state = np.where(opened, OPEN, np.where(stick, STICK, SLIP))
    return t, Dy, Dl, state


def _trial(lamT, uT, uTn, eps_t, tfree):
    """Trial traction :math:`z = \\lambda_T + \\varepsilon_T (u_T - u_{T,n})`, zero in held directions."""
    z = lamT + eps_t * (uT - uTn)
    return z if tfree is None else np.where(tfree, z, 0.0)


def tangential_energy(lamT, uT, uTn, eps_t, rho, tfree=None):
    """Convex potential of the return mapping onto a *fixed* disc of radius ``rho``.

    :math:`\\phi_T = |z|^2/(2\\varepsilon_T)` for :math:`|z| \\le \\rho`, else
    :math:`(\\rho|z| - \\rho^2/2)/\\varepsilon_T`, with :math:`z = \\lambda_T + \\varepsilon_T(u_T - u_{T,n})`;
    its gradient in :math:`u_T` is the projected traction (``tfree`` as in :func:`local_law`).
    """
    z = _trial(lamT, uT, uTn, eps_t, tfree)
    nz = np.linalg.norm(z, axis=1)
    rho = np.maximum(np.asarray(rho, dtype=float), 0.0)
    return np.where(nz <= rho, 0.5 * nz * nz, rho * nz - 0.5 * rho * rho) / eps_t


def block_diag(D: np.ndarray) -> np.ndarray:
    """Dense block-diagonal matrix from ``(c, d, d)`` blocks (point-major ordering)."""
    c, d, _ = D.shape
    out = np.zeros((c * d, c * d))
    for k in range(d):
        for l in range(d):
            out[np.arange(c) * d + k, np.arange(c) * d + l] = D[:, k, l]
    return out
