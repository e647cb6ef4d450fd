"""Figures of a contact solution: pressure profile and convergence history.

Built on :class:`matplotlib.figure.Figure` with the Agg renderer, without
``pyplot``: no global backend is switched, no window opens, and the module
works on machines without a display. matplotlib is imported when a figure is
made, not when :mod:`alcontact` is imported.

Examples
--------
>>> from alcontact.problems import hertz                      # doctest: +SKIP
>>> from alcontact.contact import solve                       # doctest: +SKIP
>>> sol = solve(hertz.hertz_2d(level=0))                      # doctest: +SKIP
>>> save_pressure_plot(sol, "pressure.png")                   # doctest: +SKIP
"""

from __future__ import annotations

import logging
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..io.results import atomic_path

__all__ = [
    "Units",
    "contact_coordinate",
    "loaded_half_width",
    "contact_center",
    "contact_half_width",
    "edge_search_applies",
    "pressure_figure",
    "convergence_figure",
    "save_figure",
    "save_pressure_plot",
    "save_convergence_plot",
    "steps_figure",
    "reaction_force_figure",
    "load_displacement_figure",
    "load_path_phases",
    "force_path_figure",
]

logger = logging.getLogger(__name__)

_HISTORY_SERIES = (
    ("penetration", r"penetration $\max g^+/h$"),
    ("complementarity", r"complementarity $\max|\lambda g|/(p_{ref}h)$"),
    ("multiplier_change", r"multiplier change $\|\Delta\lambda\|_\infty/p_{ref}$"),
)


@dataclass(frozen=True)
class Units:
    """Units of a problem for axis labels: a length and a stress unit, force derived.

    ``None`` stands for "whatever consistent unit the problem uses" (a problem file
    without ``[units]``): labels then use the symbols ``L`` (length unit of the mesh)
    and ``[E]`` (stress unit of Young's modulus), explained by :attr:`note` in the
    figure. The force unit is ``force_unit`` when given, else the named unit equal to
    stress x length^2 (:func:`alcontact._options.derived_force_unit`), else the product.

    Examples
    --------
    >>> Units("mm", "MPa").force(2), Units("mm", "MPa").force(3), Units("mm", "GPa").force(3)
    ('N/mm', 'N', 'kN')
    >>> Units().pressure, Units().force(3)
    ('[E]', '[E]·L²')
    """

    length_unit: str | None = None
    stress_unit: str | None = None
    force_unit: str | None = None

    @property
    def length(self) -> str:
        """Length unit (of the mesh coordinates)."""
        return self.length_unit or "L"

    @property
    def pressure(self) -> str:
        """Stress unit (of Young's modulus E)."""
        return self.stress_unit or "[E]"

    @property
    def named(self) -> bool:
        """Both units are named (a ``[units]`` table or a built-in problem)."""
        return bool(self.length_unit and self.stress_unit)

    @property
    def note(self) -> str:
        """What the generic symbols mean (empty when both units are named)."""
        if self.named:
            return ""
        return "units: L = length unit of the mesh, [E] = stress unit of Young's modulus E"

    def force(self, dim: int) -> str:
        """Force unit of a contact force: per unit thickness in 2D (plane strain/stress)."""
        from .._options import derived_force_unit

        f = self.force_unit or derived_force_unit(self.length_unit, self.stress_unit)
        if f:
            return f"{f}/{self.length}" if dim == 2 else f
        return f"{self.pressure}·{self.length}" + ("" if dim == 2 else "²")

    def as_dict(self, dim: int) -> dict[str, str | None]:
        """``summary.json``'s ``units``: the labels used (``None`` where unnamed)."""
        return {"length": self.length_unit, "stress": self.stress_unit,
                "force": self.force(dim) if self.named else None}


def _units(units) -> Units:
    return units if isinstance(units, Units) else Units()


def _note_units(fig, u: Units) -> None:
    if u.note:
        fig.supxlabel(u.note, fontsize="x-small", color="0.3")


def _new_figure(size=(6.4, 4.2)):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _pad(center, d: int) -> np.ndarray:
    c = np.zeros(d) if center is None else np.asarray(center, dtype=float).ravel()
    return np.concatenate([c, np.zeros(d - c.size)]) if c.size < d else c[:d]


def _body_normals(solution, points: np.ndarray) -> np.ndarray | None:
    """Outward unit normals of the body's contact boundary at ``points`` (``None`` without a mesh).

    Facet normals (oriented away from the facet's element) summed at the vertices with the
    facet size as weight; each point takes the normal of its nearest boundary vertex (the
    edge midpoints of P2 included).
    """
    problem = getattr(solution, "problem", None)
    model = getattr(problem, "model", None)
    name = getattr(problem, "contact_boundary", None)
    mesh = getattr(model, "mesh", None)
    if mesh is None or name is None or not hasattr(model, "facets"):
        return None
    try:
        f = np.asarray(model.facets(name), dtype=np.int64)
        P = np.asarray(mesh.p, dtype=float)
        nodes = np.asarray(mesh.facets)[:, f]
        elem = np.asarray(mesh.f2t)[0, f]
        centroid = P[:, np.asarray(mesh.t)[:, elem]].mean(axis=1)
    except (AttributeError, KeyError, IndexError, TypeError, ValueError):
        return None
    d = P.shape[0]
    if f.size == 0 or d != points.shape[1] or d not in (2, 3):
        return None
    a = P[:, nodes[1]] - P[:, nodes[0]]
    if d == 2:
        nrm = np.vstack([a[1], -a[0]])
    else:
        nrm = np.cross(a.T, (P[:, nodes[2]] - P[:, nodes[0]]).T).T
    nrm *= np.where(np.sum(nrm * (P[:, nodes].mean(axis=1) - centroid), axis=0) < 0, -1.0, 1.0)
    acc = np.zeros((P.shape[1], d))
    for k in range(nodes.shape[0]):
        np.add.at(acc, nodes[k], nrm.T)
    verts = np.unique(nodes)
    from scipy.spatial import cKDTree

    _, nearest = cKDTree(P[:, verts].T).query(points)
    nu = acc[verts[nearest]]
    return nu / np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)


def contact_coordinate(solution, axis: int = 0, center=None) -> tuple[np.ndarray, str]:
    r"""Abscissa of the contact points for a profile plot, monotone along the contact boundary.

    The approach direction :math:`n` is the pressure-weighted mean normal at the loaded
    points (all points when none is loaded), of the obstacle or of the body's contact
    boundary, whichever varies less over them (a plane obstacle, a flat face), so
    that a curved contact boundary (ball, O-ring, a Gmsh body) is measured in the
    plane the obstacle presses on rather than along the direction of least extent. With the
    contact centre :math:`c`, a point :math:`x` on the side of the body that faces
    the obstacle (outward boundary normal :math:`\nu` with :math:`\nu\cdot n > 0`) gets

    .. math::

        r(x) = \bigl|(x - c) - ((x - c)\cdot n)\,n\bigr|,

    its distance from the axis through :math:`c` along :math:`n` (2D: signed by the
    tangent :math:`t \perp n` that points along ``+axis``). This is Hertz's radius for
    a flat body and the chord radius :math:`R\sin\theta` on a sphere or a cylinder of
    radius :math:`R`. Points on the far side (:math:`\nu\cdot n \le 0`: the back of a
    ball, the sides of a punch) continue past the fold, at
    :math:`r_f + |(r_f - r,\; h - h_f)|` with :math:`r_f` the largest front radius,
    :math:`h = (x - c)\cdot n` and :math:`h_f` the deepest front height, so that the
    abscissa keeps increasing along the boundary instead of folding back onto the
    contact zone.

    Parameters
    ----------
    solution : ContactSolution
        ``points`` (m, d), ``pressure`` (m,), ``normals`` (m, d) (outward normals of
        the obstacle, optional: without any normals the coordinate direction of least
        extent is the approach direction) and ``problem`` (mesh and contact boundary, optional:
        without them no point is treated as far side).
    axis : int
        2D: the coordinate whose direction gives the sign.
    center : sequence of float, optional
        Contact centre :math:`c` (e.g. the symmetry point of a half or quarter
        model). Default: the point of the largest pressure (of the largest gap when
        nothing is loaded).

    Returns
    -------
    r : ndarray (m,)
    label : str
        Axis label without unit: ``"x ..."`` in 2D, ``"r ..."`` in 3D.
    """
    pts = np.asarray(solution.points, dtype=float)
    m, d = pts.shape
    p = np.asarray(getattr(solution, "pressure", np.zeros(m)), dtype=float)
    loaded = p > 0
    nu = _body_normals(solution, pts)
    w = p if np.any(loaded) else np.ones(m)
    n, spread = None, np.inf
    # the flatter side sets the direction: the obstacle's normals for a plane, the body's for a flat face
    ob = getattr(solution, "normals", None)  # outward normals of the obstacle: they point at the body
    for normals in (None if ob is None else -np.asarray(ob, dtype=float), nu):
        if normals is None or np.shape(normals) != (m, d):
            continue
        s = np.asarray(normals, dtype=float).T @ w
        norm = float(np.linalg.norm(s))
        if norm > 0 and np.all(np.isfinite(s)) and 1.0 - norm / float(np.sum(w)) < spread - 1e-12:
            n, spread = s / norm, 1.0 - norm / float(np.sum(w))
    if n is None:  # no normals: the flat direction of the point cloud
        n = np.eye(d)[int(np.argmin(np.ptp(pts, axis=0)))] if m else np.eye(d)[-1]
    if center is not None:
        c = _pad(center, d)
    elif np.any(loaded):
        c = pts[int(np.argmax(p))]
    else:
        gap = np.asarray(getattr(solution, "gap", np.zeros(m)), dtype=float)
        c = pts[int(np.argmax(gap))] if m else np.zeros(d)
    rel = pts - c
    h = rel @ n
    lateral = rel - np.outer(h, n)
    if d == 2:
        t = np.array([-n[1], n[0]])
        if t[axis] < 0 or (t[axis] == 0 and t[1 - axis] < 0):
            t = -t
        signed = lateral @ t
        r = np.abs(signed)
    else:
        signed = None
        r = np.linalg.norm(lateral, axis=1)
    if nu is not None:
        front = nu @ n > 1e-3
        if np.any(front) and not np.all(front):
            r_f = float(np.max(r[front]))
            h_f = float(np.min(h[front]))
            back = ~front
            r = r.copy()
            r[back] = r_f + np.hypot(r_f - r[back], h[back] - h_f)
    if d == 2:
        sign = np.where(signed < 0, -1.0, 1.0)
        return sign * r, "x (along the contact boundary)"
    return r, "r (distance from the centre in the contact plane)"


def contact_center(solution, center=None, declared: bool = True):
    """The contact centre to measure contact widths from, or ``None`` (measure the loaded zone itself).

    A ``declared`` centre (a Hertz reference, ``[reference] center``, a built-in
    problem's symmetry point) is used as given. An undeclared default (a problem
    file's origin) is used only while it lies in the loaded zone, i.e. within its
    bounding box widened by the element size ``solution.extra["h"]``: the symmetry
    point of a half model pressed at the origin keeps it, a contact zone elsewhere (a
    moving obstacle, a body away from the origin) does not, so that a "half-width" is
    never the distance of the zone from the origin.
    """
    if center is None or declared:
        return center
    pts = np.asarray(solution.points, dtype=float)
    loaded = np.asarray(solution.pressure, dtype=float) > 0
    if not np.any(loaded):
        return None
    c = _pad(center, pts.shape[1])
    h = float((getattr(solution, "extra", None) or {}).get("h") or 0.0)
    lo, hi = pts[loaded].min(axis=0) - h, pts[loaded].max(axis=0) + h
    return center if bool(np.all((c >= lo) & (c <= hi))) else None


def contact_half_width(solution, axis: int = 0, center=None, declared: bool = True) -> float:
    """The contact half-width a report shows: from the centre where there is one, else of the loaded zone.

    With a centre (see :func:`contact_center`): ``solution.contact_half_width(axis,
    center)`` (the Hertz fit or the loaded edge measured from the centre), except in 3D
    without a Hertz reference on a contact boundary that is not a coordinate plane (a
    ball, a Gmsh body), where that edge, searched along a line of the "flat" coordinate
    plane, does not exist: there the contact radius of :func:`loaded_half_width`.
    Without a centre: :func:`loaded_half_width`.
    """
    c = contact_center(solution, center, declared)
    if c is None and not declared:
        return loaded_half_width(solution, axis=axis)
    if not edge_search_applies(solution):
        return loaded_half_width(solution, axis=axis, center=c)
    return float(solution.contact_half_width(axis=axis, center=c))


def edge_search_applies(solution) -> bool:
    """Whether ``solution.contact_half_width`` measures a real width: 2D, a Hertz fit, or a 3D contact
    boundary that is a coordinate plane (its edge is searched along a line of that plane)."""
    pts = np.asarray(solution.points, dtype=float)
    if pts.shape[1] != 3 or getattr(getattr(solution, "problem", None), "reference", None) is not None:
        return True
    spread = np.ptp(pts, axis=0) if pts.shape[0] else np.zeros(3)
    return bool(spread.min() <= 1e-9 * max(float(spread.max()), 1e-300))


def loaded_half_width(solution, axis: int = 0, center=None) -> float:
    """Half-width of the loaded zone measured with :func:`contact_coordinate` (contact radius in 3D).

    2D: half the extent :math:`(x_{max} - x_{min})/2` of the loaded points along the
    contact boundary; 3D: the largest distance of a loaded point from the centre.
    A contact measure for problems without a declared contact centre (a moving
    obstacle, a curved body): unlike a distance from the origin it stays a width
    wherever the contact zone is. ``0.0`` when no point carries pressure.
    """
    r, _ = contact_coordinate(solution, axis=axis, center=center)
    loaded = np.asarray(solution.pressure, dtype=float) > 0
    if not np.any(loaded):
        return 0.0
    if np.asarray(solution.points).shape[1] == 2:
        return 0.5 * float(np.ptp(r[loaded]))
    return float(np.max(r[loaded]))


def pressure_figure(solution, *, reference=None, load: float | None = None, center=None, axis: int = 0,
                    title: str | None = None, mindlin=None, units: Units | None = None):
    """Contact pressure at the contact points against the analytical profile.

    Parameters
    ----------
    solution : ContactSolution
    reference : object, optional
        Analytical reference with ``half_width(P)`` and ``pressure(r, P)``
        (e.g. :class:`~alcontact.problems.hertz.HertzReference`); default
        ``solution.problem.reference``. ``None``: numerical values only.
    load : float, optional
        Total load ``P`` of the reference; default ``reference.load(solution.normal_force)``.
    center, axis
        See :func:`contact_coordinate`; default centre: ``problem.meta["center"]``, used
        as :func:`contact_center` says (``meta["center_declared"]``).
    mindlin : MindlinReference, optional
        Frictional runs (``solution.extra["shear"]`` present) get a second panel
        with the tangential traction and the Coulomb bound :math:`\\mu p`; with
        ``mindlin`` also the Cattaneo-Mindlin profile for the model's P and Q.
    units : Units, optional
        Axis units; default: the units of the problem file (unnamed).

    Returns
    -------
    matplotlib.figure.Figure
    """
    problem = solution.problem
    reference = reference if reference is not None else getattr(problem, "reference", None)
    declared = True
    if center is None:
        meta = getattr(problem, "meta", None) or {}
        center, declared = meta.get("center"), bool(meta.get("center_declared", True))
    u = _units(units)
    a_num = contact_half_width(solution, axis=axis, center=center, declared=declared)
    r, xlabel = contact_coordinate(solution, axis=axis, center=contact_center(solution, center, declared))
    var = xlabel[0]  # "x" (2D) or "r" (3D)
    xlabel = f"{xlabel} ({u.length})"
    p = np.asarray(solution.pressure, dtype=float)

    extra = getattr(solution, "extra", None) or {}
    friction = "shear" in extra
    fig = _new_figure(size=(6.4, 6.4) if friction else (6.4, 4.2))
    ax = fig.add_subplot(2, 1, 1) if friction else fig.add_subplot()
    a_ref = None
    if reference is not None:
        P = reference.load(solution.normal_force) if load is None else float(load)
        a_ref = float(reference.half_width(P))
    extent = 2.0 * max(a_num, a_ref or 0.0)
    keep = np.abs(r) <= extent if extent > 0 else np.ones(r.size, bool)
    order = np.argsort(r[keep], kind="stable")
    rk, pk = r[keep][order], p[keep][order]
    if reference is not None and a_ref is not None and a_ref > 0:
        lo = min(float(rk.min(initial=0.0)), 0.0)
        hi = max(float(rk.max(initial=0.0)), a_ref)
        xs = np.linspace(lo, hi, 600)
        p0 = f", $p_0$ = {float(reference.peak_pressure(P)):.5g} {u.pressure}" \
            if hasattr(reference, "peak_pressure") else ""
        ax.plot(xs, reference.pressure(np.abs(xs), P), "-", color="0.35", lw=1.5,
                label=rf"analytical $p_0\sqrt{{1-{var}^2/a^2}}${p0}")
        ax.axvline(a_ref, color="0.35", ls=":", lw=1, label=f"analytical $a$ = {a_ref:.4g} {u.length}")
    ax.plot(rk, pk, "o", ms=3.5, color="C0", label="computed pressure")
    # 2D: on the side that carries the pressure (a half model at x <= 0 has its edge at -a)
    side = -1.0 if r.size and float(np.sum(p * r)) < 0 else 1.0
    ax.axvline(side * a_num, color="C0", ls="--", lw=1, label=f"computed $a$ = {a_num:.4g} {u.length}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"contact pressure p ({u.pressure})")
    ax.set_ylim(bottom=0.0)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    ax.set_title(title or getattr(problem, "name", "contact pressure"), fontsize="medium")
    if friction:
        _shear_panel(fig.add_subplot(2, 1, 2, sharex=ax), solution, r, keep, order, axis, mindlin, xlabel, u)
    _note_units(fig, u)
    return fig


def _shear_panel(ax, solution, r, keep, order, axis, mindlin, xlabel, u) -> None:
    extra = solution.extra
    shear = np.asarray(extra["shear"], dtype=float)[:, axis]
    mu = float(extra.get("mu", 0.0))
    rk = r[keep][order]
    q = shear[keep][order]
    bound = mu * np.asarray(solution.pressure, dtype=float)[keep][order]
    ax.plot(rk, bound, "-", color="0.6", lw=1, label=r"Coulomb bounds $\pm\mu p$")
    ax.plot(rk, -bound, "-", color="0.6", lw=1)  # same style: covered by the entry above
    state = np.asarray(extra.get("state", np.zeros(r.size)))[keep][order]
    for val, name, mk in ((1, "stick", "o"), (2, "slip", "s")):
        sel = state == val
        if np.any(sel):
            ax.plot(rk[sel], q[sel], mk, ms=3.5, label=f"computed ({name})")
    if mindlin is not None:
        P = float(solution.normal_force) * mindlin.hertz.symmetry
        Q = float(extra.get("tangential_force", [0.0])[axis]) * mindlin.hertz.symmetry
        if P > 0 and abs(Q) > 0:
            xs = np.linspace(float(rk.min(initial=0.0)), float(rk.max(initial=0.0)), 800)
            c = mindlin.stick_half_width(P, abs(Q))
            ax.plot(xs, np.sign(Q) * mindlin.shear(xs, P, abs(Q)), "-", color="k", lw=1.2,
                    label=f"Cattaneo-Mindlin, c = {c:.3g} {u.length}")
    ax.axhline(0.0, color="0.8", lw=0.8)  # the axis, not data
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"tangential traction $t_{{T,{'xyz'[axis]}}}$ ({u.pressure})")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", loc="best")


def steps_figure(rows, *, title: str | None = None):
    """Per load step: outer and Newton iterations, penetration and Coulomb violation.

    Parameters
    ----------
    rows : sequence of dict
        Rows of ``steps.csv`` (keys ``t``, ``outer_iterations``, ``newton_iterations``,
        ``penetration``, optionally ``coulomb``).
    """
    fig = _new_figure(size=(6.4, 5.2))
    if not rows:
        ax = fig.add_subplot()
        ax.text(0.5, 0.5, "no converged load step", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return fig
    t = np.array([float(r["t"]) for r in rows])
    ax1 = fig.add_subplot(2, 1, 1)
    ax1.plot(t, [r["outer_iterations"] for r in rows], "o-", label="outer iterations")
    ax1.plot(t, [r["newton_iterations"] for r in rows], "s--", label="Newton iterations")
    ax1.set_ylabel("iterations per step (count)")
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize="small")
    ax1.set_title(title or "convergence per load step", fontsize="medium")
    ax2 = fig.add_subplot(2, 1, 2, sharex=ax1)
    series = (("penetration", "penetration / h"), ("coulomb", r"Coulomb violation $(|t_T|-\mu t_N)^+/p_{max}$"))
    for key, label in series:
        y = np.array([float(r.get(key, np.nan) if r.get(key) is not None else np.nan) for r in rows])
        y = np.where(np.isfinite(y) & (y > 0), y, np.nan)
        if np.any(np.isfinite(y)):
            ax2.semilogy(t, y, "o-", ms=4, label=label)
    ax2.set_xlabel("pseudo-time t (load factor, dimensionless)")
    ax2.set_ylabel("final measure of the step (dimensionless)")
    ax2.grid(alpha=0.3, which="both")
    if ax2.lines:
        ax2.legend(fontsize="small")
    return fig


def load_displacement_figure(rows, controls, *, title: str | None = None, units: Units | None = None,
                             dim: int = 2):
    """Contact forces against the displacement of the loaded boundaries over the load steps.

    Parameters
    ----------
    rows : sequence of dict
        Rows of ``steps.csv``: ``normal_force``, ``tangential_force`` and one
        ``u_<label>`` column per control.
    controls : sequence of (label, kind)
        ``kind`` is ``"normal"`` (plotted against the normal force) or
        ``"tangential"`` (against the tangential force).
    units : Units, optional
        Axis units (default: the problem file's, unnamed).
    dim : int
        Dimension of the model (the force is per unit thickness in 2D).
    """
    u = _units(units)
    fig = _new_figure()
    ax = fig.add_subplot()
    for i, (label, kind) in enumerate(controls):
        x = np.array([float(r[f"u_{label}"]) for r in rows])
        key = "normal_force" if kind == "normal" else "tangential_force"
        y = np.array([float(r[key]) for r in rows])
        ax.plot(np.concatenate([[0.0], x]), np.concatenate([[0.0], y]), "o-", ms=4, color=f"C{i}",
                label=f"{key.replace('_', ' ')} vs mean displacement of {label}")
    if not controls:
        t = np.array([float(r["t"]) for r in rows])
        ax.plot(t, [float(r["normal_force"]) for r in rows], "o-", ms=4, label="normal force")
        ax.set_xlabel("pseudo-time t (load factor, dimensionless)")
    else:
        ax.set_xlabel(f"mean displacement of the loaded boundary ({u.length})")
    ax.set_ylabel(f"contact force of the model ({u.force(dim)})")
    _note_units(fig, u)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title(title or "load-displacement curve", fontsize="medium")
    return fig


def reaction_force_figure(rows, control: str | None = None, *, title: str | None = None,
                          units: Units | None = None, dim: int = 2):
    """Reaction force and contact force against the prescribed displacement (or the load factor) per step.

    Parameters
    ----------
    rows : sequence of dict
        Rows of ``reaction_force.csv`` / ``steps.csv``: ``t``, ``reaction_<c>`` and
        ``force_<c>`` for each coordinate ``c``, and ``u_<control>`` when given.
    control : str, optional
        Label of the driving support (``"top_y"``): its mean displacement is the
        abscissa and its component (the last letter) the plotted one; default: the
        pseudo-time (load factor) and the component with the largest force over the steps.
    units : Units, optional
        Axis units (default: the problem file's, unnamed).
    dim : int
        Dimension of the model (the force is per unit thickness in 2D).
    """
    u = _units(units)
    fig = _new_figure()
    ax = fig.add_subplot()
    axes = "xyz"[:dim]
    if not rows:
        ax.text(0.5, 0.5, "no converged load step", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return fig
    if control is not None and control[-1:] in axes:
        comp = control[-1]
        x = np.array([float(r[f"u_{control}"]) for r in rows])
        ax.set_xlabel(f"prescribed displacement: mean u_{comp} of {control[:-2]} ({u.length})")
    else:
        comp = max(axes, key=lambda c: max(abs(float(r.get(f"reaction_{c}", r.get(f"force_{c}", 0.0))))
                                           for r in rows))
        x = np.array([float(r["t"]) for r in rows])
        ax.set_xlabel("pseudo-time t (load factor, dimensionless)")
    x = np.concatenate([[0.0], x])
    for key, style, label in ((f"reaction_{comp}", "o-", f"support reaction R_{comp} (all supports)"),
                              (f"force_{comp}", "s--", f"contact force F_{comp} on the body")):
        if key not in rows[0]:  # small deformation: no support reactions in the rows
            continue
        y = np.concatenate([[0.0], [float(r.get(key, np.nan)) for r in rows]])
        ax.plot(x, y, style, ms=4, label=label)
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_ylabel(f"force of the model ({u.force(dim)})")
    _note_units(fig, u)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title(title or "reaction-force curve", fontsize="medium")
    return fig


#: Most phases :func:`force_path_figure` draws side by side (a longer path is drawn over the pseudo-time).
MAX_PHASE_PANELS = 4


def load_path_phases(rows, quantities, start=None) -> list[tuple[int, int, str]]:
    """Split the load steps into phases in which the same prescribed quantities move the same way.

    Parameters
    ----------
    rows : sequence of dict
        One per load step, with a column per prescribed quantity.
    quantities : sequence of (column, label, normal)
        The prescribed quantities (``normal``: a pressing action).
    start : dict, optional
        Their values at ``t = 0`` (default 0).

    Returns
    -------
    list of (first, last, column)
        Rows ``first..last`` (inclusive) form a phase: a new one starts where the set of
        moving quantities or the sign of a motion changes (press, then slide; load, then
        unload); a step where nothing moves stays in the phase before. ``column`` is the
        phase's abscissa: the quantity that changes most in the phase, a pressing one
        where one moves.
    """
    if not rows or not quantities:
        return []
    cols = [q[0] for q in quantities]
    start = start or {}
    Q = np.array([[float(start.get(c, 0.0)) for c in cols]] + [[float(r[c]) for c in cols] for r in rows])
    D = np.diff(Q, axis=0)
    tol = 1e-9 * max(float(np.max(np.abs(D), initial=0.0)), 1e-300)
    sig = np.where(np.abs(D) > tol, np.sign(D), 0.0)
    phases: list[list[int]] = []
    last = None
    for k in range(len(rows)):
        if last is None or (np.any(sig[k]) and not np.array_equal(sig[k], last)):
            phases.append([k, k])
        else:
            phases[-1][1] = k
        if np.any(sig[k]):
            last = sig[k]
    out = []
    for first, end in phases:
        change = np.abs(Q[end + 1] - Q[first])
        normal = np.array([bool(q[2]) for q in quantities])
        pick = normal & (change > tol) if np.any(normal & (change > tol)) else np.ones(len(cols), bool)
        j = int(np.argmax(np.where(pick, change, -1.0)))
        out.append((first, end, cols[j]))
    return out


def force_path_figure(rows, quantities, *, start=None, title: str | None = None, units: Units | None = None,
                      dim: int = 2):
    """Support reactions and contact forces against what was prescribed, one panel per phase of the path.

    Parameters
    ----------
    rows : sequence of dict
        Rows of ``reaction_force.csv``: ``reaction_<c>``, ``force_<c>`` and the prescribed quantities.
    quantities : sequence of (column, label, normal)
        The prescribed quantities (see :func:`load_path_phases`); ``obstacle_*`` and
        ``prescribed_u_*`` are lengths, ``load_factor_*`` dimensionless.
    start : dict, optional
        The prescribed quantities at ``t = 0`` (the curves start there, at zero force).
    units : Units, optional
        Axis units (default: the problem file's, unnamed).
    dim : int
        Dimension of the model (the force is per unit thickness in 2D).

    Returns
    -------
    matplotlib.figure.Figure
        One panel per phase (press, then slide: two), each against its own abscissa
        (e.g. the prescribed displacement, then the obstacle travel); more than
        :data:`MAX_PHASE_PANELS` phases: :func:`reaction_force_figure` over the pseudo-time.
    """
    u = _units(units)
    phases = load_path_phases(rows, quantities, start)
    if not phases or len(phases) > MAX_PHASE_PANELS:  # a cyclic path: one panel over the pseudo-time
        return reaction_force_figure(rows, None, title=title, units=units, dim=dim)
    labels = {q[0]: q[1] for q in quantities}
    fig = _new_figure(size=(6.4 if len(phases) == 1 else 4.2 * min(len(phases), 3), 4.4))
    comps = [c for c in "xyz"[:dim]
             if any(abs(float(r.get(f"force_{c}", 0.0))) > 0 or abs(float(r.get(f"reaction_{c}", 0.0))) > 0
                    for r in rows)]
    first_ax = None
    start = start or {}
    for i, (first, end, col) in enumerate(phases):
        ax = fig.add_subplot(1, len(phases), i + 1, sharey=first_ax)
        first_ax = first_ax or ax
        before = rows[first - 1] if first > 0 else None
        x = [float(before[col]) if before else float(start.get(col, 0.0))] + \
            [float(r[col]) for r in rows[first:end + 1]]
        for j, c in enumerate(comps):
            for key, style, text in ((f"force_{c}", "o-", f"contact force F_{c} on the body"),
                                     (f"reaction_{c}", "s--", f"support reaction R_{c}")):
                if key not in rows[0]:  # small deformation: no support reactions in the rows
                    continue
                y = [float(before.get(key, np.nan)) if before else 0.0] + \
                    [float(r.get(key, np.nan)) for r in rows[first:end + 1]]
                ax.plot(x, y, style, ms=3.5, color=f"C{j}", label=text)
        ax.axhline(0.0, color="0.6", lw=0.8)  # the axis, not data
        unit = "dimensionless" if col.startswith("load_factor_") else u.length
        ax.set_xlabel(f"{labels[col]} ({unit})")
        if i == 0:
            ax.set_ylabel(f"force of the model ({u.force(dim)})")
        t0 = float(before["t"]) if before else 0.0
        ax.set_title(f"phase {i + 1}: t = {t0:g} to {float(rows[end]['t']):g}" if len(phases) > 1
                     else (title or "reaction-force curve"), fontsize="medium")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="x-small")
    if len(phases) > 1 and title:
        fig.suptitle(title, fontsize="medium")
    _note_units(fig, u)
    return fig


def convergence_figure(result, *, tolerances: Mapping[str, float] | None = None, title: str | None = None):
    """Convergence history of the outer iterations (log scale).

    A converged run ends below the tolerance line in every measure its stopping test
    used; a measure it did not use (the multiplier change of ``ssn``, which stops when
    the active set repeats, or of a physical stopping test) is labelled so, and the
    penetration and complementarity of the returned state (the verified values of
    ``result``) are drawn as stars at the last iteration.

    Parameters
    ----------
    result : ContactResult
        ``solution.result``; its ``history`` gives one point per outer iteration.
    tolerances : mapping, optional
        ``{"penetration": tol, ...}``: drawn as dashed horizontal lines.

    Returns
    -------
    matplotlib.figure.Figure
    """
    hist = tuple(result.history)
    fig = _new_figure()
    ax = fig.add_subplot()
    if not hist:
        ax.text(0.5, 0.5, "no outer iterations recorded", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return fig
    k = np.array([it.k for it in hist], dtype=float)
    tols = {name: float(v) for name, v in (tolerances or {}).items() if v and v > 0}
    converged = getattr(result, "success", False)
    for i, (name, label) in enumerate(_HISTORY_SERIES):
        y = np.array([getattr(it, name) for it in hist], dtype=float)
        y = np.where(np.isfinite(y) & (y > 0), y, np.nan)  # zeros cannot be drawn on a log axis
        if converged and name in tols and np.isfinite(y[-1]) and y[-1] > tols[name]:
            # the solver stopped on other tests (ssn: the active set repeats; physical stopping at finite
            # deformation: penetration, complementarity and equilibrium): this measure was not one of them
            label += f" (not a stopping test here: {result.message})"
        ax.semilogy(k, y, "o-", ms=4, color=f"C{i}", label=label)
    if converged:  # the measures of the returned state, as verified where results are built
        for i, (name, label) in enumerate(_HISTORY_SERIES[:2]):
            v = float(getattr(result, name, np.nan))
            if np.isfinite(v) and v > 0:
                ax.semilogy([k[-1]], [v], "*", ms=11, mec="k", mew=0.6, color=f"C{i}",
                            label=f"{name} of the returned state (verified)")
    same = len(set(tols.values())) == 1
    for i, (name, _label) in enumerate(_HISTORY_SERIES):
        if name in tols:  # one grey line when all tolerances coincide
            label = f"tolerance {tols[name]:.0e}" if same else f"tolerance of {name.replace('_', ' ')}"
            ax.axhline(tols[name], color="0.4" if same else f"C{i}", ls="--", lw=0.8, label=label)
            if same:
                break
    ax.set_xlabel("outer iteration k (count)")
    ax.set_ylabel("measure (dimensionless)")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    status = getattr(result.status, "label", str(result.status))
    ax.set_title(title or f"{result.algorithm} / {result.penalty}: {status}", fontsize="medium")
    return fig


def save_figure(fig, path: str | os.PathLike, *, dpi: int = 120) -> Path:
    """Save ``fig`` as PNG atomically; return ``path``."""
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    logger.debug("wrote %s", path)
    return path


def save_pressure_plot(solution, path: str | os.PathLike, **kwargs) -> Path:
    """:func:`pressure_figure` saved as PNG at ``path``."""
    return save_figure(pressure_figure(solution, **kwargs), path)


def save_convergence_plot(result, path: str | os.PathLike, **kwargs) -> Path:
    """:func:`convergence_figure` saved as PNG at ``path``."""
    return save_figure(convergence_figure(result, **kwargs), path)
