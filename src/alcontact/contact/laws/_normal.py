r"""Normal contact laws: traction as a function of the gap for a given multiplier.

Every law of chapter 6 is written with one penalty object ``p`` of
:mod:`alcontact.penalties` and a per-point scale :math:`\eta_i` (a length):

.. math::

    t_N(g) = p'(g/\eta, \lambda), \qquad
    \psi(g) = \eta\, p(g/\eta, \lambda), \qquad
    \lambda \leftarrow p'(g/\eta, \lambda),

the traction (6.66, corrected: the force is the derivative of the penalty energy),
the energy per unit area and the multiplier update of Algorithm 6.3.

Scaling (see SEED_NOTES, "Scaling remark"): the argument of ``p`` must be
dimensionless, while the user thinks in a penalty stiffness :math:`\varepsilon_N`
(pressure per length, of order E/h). We choose :math:`\eta` so that the
tangent stiffness of the traction law at zero gap equals :math:`\varepsilon_N`:

.. math::

    \frac{dt_N}{dg}\Big|_{g=0} = \frac{p''(0, \lambda_{ref})}{\eta} = \varepsilon_N
    \quad\Longrightarrow\quad \eta = p''(0, \lambda_{ref}) / \varepsilon_N .

For Rockafellar's penalty :math:`p'' = 1`, :math:`\eta = 1/\varepsilon_N` and the law is
exactly Simo & Laursen's :math:`t_N = \langle \lambda + \varepsilon_N g\rangle` (6.13),
so Algorithm 6.1 is Algorithm 6.3 with ``rockafellar``. For MET 1 (``p'' = \lambda\theta''``)
and MET 2 (``p'' = \lambda^2\theta''``) the scale depends on the reference multiplier:
``eta_scaling="fixed"`` computes it once from the initial multipliers (the
dissertation's fixed :math:`\varepsilon_N`); ``"adaptive"`` recomputes it from the
current multipliers at every outer iteration, which keeps the stiffness at
:math:`\varepsilon_N` (then MET 1 and MET 2 give the same law).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import penalties as _pen


def freezes_at_zero(penalty) -> bool:
    """Whether a zero multiplier stays zero (``p'(y, 0) = 0``), as for MET 1 / MET 2.

    Such penalties need strictly positive multipliers (a floor); Rockafellar's does not.
    Read from the penalty's declared facts (:func:`alcontact.penalties.facts`).
    """
    return _pen.facts(penalty).freezes_at_zero


def eta_for_stiffness(penalty, lam_ref: np.ndarray, eps: float) -> np.ndarray:
    """Scale :math:`\\eta = p''(0, \\lambda_{ref}) / \\varepsilon_N` per point (see module doc)."""
    lam_ref = np.asarray(lam_ref, dtype=float)
    curv = np.asarray(penalty.second_derivative(np.zeros_like(lam_ref), lam_ref), dtype=float)
    # at a kink (Rockafellar's with lambda = 0) take the right limit: the active branch
    kink = ~(curv > 0)
    if np.any(kink):
        right = np.asarray(penalty.second_derivative(np.full(lam_ref.shape, 1e-9), lam_ref), dtype=float)
        curv = np.where(kink, right, curv)
    bad = ~np.isfinite(curv) | (curv <= 0)
    if np.any(bad):
        curv = np.where(bad, np.nanmax(np.where(bad, np.nan, curv)) if np.any(~bad) else 1.0, curv)
    return curv / eps


@dataclass(frozen=True)
class NormalLaw:
    """Traction law ``t_N(g) = p'(g/eta, lam)`` at the contact points (vectorized)."""

    penalty: object
    eta: np.ndarray

    def traction(self, g: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """Contact pressure :math:`t_N = p'(g/\\eta, \\lambda)` (>= 0 for family P)."""
        return np.asarray(self.penalty.derivative(g / self.eta, lam), dtype=float)

    def stiffness(self, g: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """:math:`dt_N/dg = p''(g/\\eta, \\lambda)/\\eta`."""
        return np.asarray(self.penalty.second_derivative(g / self.eta, lam), dtype=float) / self.eta

    def energy(self, g: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """Energy per unit area :math:`\\eta\\,p(g/\\eta, \\lambda)` (+inf outside the domain)."""
        return self.eta * np.asarray(self.penalty.value(g / self.eta, lam), dtype=float)

    def gap_bound(self, lam: np.ndarray) -> np.ndarray:
        """Largest admissible gap :math:`\\eta\\, b(\\lambda)` (inf for unbounded penalties)."""
        return self.eta * np.asarray(self.penalty.domain_upper(lam), dtype=float)


def make_law(penalty, eta) -> NormalLaw:
    """The normal law of ``penalty``, with Matioli's safeguard when its facts ask for one.

    A penalty declaring ``needs_multiplier_safeguard`` (Matioli's quadratic (5.27):
    ``p'`` turns negative, i.e. tension) is replaced by
    :func:`alcontact.penalties.safeguarded` -- the same implementation the
    optimization engine uses -- so the traction is :math:`\\max(0, p')` and the
    multipliers stay non-negative.
    """
    return NormalLaw(_pen.safeguarded(penalty), np.asarray(eta, dtype=float))
