"""Contact solver result and contact solution objects."""

from __future__ import annotations

import dataclasses

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import ConvergenceError
from ...status import Status


#: Termination reason of a contact solve: the project's one status table
#: :class:`alcontact.status.Status` (positive = converged, negative = failed, as PETSc),
#: shared with :func:`alcontact.optim.minimize`.  Contact members: ``CONVERGED``,
#: ``NO_CONTACT``, ``MAXITER``, ``NEWTON_FAILED``, ``NONFINITE``, ``PENALTY_LIMIT``,
#: ``NOT_VERIFIED``.
ContactStatus = Status


@dataclass(frozen=True)
class ContactIteration:
    """One outer iteration (one subproblem (S) and one multiplier update)."""

    k: int
    penetration: float  # max positive gap / h
    complementarity: float  # max |lambda g| / (p_ref h)
    multiplier_change: float  # max |lambda_new - lambda| / p_ref
    residual: float  # Newton residual of the subproblem (relative)
    newton_iterations: int
    eps_n: float
    active: int


@dataclass(frozen=True)
class ContactResult:
    """Solver outcome: status, counters and per-iteration history."""

    status: ContactStatus
    message: str
    algorithm: str
    penalty: str
    outer_iterations: int
    newton_iterations: int
    linear_solves: int
    factorizations: int
    penetration: float
    complementarity: float
    residual: float
    eps_n: float
    history: tuple[ContactIteration, ...] = ()

    @property
    def success(self) -> bool:
        return self.status > 0

    def raise_for_status(self) -> None:
        """Raise :class:`~alcontact.errors.ConvergenceError` unless converged."""
        if not self.success:
            raise ConvergenceError(f"contact solve failed ({self.status.label}): {self.message}")


@dataclass(frozen=True)
class ContactSolution:
    """Displacements and contact quantities of a solved contact problem.

    Attributes
    ----------
    u : ndarray (ndofs,)
        Displacement.
    points : ndarray (m, d)
        Contact-boundary points (reference positions).
    pressure : ndarray (m,)
        Contact pressure recovered from the nodal forces in the element's boundary
        space (:math:`r_i/w_i = \\lambda_i` except for 3D P2, see
        :meth:`~alcontact.fem.LinearElasticity.boundary_pressure`; 0 off the candidates).
    gap : ndarray (m,)
        Linearized gap (6.15) per point (<= 0 feasible).
    weights : ndarray (m,)
        Tributary lengths / areas.
    active : ndarray of bool (m,)
        Points in contact (positive pressure and closed gap).
    normals : ndarray (m, d)
        Obstacle normals at the points.
    total_contact_force : ndarray (d,)
        Resultant of the nodal contact forces on the body :math:`\\sum_i r_i \\nu_i`.
    result : ContactResult
    timings : dict
        ``setup_s``, ``factor_s``, ``linear_solve_s`` (one factor + solve), ``solve_s``, ``total_s``.
    nodal_forces : ndarray (m,), optional
        Normal nodal contact forces :math:`r_i = w_i \\lambda_i` the solver applied to
        the body (the exact discrete forces; ``pressure`` is the field recovered from
        them, :meth:`~alcontact.fem.LinearElasticity.boundary_pressure`). ``None``:
        ``weights * pressure``.

    Estimators (documented in :mod:`alcontact.contact.solution._estimators` and
    ``docs/estimators.md``): :attr:`normal_force` and :attr:`total_contact_force`
    sum the nodal forces; :attr:`peak_pressure` and :meth:`contact_half_width`
    come from least-squares Hertz fits when the problem's reference is a Hertz
    profile (``p0`` of the free fit, ``a`` of the load-matched fit), otherwise from
    the recovered pressure (largest value; outermost loaded point interpolated);
    :attr:`peak_pressure_nodal_max` is the raw largest nodal pressure;
    :meth:`equilibrium` checks the global force balance.
    """

    problem: Any
    u: np.ndarray
    points: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    weights: np.ndarray
    active: np.ndarray
    normals: np.ndarray
    total_contact_force: np.ndarray
    result: ContactResult
    timings: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)
    nodal_forces: np.ndarray | None = None
    #: the states of the accepted load steps, in order (:class:`ContactFrame`); the last one is this
    #: solution's own state. Empty when constructed by hand: one frame of this state is made.
    frames: tuple = field(default=(), repr=False, compare=False)
    #: the stepping engine's own record of a load-stepped run (``FiniteSolution``, ``FrictionSolution``,
    #: ``FiniteFrictionSolution``: what the deprecated wrappers return), ``None`` for one static solve
    record: Any = field(default=None, repr=False, compare=False)
    #: fitted Hertz profiles by (amplitude, center, axis): the fit costs a boundary
    #: quadrature and a scalar minimization, and a summary asks for p0 and a of each frame
    _fits: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        if len(self.frames) <= 1:
            # one state (a static solve, a one-step run, a copy made by dataclasses.replace): its own frame
            object.__setattr__(self, "frames", (frame_of(self),))

    @property
    def status(self) -> ContactStatus:
        return self.result.status

    @property
    def success(self) -> bool:
        return self.result.success

    def raise_for_status(self) -> None:
        """Raise :class:`~alcontact.errors.ConvergenceError` unless converged."""
        self.result.raise_for_status()

    @property
    def final(self) -> "ContactFrame":
        """The last accepted frame (this solution's state)."""
        return self.frames[-1]

    @property
    def times(self) -> np.ndarray:
        """Pseudo-time of every frame."""
        return np.array([f.t for f in self.frames])

    def frame_solutions(self) -> tuple["ContactSolution", ...]:
        """One :class:`ContactSolution` per frame (the last is this solution): the estimators, the
        equilibrium and the writers of one state, applied to every step."""
        return tuple(f.view for f in self.frames[:-1]) + (self,)

    # ------------------------------------------------------------ estimators
    @property
    def normal_nodal_forces(self) -> np.ndarray:
        """Normal nodal contact forces :math:`r_i` (``(m,)``)."""
        if self.nodal_forces is not None:
            return np.asarray(self.nodal_forces, dtype=float)
        return self.weights * self.pressure

    @property
    def normal_force(self) -> float:
        """Total normal contact force of the model :math:`\\sum_i r_i` (the forces the solver applied)."""
        return float(np.sum(self.normal_nodal_forces))

    def contact_point_forces(self) -> np.ndarray:
        """Contact force vectors on the body per point, ``(m, d)``: :math:`r_i\\nu_i` plus the
        tangential forces :math:`w_i\\,t_{T,i}` of a frictional state (``extra["shear"]``)."""
        f = self.normal_nodal_forces[:, None] * self.normals
        shear = self.extra.get("shear")
        if shear is not None:
            f = f + self.weights[:, None] * np.asarray(shear, dtype=float)
        return f

    def pair_contact_forces(self) -> np.ndarray:
        """Contact force on the body from each contact pair, ``(n_pairs, d)``.

        The sum of :meth:`contact_point_forces` over the stacked points of each pair
        (``problem.pair_of_points()``); one row, the total contact force, for one pair. A pair between
        two bodies reports the force on its slave body (``extra["slave_contact_force"]``: at finite
        deformation the mortar rows put part of it on the slave nodes' neighbours).
        """
        f = self.contact_point_forces()
        pairs = getattr(self.problem, "pairs", ())
        if len(pairs) == 1 and self.extra.get("slave_contact_force") is not None:
            return np.asarray([self.extra["slave_contact_force"]], dtype=float)
        if self.extra.get("pair_slave_contact_forces") is not None:  # several two-body pairs
            return np.asarray(self.extra["pair_slave_contact_forces"], dtype=float)
        owner = self.problem.pair_of_points() if len(pairs) > 1 else np.zeros(f.shape[0], dtype=np.int64)
        out = np.zeros((max(len(pairs), 1), f.shape[1]))
        np.add.at(out, owner, f)
        return out

    def equilibrium(self, problem=None):
        """Global equilibrium of this state, :func:`alcontact.contact.solution._estimators.equilibrium`.

        ``problem`` defaults to :attr:`problem`; pass the problem frozen at the
        state's load level for a stepped run (``problem_at(problem, history, t)``).
        """
        from ._estimators import equilibrium, nodal_force_vector

        prob = self.problem if problem is None else problem
        model = prob.model
        fixed, _ = prob.dirichlet()
        if "contact_force_points" in self.extra:
            # two bodies: the forces on the slave and master nodes balance with the loads and reactions (their
            # resultant is zero, action = reaction); the contact force reported is the one on the slave body
            dofs, forces = self.extra["contact_force_points"]
            fc = nodal_force_vector(model.ndofs, dofs, forces)
            eq = equilibrium(model, self.u, fixed, prob.load_vector(), fc, length=self.extra.get("h"))
            return dataclasses.replace(eq, contact_force=np.asarray(self.extra["slave_contact_force"], dtype=float))
        _, dofs = prob.slave_nodes()
        fc = nodal_force_vector(model.ndofs, dofs, self.contact_point_forces())
        return equilibrium(model, self.u, fixed, prob.load_vector(), fc, length=self.extra.get("h"))

    def _geometry(self, axis: int, center):
        meta = getattr(self.problem, "meta", None) or {}
        if center is None:
            center = meta.get("center")
        return axis, center

    def hertz_fit(self, center=None, axis: int = 0, *, amplitude: str = "free"):
        """Least-squares Hertz profile of the recovered pressure field in :math:`L^2(\\Gamma)`
        (:func:`~._estimators.fit_hertz_field`; at the points, :func:`~._estimators.fit_hertz`,
        for a body without ``boundary_field_at_quadrature``).

        Radii are measured from ``center`` (default ``problem.meta["center"]``; a
        coordinate in which the loaded zone lies on both sides of it is replaced by
        the force centroid, :func:`~._estimators.load_center`) in the contact plane
        (2D: along ``axis``); the weights are the tributary lengths/areas.
        ``amplitude="free"`` fits ``p0`` and ``a`` (its ``p0`` is :attr:`peak_pressure`);
        ``"load"`` fits ``a`` of the profile that carries the field's load (its ``a`` is
        :meth:`contact_half_width`). The fit is computed once per arguments and cached.
        """
        axis, center = self._geometry(axis, center)
        key = (amplitude, None if center is None else tuple(np.ravel(center).tolist()), int(axis))
        if key not in self._fits:
            self._fits[key] = self._hertz_fit(center, axis, amplitude)
        return self._fits[key]

    def _hertz_fit(self, center, axis: int, amplitude: str):
        from ._estimators import fit_hertz, fit_hertz_field

        data = self._fit_data(center, axis)
        if data[0] == "points":
            return fit_hertz(*data[1:])
        return fit_hertz_field(*data[1:], amplitude=amplitude)

    def _fit_data(self, center, axis: int):
        """Radii and pressure field the Hertz fits use (cached: shared by both fits)."""
        key = ("data", None if center is None else tuple(np.ravel(center).tolist()), int(axis))
        if key in self._fits:
            return self._fits[key]
        from ._estimators import load_center, normal_coordinate, radial_coordinate

        p = np.where(self.active, self.pressure, 0.0)
        center = load_center(self.points, np.where(self.active, self.normal_nodal_forces, 0.0), center)
        ax = axis if self.points.shape[1] == 2 else None
        flat = normal_coordinate(self.points, p > 0) if self.points.shape[1] == 3 else None
        r = radial_coordinate(self.points, center, ax, flat=flat)
        model = getattr(self.problem, "model", None)
        if not hasattr(model, "boundary_field_at_quadrature"):
            data = ("points", r, p, self.weights)
        else:
            loaded = p > 0
            near = r <= 2.0 * float(r[loaded].max()) if np.any(loaded) else None
            x, dx, v = model.boundary_field_at_quadrature(self.problem.contact_boundary, p, near=near)
            # the same in-plane radius at the quadrature points (flat direction from the nodes)
            data = ("field", _radius_like(self.points, x, center, ax, flat), dx, v, r, p)
        self._fits[key] = data
        return data

    def _uses_hertz_fit(self) -> bool:
        from ._estimators import has_hertz_profile

        return has_hertz_profile(self.problem) and bool(np.any(self.active & (self.pressure > 0)))

    def contact_half_width(self, axis: int = 0, center=None) -> float:
        """Half-width of the contact zone along coordinate ``axis`` (contact radius in 3D).

        Hertz problems (reference with a Hertz profile): ``a`` of the load-matched
        least-squares Hertz fit (:meth:`hertz_fit` with ``amplitude="load"``: the profile
        carries the load of the recovered field, the sum of the nodal forces). Otherwise the outermost loaded point
        interpolated along the boundary (:func:`~._estimators.edge_from_profile`):
        2D along the contact boundary; 3D along the line through ``center``
        parallel to ``axis`` in the contact plane (e.g. a symmetry line).
        """
        if self._uses_hertz_fit():
            return float(self.hertz_fit(center=center, axis=axis, amplitude="load").a)
        return self.contact_half_width_edge(axis=axis, center=center)

    def contact_half_width_edge(self, axis: int = 0, center=None) -> float:
        """Outermost loaded point along ``axis`` interpolated to the contact edge (no fit)."""
        from ._estimators import edge_from_profile

        pts = self.points
        d = pts.shape[1]
        c = np.zeros(d) if center is None else np.asarray(center, dtype=float)
        if c.size < d:
            c = np.concatenate([c, np.zeros(d - c.size)])
        on_line = np.ones(pts.shape[0], bool)
        if d == 3:
            # points on the line through c along `axis`, within the contact plane
            other = [k for k in range(d) if k != axis]
            spread = np.ptp(pts, axis=0)
            flat = int(np.argmin(spread))  # normal direction of the (flat) contact boundary
            lateral = [k for k in other if k != flat][0]
            on_line = np.abs(pts[:, lateral] - c[lateral]) <= 1e-9 * max(spread.max(), 1e-300)
        r = np.abs(pts[on_line, axis] - c[axis])
        return edge_from_profile(r, self.pressure[on_line], self.active[on_line])

    @property
    def peak_pressure(self) -> float:
        """Peak contact pressure: ``p0`` of the (free) Hertz fit for Hertz problems, else the
        largest recovered pressure (:attr:`peak_pressure_nodal_max`)."""
        if self._uses_hertz_fit():
            return float(self.hertz_fit().p0)
        return self.peak_pressure_nodal_max

    @property
    def peak_pressure_nodal_max(self) -> float:
        """Largest nodal value of the recovered pressure (raw, no fit)."""
        return float(np.max(self.pressure, initial=0.0))


@dataclass(frozen=True)
class ContactFrame:
    r"""State of one accepted load step of a contact solve (one frame for a static solve).

    Every array is over the ``m`` contact-boundary points; vectors have global components.

    Attributes
    ----------
    t : float
        Pseudo-time of the step (1 for a static solve).
    requested : bool
        ``t`` is a requested step time; ``False`` for a sub-step a cut-back inserted.
    u : ndarray (ndofs,)
        Displacement.
    pressure : ndarray (m,)
        Normal traction :math:`t_N \ge 0`.
    gap : ndarray (m,)
        Gap, :math:`g_N \le 0` means no penetration (linearized (6.15) at small deformation,
        current configuration at finite deformation).
    normals : ndarray (m, d)
        Obstacle normals at the points (current projections at finite deformation).
    traction_t : ndarray (m, d)
        Tangential traction on the body, **global** components (the one convention of every
        solve; zeros without friction). The tangential force of point :math:`i` is
        :math:`w_i\,t_{T,i}`. The frictional solvers' local tangent-basis components
        (``FrictionStep.traction_t``, :math:`(m, d-1)`, dissertation sign) map to it by
        :math:`-T\,t_T`.
    slip : ndarray (m, d)
        Slip increment of the step at closed points (zeros without friction).
    slip_total : ndarray (m, d)
        Slip accumulated over the steps so far.
    state : ndarray of int (m,)
        ``OPEN`` (0), ``STICK`` (1), ``SLIP`` (2) of :mod:`alcontact.contact.laws._coulomb`; without
        friction a closed point slides freely: ``SLIP`` where active, else ``OPEN``.
    contact_force : ndarray (d,)
        Resultant of all contact forces on the body (normal and tangential).
    normal_force : float
        :math:`\sum_i w_i t_{N,i}` (the nodal forces the solver applied).
    tangential_force : ndarray (d,)
        Resultant of the tangential forces on the body (zeros without friction).
    status : ContactStatus
    message : str
    newton_iterations, outer_iterations, linear_solves, cutbacks : int
        Counters of the step (``cutbacks``: failed tries before it was accepted).
    seconds : float
        Wall time of the step (failed tries included).
    view : ContactSolution
        The step's state as a :class:`ContactSolution` (estimators, :meth:`~ContactSolution.equilibrium`
        with the step's loads, the writers).
    """

    t: float
    requested: bool
    u: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    normals: np.ndarray
    traction_t: np.ndarray
    slip: np.ndarray
    slip_total: np.ndarray
    state: np.ndarray
    contact_force: np.ndarray
    normal_force: float
    tangential_force: np.ndarray
    status: ContactStatus
    message: str
    newton_iterations: int
    outer_iterations: int
    linear_solves: int
    cutbacks: int
    seconds: float
    view: Any = field(repr=False, compare=False)

    @property
    def rigid_bodies(self) -> dict:
        """Pose, contact force and moment, applied load and reaction of every rigid body at this step,
        ``{name: state}`` (:func:`~alcontact.contact.solution._rigid.rigid_body_results`; empty without one)."""
        return dict(self.view.extra.get("rigid_bodies", {})) if self.view is not None else {}

    @property
    def force(self) -> np.ndarray:
        """``contact_force`` (the name of the step records)."""
        return self.contact_force

    @property
    def reaction_force(self) -> np.ndarray:
        """Resultant of the support reactions :math:`R` of this step (:meth:`ContactSolution.equilibrium`)."""
        return np.asarray(self.view.equilibrium().reaction, dtype=float)

    @property
    def success(self) -> bool:
        return self.status > 0

    @property
    def pair_forces(self) -> np.ndarray:
        """Contact force on the body from each contact pair at this step, ``(n_pairs, d)``
        (:meth:`ContactSolution.pair_contact_forces`)."""
        return self.view.pair_contact_forces()


def frame_of(sol: ContactSolution) -> ContactFrame:
    """The :class:`ContactFrame` of one state (the one place a frame is made).

    Reads the typed fields of ``sol`` and the per-step keys its builder put in ``extra``
    (``t``, ``requested``, ``shear``, ``slip``, ``slip_increment``, ``state``,
    ``tangential_force``, ``cutbacks``, ``seconds``, ``step_newton_iterations``,
    ``step_outer_iterations``, ``step_linear_solves``: a run's result holds its totals).
    """
    from ..laws._coulomb import OPEN, SLIP

    ex = sol.extra
    m, d = np.shape(sol.points)
    zeros = np.zeros((m, d))
    state = ex.get("state")
    if state is None:
        state = np.where(np.asarray(sol.active, dtype=bool), SLIP, OPEN)
    res = sol.result
    return ContactFrame(
        t=float(ex.get("t", 1.0)), requested=bool(ex.get("requested", True)), u=sol.u, pressure=sol.pressure,
        gap=sol.gap, normals=sol.normals, traction_t=np.asarray(ex.get("shear", zeros), dtype=float),
        slip=np.asarray(ex.get("slip_increment", zeros), dtype=float),
        slip_total=np.asarray(ex.get("slip", zeros), dtype=float), state=np.asarray(state, dtype=int),
        contact_force=np.asarray(sol.total_contact_force, dtype=float), normal_force=sol.normal_force,
        tangential_force=np.asarray(ex.get("tangential_force", np.zeros(d)), dtype=float), status=res.status,
        message=res.message, newton_iterations=int(ex.get("step_newton_iterations", res.newton_iterations)),
        outer_iterations=int(ex.get("step_outer_iterations", res.outer_iterations)),
        linear_solves=int(ex.get("step_linear_solves", res.linear_solves)), cutbacks=int(ex.get("cutbacks", 0)),
        seconds=float(ex.get("seconds", sol.timings.get("total_s", float("nan")))), view=sol)


def _radius_like(points, x, center, axis, flat=None):
    """In-plane radius of ``x`` measured as :func:`radial_coordinate` measures ``points``."""
    from ._estimators import radial_coordinate

    pts = np.asarray(points, dtype=float)
    # append the nodes so that the flat direction is decided by the same point cloud
    r = radial_coordinate(np.vstack([x, pts]), center, axis, flat=flat)
    return r[: x.shape[0]]
