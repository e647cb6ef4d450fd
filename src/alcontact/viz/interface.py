"""The pressure along the interface of two bodies, on both sides (``interface_pressure.png``).

The slave side is the pressure the solve applied at the slave nodes; the master side is the
same nodal forces carried to the master nodes by the mortar weights, per master tributary
length (:mod:`alcontact.contact.solution._sides`, in ``solution.extra["master_side"]``). On
matching meshes and a flat interface both are the same field; on non-matching meshes they are
two discretizations of one pressure, with the same resultant.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .plots import Units, _new_figure, _note_units, _units, save_figure


def interface_pressure_figure(solution, *, axis: int = 0, units: Units | None = None, title: str | None = None):
    """Slave-side and master-side contact pressure against coordinate ``axis`` of the interface points.

    ``solution.extra["master_side"]`` (a pair between two bodies, small deformation) gives the
    master side; without it only the slave side is drawn.
    """
    u = _units(units)
    fig = _new_figure()
    ax = fig.add_subplot(1, 1, 1)
    pts = np.asarray(solution.points, dtype=float)
    order = np.argsort(pts[:, axis])
    ax.plot(pts[order, axis], np.asarray(solution.pressure)[order], "o-", ms=3, label="slave side (solved)")
    side = (solution.extra or {}).get("master_side")
    if side is not None:
        mp = np.asarray(side["points"], dtype=float)
        p = np.asarray(side["pressure"], dtype=float)
        seen = np.isfinite(np.asarray(side["gap"], dtype=float))
        o = np.argsort(mp[:, axis])
        o = o[seen[o]]
        ax.plot(mp[o, axis], p[o], "s--", ms=3, label=f"master side ({side['boundary']}, mortar weights)")
    loaded = np.asarray(solution.pressure) > 0
    if np.any(loaded):
        hi = float(pts[loaded, axis].max())
        lo = float(pts[loaded, axis].min())
        span = max(hi - lo, 1e-300)
        ax.set_xlim(lo - 0.5 * span, hi + 0.5 * span)
    ax.set_xlabel(f"{'xyz'[axis]} ({u.length})")
    ax.set_ylabel(f"contact pressure ({u.pressure})")
    ax.set_title(title or "contact pressure along the interface, both sides")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    _note_units(fig, u)
    return fig


def save_interface_pressure_plot(solution, path: str | os.PathLike, **kwargs) -> Path:
    """:func:`interface_pressure_figure` saved as PNG at ``path``."""
    return save_figure(interface_pressure_figure(solution, **kwargs), path)
