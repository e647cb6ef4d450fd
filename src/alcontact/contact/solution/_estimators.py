r"""Post-processing estimators of a contact solution: equilibrium, peak pressure, contact size.

Everything here works on the *nodal contact forces* the solver applied to the
body, :math:`r_i = w_i \lambda_i` along the obstacle normal :math:`\nu_i` (plus the
tangential forces with friction), because those are exact for the discrete
problem: :math:`f_{int}(u) = f_{ext} + f_c` on the free DOFs.

Global equilibrium
    With :math:`R` the support reactions, summing the equilibrium equations
    over all DOFs of each component (a rigid translation does no internal work,
    :math:`\sum_{i \in c} f_{int,i} = 0`) gives the invariant

    .. math::  F_c + F_{ext} + R = 0, \qquad F_c = \sum_i f_{c,i},\;
               F_{ext} = \sum_i f_{ext,i},\; R = \sum_{i\ \mathrm{fixed}} (f_{int} - f_{ext} - f_c)_i,

    checked by :func:`equilibrium` for any body of the
    :class:`~alcontact.fem._body.Body` protocol (its ``internal_force``).

Recovered pressure
    The pressure field whose consistent load on the element's boundary space is
    :math:`r`: :math:`M_\Gamma p = r` (``model.boundary_pressure``), which is
    :math:`r_i / w_i` wherever the tributary weights are the integrals of the
    shape functions (P1, 2D P2).

Hertz fit
    Where the analytical solution is a Hertz profile, :math:`p(r) = p_0
    \sqrt{1 - r^2/a^2}` is fitted to the recovered pressure field by least squares
    in :math:`L^2(\Gamma)` (:func:`fit_hertz_field`, integrals over the model's
    boundary), or, for a body without boundary quadrature, at the points
    (:func:`fit_hertz`), each point weighing its tributary length/area. On the
    symmetry planes of a half or quarter model both give the half/quarter share
    of the full model, so nothing counts twice. The peak pressure is ``p0`` of the
    free fit (``p0`` and ``a``); the contact size is ``a`` of the *load-matched* fit,
    whose profile carries the load of the field (:math:`\int p_0 s_a = \int p_h`,
    the sum of the nodal forces), which removes the trade-off between ``p0`` and
    ``a`` that lets the free fit pull ``a`` inwards where the element's field
    resolves the square-root edge poorly (P1 tetrahedra).

Contact edge
    Elsewhere the contact size is the outermost loaded point interpolated
    along the boundary with the square-root behaviour of the pressure at a
    smooth contact edge (:func:`edge_from_profile`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Equilibrium:
    """Global force balance of a solved body (see module doc).

    Attributes
    ----------
    contact_force : ndarray (d,)
        Resultant of the nodal contact forces on the body, :math:`F_c`.
    applied_load : ndarray (d,)
        Resultant of the external loads, :math:`F_{ext}`.
    reaction : ndarray (d,)
        Resultant of the support reactions, :math:`R`.
    residual : float
        The imbalance :math:`|F_c + F_{ext} + R|` beyond what the free-DOF residuals explain, over
        the scale (see :func:`equilibrium`; 0 when all vanish).
    free_residual : float
        Max norm of :math:`f_{int} - f_{ext} - f_c` on the free DOFs over the same scale
        (the discrete equilibrium the solver reached).
    """

    contact_force: np.ndarray
    applied_load: np.ndarray
    reaction: np.ndarray
    residual: float
    free_residual: float

    @property
    def largest(self) -> float:
        """The larger of the two residuals (the ``equilibrium`` measure of :mod:`alcontact.contact._verify`)."""
        return max(float(self.residual), float(self.free_residual))

    def as_dict(self) -> dict:
        """JSON-ready dictionary (lists of floats)."""
        return {
            "contact_force": [float(x) for x in self.contact_force],
            "applied_load": [float(x) for x in self.applied_load],
            "reaction": [float(x) for x in self.reaction],
            "residual": float(self.residual),
            "free_residual": float(self.free_residual),
        }


def _dof_components(body) -> np.ndarray:
    """Component (0..d-1) of every DOF of ``body`` (interleaved numbering without ``all_node_dofs``);
    -1 for a DOF that is no displacement component (the pressure of a mixed u-p body)."""
    if not hasattr(body, "all_node_dofs"):
        return np.arange(body.ndofs, dtype=np.int64) % int(body.dim)
    _, dofs = body.all_node_dofs()
    comp = np.full(body.ndofs, -1, dtype=np.int64)
    for c in range(dofs.shape[1]):
        comp[dofs[:, c]] = c
    return comp


def nodal_force_vector(ndofs: int, dofs: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Scatter point forces ``forces`` ``(m, d)`` onto the DOFs ``dofs`` ``(m, d)``: a ``(ndofs,)`` vector."""
    out = np.zeros(int(ndofs))
    np.add.at(out, np.asarray(dofs, dtype=np.int64).ravel(), np.asarray(forces, dtype=float).ravel())
    return out


def equilibrium(body, u, fixed, load, contact_forces, *, length: float | None = None,
                force_scale: float = 0.0) -> Equilibrium:
    r"""Global equilibrium :math:`F_c + F_{ext} + R = 0` of a solved body.

    Both residuals are relative to the force scale

    .. math::  s = \max\big(|F_c|, |F_{ext}|, |R|, \|f_{int}\|_\infty, \|f_{ext}\|_\infty,
               \|f_c\|_\infty, E' h^{d-2} \|u\|_\infty\big),

    whose last term (a stiffness times the displacement, ``E'`` the plane-strain modulus of
    the body's material, ``h = length``) does not vanish when the contact force and the
    reactions do: a body that is only moved (no load, no contact force) otherwise
    compares round-off with round-off and reads 1.0.

    The internal forces sum to zero (a rigid translation does no work), so the imbalance is
    the sum of the residuals :math:`r = f_{int} - f_{ext} - f_c` on the free DOFs:
    :math:`F_c + F_{ext} + R = -\sum_{free} r` per component, up to the round-off of
    :math:`\sum f_{int}`. Each free residual is measured by ``free_residual``; their sum over
    :math:`n_f` DOFs of a component is bounded by :math:`\sqrt{n_f} \|r_f\|_2`
    (Cauchy-Schwarz) and grows with the mesh even when every one of them is at round-off
    (2D Hertz, 277k DOFs, Algorithm 6.1: free residual 6.4e-14, imbalance 1.2e-11). The
    ``residual`` reported is the imbalance beyond that bound: what no free residual
    explains (a reaction or contact force that is not the one the state carries).

    Parameters
    ----------
    body : Body
        Any body of the :class:`~alcontact.fem._body.Body` protocol; its
        ``all_node_dofs()`` gives the component of each DOF where it exists
        (otherwise the interleaved numbering ``dof % dim``); its ``internal_force(u)`` is used (``K u`` for
        small deformation, the internal force of a finite-deformation body).
    u : ndarray (ndofs,)
        Displacement.
    fixed : array_like of int
        Dirichlet DOFs.
    load : ndarray (ndofs,)
        External load vector :math:`f_{ext}`.
    contact_forces : ndarray (ndofs,)
        Nodal contact forces on the body :math:`f_c` (see :func:`nodal_force_vector`).
    length : float, optional
        Element size ``h`` of the stiffness scale (default: no stiffness scale, or a body
        without a ``material``).
    force_scale : float
        A further force of the scale (the verification passes the largest contact pressure
        times the largest tributary weight of a contact point).

    Returns
    -------
    Equilibrium
    """
    u = np.asarray(u, dtype=float)
    fint = np.asarray(body.internal_force(u), dtype=float)
    fext = np.asarray(load, dtype=float)
    fc = np.asarray(contact_forces, dtype=float)
    fixed = np.unique(np.asarray(fixed, dtype=np.int64).ravel())
    comp = _dof_components(body)
    d = int(body.dim)
    res = fint - fext - fc
    free = np.ones(body.ndofs, dtype=bool)
    free[fixed] = False
    disp = comp >= 0  # force components (a mixed body's pressure rows are constraint residuals)
    fixed_disp = fixed[disp[fixed]]
    Fc = np.bincount(comp[disp], weights=fc[disp], minlength=d)
    Fe = np.bincount(comp[disp], weights=fext[disp], minlength=d)
    R = np.bincount(comp[fixed_disp], weights=res[fixed_disp], minlength=d)
    with np.errstate(over="ignore", invalid="ignore"):
        scale = max(float(np.linalg.norm(Fc)), float(np.linalg.norm(Fe)), float(np.linalg.norm(R)),
                    float(np.max(np.abs(fint), initial=0.0)), float(np.max(np.abs(fext), initial=0.0)),
                    float(np.max(np.abs(fc), initial=0.0)), stiffness_scale(body, length) * float(
                        np.max(np.abs(u), initial=0.0)), float(force_scale))
    if not np.isfinite(scale):
        return Equilibrium(Fc, Fe, R, np.inf, np.inf)
    if scale == 0.0:
        return Equilibrium(Fc, Fe, R, 0.0, 0.0)
    # a body of revolution balances the axial force only (radial nodal forces are held by the hoop stress)
    balanced = slice(1, 2) if body.axisymmetric else slice(None)
    free_disp = free & disp
    explained = np.sqrt(np.bincount(comp[free_disp], minlength=d)
                        * np.bincount(comp[free_disp], weights=res[free_disp] ** 2, minlength=d))
    imbalance = float(np.linalg.norm((Fc + Fe + R)[balanced])) - float(np.linalg.norm(explained[balanced]))
    resid = max(imbalance, 0.0) / scale
    free_res = float(np.max(np.abs(res[free]), initial=0.0)) / scale
    return Equilibrium(Fc, Fe, R, resid, free_res)


def stiffness_scale(body, length: float | None) -> float:
    r"""Nodal stiffness :math:`E' h^{d-2}` of ``body`` (force per displacement; 0 without ``length`` or material).

    ``E'`` is the plane-strain modulus :math:`E/(1-\nu^2)` (plane stress: ``E``), the
    stiffness of an element layer of thickness ``h`` per unit area, times the
    tributary area :math:`h^{d-1}` over ``h``.
    """
    mat = getattr(body, "material", None)
    if length is None or mat is None or not hasattr(mat, "E"):
        return 0.0
    d = int(body.dim)
    e = float(mat.E) if (d == 2 and getattr(mat, "plane", "strain") == "stress") else float(
        getattr(mat, "plane_strain_modulus", mat.E))
    return e * float(length) ** (d - 2)


def normal_coordinate(points: np.ndarray, loaded: np.ndarray) -> int:
    """The coordinate normal to the contact plane of a 3D contact boundary: the one in which the loaded points
    spread least when they cover a patch (three or more, the least spread below half the next), else the one in
    which all ``points`` spread least (a flat boundary). A curved boundary (a sphere's surface) spreads in every
    coordinate; its contact zone does not."""
    pts = np.asarray(points, dtype=float)
    sel = pts[np.asarray(loaded, dtype=bool)]
    if sel.shape[0] >= 3:
        s = np.sort(np.ptp(sel, axis=0))
        if s[0] < 0.5 * s[1]:
            return int(np.argmin(np.ptp(sel, axis=0)))
    return int(np.argmin(np.ptp(pts, axis=0))) if pts.shape[0] else pts.shape[1] - 1


def radial_coordinate(points: np.ndarray, center=None, axis: int | None = None, *,
                      flat: int | None = None) -> np.ndarray:
    """Distance of contact-boundary points from ``center`` within the contact plane.

    2D: :math:`|x_{axis} - c_{axis}|` (``axis`` defaults to the coordinate of
    largest spread). 3D: the in-plane distance, the out-of-plane direction being
    ``flat`` (default: the coordinate in which the (flat) contact boundary spreads least;
    :func:`normal_coordinate`).
    """
    pts = np.asarray(points, dtype=float)
    m, d = pts.shape
    c = np.zeros(d) if center is None else np.asarray(center, dtype=float).ravel()
    if c.size < d:
        c = np.concatenate([c, np.zeros(d - c.size)])
    spread = np.ptp(pts, axis=0) if m else np.ones(d)
    if d == 2:
        k = int(np.argmax(spread)) if axis is None else int(axis)
        return np.abs(pts[:, k] - c[k])
    flat = int(np.argmin(spread)) if flat is None else int(flat)
    keep = [k for k in range(d) if k != flat]
    return np.linalg.norm(pts[:, keep] - c[keep], axis=1)


@dataclass(frozen=True)
class HertzFit:
    """Least-squares Hertz profile :math:`p_0\\sqrt{1 - r^2/a^2}` of a pressure field."""

    p0: float
    a: float
    rms: float  # weighted RMS misfit over p0
    points: int  # points that entered the fit


def _hertz_misfit(a: float, r, p, w):
    s = np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    den = float(np.sum(w * s * s))
    p0 = float(np.sum(w * s * p)) / den if den > 0 else 0.0
    return float(np.sum(w * (p - p0 * s) ** 2)), p0


def _minimize_on(f, lo: float, hi: float, tol: float) -> float:
    """Minimize a scalar function on ``[lo, hi]``: a 64-point scan, then Brent's bounded
    method in the bracket around the best point (quadrature makes the misfit slightly
    rough near the contact edge; the scan keeps Brent out of spurious local minima)."""
    from scipy.optimize import minimize_scalar

    grid = np.linspace(lo, hi, 64)
    vals = np.array([f(a) for a in grid])
    k = int(np.argmin(vals))
    a0, a1 = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(f, bounds=(a0, a1), method="bounded", options={"xatol": tol})
    return float(res.x) if res.fun <= vals[k] else float(grid[k])


def _loaded_extent(r: np.ndarray, p: np.ndarray):
    """``(loaded, r_out, trivial)``: the points with a pressure, the largest radius among them, and the fit
    when there is nothing to fit (no loaded point: zeros; all at r = 0: the peak only), else ``None``."""
    loaded = p > 0
    if not np.any(loaded):
        return loaded, 0.0, HertzFit(0.0, 0.0, 0.0, 0)
    r_out = float(r[loaded].max())
    if r_out <= 0.0:
        return loaded, r_out, HertzFit(float(p.max()), 0.0, 0.0, int(loaded.sum()))
    return loaded, r_out, None


def fit_hertz(r, p, w) -> HertzFit:
    r"""Fit :math:`p(r) = p_0\sqrt{1 - r^2/a^2}` to pressures ``p`` at radii ``r``.

    Minimizes :math:`\sum_i w_i (p_i - p_0 \sqrt{1 - r_i^2/a^2}_+)^2` over the
    points out to twice the outermost loaded radius (so points inside the fitted
    ``a`` that carry no pressure count against it): for fixed ``a`` the optimal
    :math:`p_0` is explicit, and ``a`` is found by a bounded scalar minimization.
    ``w`` are the tributary lengths/areas of the points (on a symmetry plane the
    model's half/quarter share), so every point weighs its share of the boundary.

    Returns
    -------
    HertzFit
        ``p0 = a = 0`` when no point is loaded.
    """
    r = np.asarray(r, dtype=float)
    p = np.asarray(p, dtype=float)
    w = np.asarray(w, dtype=float)
    _, r_out, trivial = _loaded_extent(r, p)
    if trivial is not None:
        return trivial
    use = r <= 2.0 * r_out
    r, p, w = r[use], np.maximum(p[use], 0.0), w[use]
    # a lies between the outermost loaded point's inner neighbour and twice its radius
    inner = r[(r < r_out) & (p > 0)]
    lo = 0.5 * float(inner.max()) if inner.size else 0.5 * r_out
    a = _minimize_on(lambda a: _hertz_misfit(a, r, p, w)[0], lo, 2.0 * r_out, 1e-10 * r_out)
    f, p0 = _hertz_misfit(a, r, p, w)
    rms = math.sqrt(f / max(float(np.sum(w)), 1e-300)) / max(p0, 1e-300)
    return HertzFit(p0, a, rms, int(r.size))


def _amplitude_free(num: float, den: float, load: float, norm: float) -> float:
    """Best amplitude in L2: :math:`p_0 = \\int p_h s_a / \\int s_a^2`."""
    return num / den if den > 0 else 0.0


def _amplitude_load(num: float, den: float, load: float, norm: float) -> float:
    """Amplitude whose profile carries the field's load: :math:`p_0 = \\int p_h / \\int s_a`."""
    return load / norm if norm > 0 else 0.0


#: How :func:`fit_hertz_field` sets the amplitude ``p0`` for a trial ``a`` (by name).
AMPLITUDES = {"free": _amplitude_free, "load": _amplitude_load}


def fit_hertz_field(r_q, dx, v, r_nodes, p_nodes, *, amplitude: str = "free") -> HertzFit:
    r"""Fit :math:`p_0\sqrt{1 - r^2/a^2}` to a pressure *field* in the :math:`L^2(\Gamma)` norm.

    Minimizes :math:`\int_\Gamma (p_h - p_0 s_a)^2\,ds`, :math:`s_a = \sqrt{1 - r^2/a^2}_+`,
    with the integrals evaluated by quadrature: ``r_q`` radii of the quadrature points,
    ``dx`` their weights, ``v`` the recovered pressure :math:`p_h` there (see
    ``LinearElasticity.boundary_field_at_quadrature``). ``a`` comes from a bounded
    scalar minimization between half the radius of the last-but-one loaded node
    (``r_nodes``, ``p_nodes``) and twice the outermost one. Integrating over the model's
    boundary weighs every part of the contact zone by its area, symmetry planes
    included, and uses the whole field of the element's boundary space (for 3D P2 the
    vertex and edge-midpoint values enter with their true influence).

    Parameters
    ----------
    amplitude : {"free", "load"}
        ``"free"``: :math:`p_0` is the best amplitude for each trial ``a``,
        :math:`p_0 = \int p_h s_a / \int s_a^2` (a two-parameter fit; its ``p0`` is
        the reported peak pressure). ``"load"`` (*load-matched*): the profile carries the
        load of the field, :math:`p_0 = \int p_h / \int s_a`, so only ``a`` is fitted
        (its ``a`` is the reported contact size; the load is the sum of the nodal
        forces the solver applied, exact for the discrete problem, see
        ``docs/estimators.md``).
    """
    try:
        amp = AMPLITUDES[amplitude]
    except KeyError:
        from ...errors import InputError

        raise InputError(f"amplitude = {amplitude!r} is not known; use one of {sorted(AMPLITUDES)}") from None
    r_q, dx, v = (np.asarray(x, dtype=float) for x in (r_q, dx, v))
    r_nodes = np.asarray(r_nodes, dtype=float)
    p_nodes = np.asarray(p_nodes, dtype=float)
    loaded, r_out, trivial = _loaded_extent(r_nodes, p_nodes)
    if trivial is not None:
        return trivial
    inner = r_nodes[loaded & (r_nodes < r_out)]
    lo = 0.5 * float(inner.max()) if inner.size else 0.5 * r_out
    v2 = float(np.sum(dx * v * v))
    load = float(np.sum(dx * v))
    # only the quadrature points that a trial profile can reach matter below
    reach = r_q < 2.0 * r_out
    rr, dd, vv = r_q[reach], dx[reach], v[reach]

    def p0_and_misfit(a):
        s = np.sqrt(np.clip(1.0 - (rr / a) ** 2, 0.0, None))
        num, den, norm = float(np.sum(dd * vv * s)), float(np.sum(dd * s * s)), float(np.sum(dd * s))
        p0 = amp(num, den, load, norm)
        # int (p_h - p0 s)^2 = int p_h^2 - 2 p0 int p_h s + p0^2 int s^2
        return p0, v2 - 2.0 * p0 * num + p0 * p0 * den

    a = _minimize_on(lambda a: p0_and_misfit(a)[1], lo, 2.0 * r_out, 1e-10 * r_out)
    p0, f = p0_and_misfit(a)
    area = float(np.sum(dx[r_q <= a])) if np.any(r_q <= a) else float(np.sum(dx))
    rms = math.sqrt(max(f, 0.0) / max(area, 1e-300)) / max(p0, 1e-300)
    return HertzFit(p0, a, rms, int(np.count_nonzero(loaded)))


def edge_from_profile(r, p, loaded) -> float:
    r"""Contact edge from the pressures along a line (outermost loaded point, interpolated).

    With the last two loaded points :math:`r_1 < r_2` the edge of a smooth
    contact, where :math:`p \propto \sqrt{a - r}`, is
    :math:`a = (r_2 - \rho r_1)/(1-\rho)`, :math:`\rho = (p_2/p_1)^2`, kept between
    :math:`r_2` and the first unloaded point; where the pressure does not drop
    towards the edge (flat punch) the midpoint between the last loaded and the
    first unloaded point.
    """
    r = np.asarray(r, dtype=float)
    p = np.asarray(p, dtype=float)
    loaded = np.asarray(loaded, dtype=bool) & (p > 0)
    if not np.any(loaded):
        return 0.0
    order = np.argsort(r, kind="stable")
    r, p, loaded = r[order], p[order], loaded[order]
    last = int(np.flatnonzero(loaded).max())
    r2, p2 = r[last], p[last]
    cap = r[last + 1] if last + 1 < r.size else r2
    if last == 0:
        return float(0.5 * (r2 + cap))
    r1, p1 = r[last - 1], p[last - 1]
    if p1 <= p2 or p1 <= 0 or r1 >= r2:
        return float(0.5 * (r2 + cap))
    rho = (p2 / p1) ** 2
    a = (r2 - rho * r1) / (1.0 - rho)
    return float(min(max(a, r2), cap))


def load_center(points, forces, center=None) -> np.ndarray:
    """Center of a contact zone: ``center``, with every coordinate in which the loaded
    points lie on both sides of it replaced by the force-weighted centroid
    :math:`\\sum_i r_i x_i / \\sum_i r_i`.

    A half or quarter model has its loaded points on one side of the symmetry
    plane, which then keeps the given coordinate; a full model (e.g. a contact
    zone shifted by a tangential load) gets the centre of its pressure
    distribution, which for a symmetric profile is the centre of the profile.
    """
    pts = np.asarray(points, dtype=float)
    f = np.asarray(forces, dtype=float)
    d = pts.shape[1]
    c = np.zeros(d) if center is None else np.asarray(center, dtype=float).ravel().copy()
    if c.size < d:
        c = np.concatenate([c, np.zeros(d - c.size)])
    loaded = f > 0
    if not np.any(loaded):
        return c
    span = float(np.max(np.ptp(pts, axis=0))) if pts.shape[0] else 1.0
    tol = 1e-9 * max(span, 1e-300)
    x = pts[loaded]
    for k in range(d):
        if np.any(x[:, k] < c[k] - tol) and np.any(x[:, k] > c[k] + tol):
            c[k] = float(np.sum(f[loaded] * x[:, k]) / np.sum(f[loaded]))
    return c


def has_hertz_profile(problem) -> bool:
    """Whether the analytical pressure of ``problem`` is a Hertz profile (its reference says so)."""
    ref = getattr(problem, "reference", None)
    return bool(getattr(ref, "hertz_profile", False))
