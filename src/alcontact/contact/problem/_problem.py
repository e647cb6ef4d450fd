"""The contact problem as data: bodies, contact pairs (slave boundary, master), supports, loads.

A :class:`ContactProblem` holds no solver state; :func:`alcontact.contact.solve`
turns it into a discrete problem and runs one of the registered algorithms.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from ...errors import InputError, UnknownNameError
from ...fem.mixed import MixedHyperelastic
from ..masters._master import Master


#: Contact kinematics a problem can ask for (see :class:`ContactProblem`)
KINEMATICS = {
    "small": "small deformation: linearized gap (6.15) at the reference configuration, condensed solve",
    "finite": "finite deformation: gap at x = X + u, load steps, full-space Newton (needs a nonlinear body)",
}


def _numbers(value: Any) -> bool:
    """A finite real number or a non-empty 1-D list of them (not a bool, not a string)."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        return False
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return False
    return a.ndim <= 1 and a.size >= 1 and bool(np.all(np.isfinite(a))) and a.dtype != object


def _is_real(value: Any) -> bool:
    return _numbers(value) and np.ndim(value) == 0


def _bad(kind: str, field_: str, value: Any, want: str) -> InputError:
    try:  # not alcontact._options.show: that module imports this one
        text = repr(value) if not (isinstance(value, int) and abs(value) > 10**40) else "<a huge integer>"
    except (RecursionError, ValueError):
        text = f"<{type(value).__name__}>"
    text = text if len(text) <= 60 else text[:57] + "..."
    return InputError(f"{kind}: {field_} = {text}: expected {want}, got {type(value).__name__}.")


def _check_boundary(kind: str, boundary: Any) -> None:
    if not isinstance(boundary, str):
        raise _bad(kind, "boundary", boundary, "the name of a boundary of the mesh (a string), e.g. 'top'")


@dataclass(frozen=True)
class Support:
    """Dirichlet condition ``u_c = value`` on a named boundary.

    Parameters
    ----------
    boundary : str
        Boundary name of the mesh.
    components : sequence of int, optional
        Displacement components (0 = x, 1 = y, 2 = z); ``None`` = all. On a rigid body
        (:class:`~alcontact.contact.RigidBody`) the components of its pose: the translation
        ``0 .. d-1``, then the rotation (2D: 2; 3D: 3, 4, 5 about x, y, z).
    value : float or callable
        Prescribed value, or ``x -> (dim, m)`` array.
    """

    boundary: str
    components: tuple[int, ...] | None = None
    value: float | Callable[..., Any] = 0.0

    def __post_init__(self) -> None:
        _check_boundary("Support", self.boundary)
        comps = self.components
        if comps is not None and (isinstance(comps, (str, bytes, bool)) or not np.iterable(comps) or not all(
                isinstance(c, (int, np.integer)) and not isinstance(c, bool) and 0 <= c <= 5 for c in comps)):
            raise _bad("Support", "components", comps, "None (all) or a list of components 0, 1, 2 (a rigid body: "
                                                        "0 .. 5, translation then rotation), e.g. [0]")
        if not (callable(self.value) or _numbers(self.value)):
            raise _bad("Support", "value", self.value, "a finite number, a list of them (one per component) or "
                                                      "a callable x -> (dim, m) array")


@dataclass(frozen=True)
class Traction:
    """Surface traction vector (force per unit area) on a named boundary."""

    boundary: str
    vector: tuple[float, ...] | Callable[..., Any]

    def __post_init__(self) -> None:
        _check_boundary("Traction", self.boundary)
        if not (callable(self.vector) or (_numbers(self.vector) and np.ndim(self.vector) == 1)):
            raise _bad("Traction", "vector", self.vector, "a list of finite numbers (one per direction) or a "
                                                          "callable x -> (dim, m) array")


@dataclass(frozen=True, init=False)
class RigidLoad(Traction):
    r"""A force and a moment on the reference point of a rigid body (:class:`~alcontact.contact.RigidBody`).

    The rigid body's pose components that no :class:`Support` prescribes are unknowns of the
    contact problem; this load is what drives them. ``vector`` is the generalized force
    :math:`(F, M)`: 2D :math:`(F_x, F_y, M_z)`, 3D :math:`(F_x, F_y, F_z, M_x, M_y, M_z)`, the
    moment about the reference point (counter-clockwise positive in 2D).

    Parameters
    ----------
    boundary : str
        The rigid body's name in the bodies (``"body1"``, or ``"body1/reference"``).
    vector : sequence of float, optional
        :math:`(F, M)` at once; or give ``force`` (d numbers) and ``moment`` (2D: a number,
        3D: 3 numbers, default zero).

    Examples
    --------
    >>> RigidLoad("body1", force=[0.0, -100.0], moment=2.5).vector
    (0.0, -100.0, 2.5)
    """

    def __init__(self, boundary: str, vector: Any = None, *, force: Any = None, moment: Any = None) -> None:
        if vector is None:
            if force is None or not _numbers(force) or np.ndim(force) != 1 or np.size(force) not in (2, 3):
                raise _bad("RigidLoad", "force", force, "the force on the reference point, 2 or 3 numbers")
            d = int(np.size(force))
            mom = np.zeros(1 if d == 2 else 3) if moment is None else moment
            if not _numbers(mom) or np.size(mom) != (1 if d == 2 else 3):
                raise _bad("RigidLoad", "moment", moment, "a number (2D) or 3 numbers (3D): the moment about the "
                                                          "reference point")
            vector = tuple(float(x) for x in np.concatenate([np.ravel(force), np.ravel(mom)]))
        elif force is not None or moment is not None:
            raise InputError("RigidLoad: give vector = (F, M) or force= and moment=, not both.")
        elif not callable(vector) and _numbers(vector):
            vector = tuple(float(x) for x in np.ravel(vector))
        object.__setattr__(self, "boundary", boundary)
        object.__setattr__(self, "vector", vector)
        self.__post_init__()


@dataclass(frozen=True)
class Pressure:
    """Normal pressure on a named boundary; positive pushes into the body."""

    boundary: str
    value: float

    def __post_init__(self) -> None:
        _check_boundary("Pressure", self.boundary)
        if not (callable(self.value) or _is_real(self.value)):
            raise _bad("Pressure", "value", self.value, "a finite number (positive pushes into the body) or a "
                                                        "callable x -> (m,) array")


@dataclass(frozen=True)
class BodyForce:
    """Body force density (force per unit volume)."""

    vector: tuple[float, ...] | Callable[..., Any]

    def __post_init__(self) -> None:
        if not (callable(self.vector) or (_numbers(self.vector) and np.ndim(self.vector) == 1)):
            raise _bad("BodyForce", "vector", self.vector, "a list of finite numbers (one per direction) or a "
                                                           "callable x -> (dim, m) array")


#: Where a refusal of what is not supported yet points the user (the pieces and the plan for a second body).
ROADMAP = "docs/architecture.md, section 'Add a second body'"


def _is_body(value: Any) -> bool:
    """A discretized body: what :class:`ContactProblem` needs from ``model`` (not a class check: any fem body)."""
    return hasattr(value, "facets") and hasattr(value, "dim") and hasattr(value, "ndofs")


def _is_obstacle(value: Any) -> bool:
    """A master as :class:`ContactProblem` has accepted it since the first release: it evaluates and checks its dimension."""
    return hasattr(value, "evaluate") and hasattr(value, "check_dim")


_BODY_WANT = "a discretized body: alcontact.fem.LinearElasticity(mesh, material) or a hyperelastic alcontact.fem.Body"
_MASTER_WANT = ("a rigid obstacle (an alcontact.contact.Master), e.g. alcontact.contact.obstacles.make('half-space', "
                "point=..., normal=...)")


def _check_friction(kind: str, friction: Any) -> None:
    """A Coulomb coefficient: a finite real number ``>= 0`` (the two messages of :class:`ContactProblem`)."""
    if not _is_real(friction) or abs(float(friction)) > 1e100:
        raise _bad(kind, "friction", friction, "a finite number in [0, 1e100] (0 = frictionless)")
    if not np.isfinite(friction) or friction < 0:
        raise InputError(f"friction coefficient must be >= 0; got {friction!r}. Use 0 for frictionless contact.")


@dataclass(frozen=True)
class Boundary:
    """A named boundary of a discretized body: the slave side of a :class:`ContactPair`.

    Parameters
    ----------
    body : alcontact.fem.LinearElasticity or alcontact.fem.Body
        The discretized body.
    name : str
        One of the body's boundary names (checked against the mesh by
        :class:`ContactProblem`, whose error lists the known names).

    Examples
    --------
    >>> from alcontact.problems import hertz
    >>> body = hertz.hertz_2d(level=0).model
    >>> Boundary(body, "top").name
    'top'
    """

    body: Any
    name: str

    def __post_init__(self) -> None:
        if not _is_body(self.body):
            raise _bad("Boundary", "body", self.body, _BODY_WANT)
        if not isinstance(self.name, str):
            raise _bad("Boundary", "name", self.name, "the name of a boundary of the body's mesh (a string), e.g. "
                                                      "'bottom'")


@dataclass(frozen=True)
class ContactPair:
    r"""Points of a body's boundary (the slave) that must not penetrate a master: :math:`g_N \le 0` (6.15).

    Parameters
    ----------
    slave : Boundary
        The candidate contact boundary :math:`\Gamma` of a body (its nodes or quadrature
        points are the contact points).
    master : Master
        What the slave points are measured against: a rigid obstacle of
        :mod:`alcontact.contact.obstacles` (any object satisfying :class:`~alcontact.contact.Master`,
        or the older :class:`~alcontact.contact.obstacles.Obstacle` protocol, which is rigid),
        or a boundary of another body, :class:`~alcontact.contact.BodySurface` (deformable:
        ``master.rigid`` false; two-body mortar contact).
    friction : float
        Coulomb coefficient :math:`\mu \ge 0` of the pair (0 = frictionless).

    Examples
    --------
    >>> from alcontact.contact import obstacles
    >>> from alcontact.problems import hertz
    >>> body = hertz.hertz_2d(level=0).model
    >>> pair = ContactPair(Boundary(body, "top"), obstacles.make("half-space", point=[0, 0], normal=[0, 1]))
    >>> pair.master.rigid, pair.friction
    (True, 0.0)
    """

    slave: Boundary
    master: Any
    friction: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.slave, Boundary):
            raise _bad("ContactPair", "slave", self.slave, "a body's boundary, alcontact.contact.Boundary(body, "
                                                           "'contact')")
        if not _is_obstacle(self.master):
            raise _bad("ContactPair", "master", self.master, _MASTER_WANT)
        _check_friction("ContactPair", self.friction)

    @property
    def rigid(self) -> bool:
        """``True`` when the master does not move with the unknowns (every master before two-body contact)."""
        return bool(self.master.rigid) if isinstance(self.master, Master) else True


class _Unset:
    """Marker of a shorthand argument that was not given (``None`` is a value the checks refuse)."""

    def __repr__(self) -> str:
        return "<from bodies and pairs>"


_UNSET: Any = _Unset()


def _sequence(kind: str, name: str, items: Any, single: Callable[[Any], bool], example: str) -> tuple[Any, ...]:
    """``items`` as a tuple; an :class:`InputError` naming ``name`` for a non-list (``single`` item) or an empty one."""
    if single(items):
        raise InputError(f"{kind}: {name} = {type(items).__name__}(...): expected a list; wrap the single item in "
                         f"a list, e.g. {name}={example}.")
    if isinstance(items, (str, bytes, dict, np.ndarray)) or not np.iterable(items):
        raise _bad(kind, name, items, f"a non-empty list, e.g. {example}")
    out = tuple(items)
    if not out:
        raise InputError(f"{kind}: {name} = []: expected at least one item, e.g. {name}={example}.")
    return out


@dataclass(frozen=True, init=False)
class ContactProblem:
    """Bodies and contact pairs, supports and loads (small deformation, ch. 6.2, or finite deformation).

    Two equivalent ways to build one:

    - the pair form ``ContactProblem(bodies=[body], pairs=[ContactPair(Boundary(body, "contact"),
      obstacle, friction=mu)], supports=..., loads=...)``;
    - the single-body shorthand ``ContactProblem(model, obstacle, contact_boundary, supports=...,
      loads=..., friction=mu)``, which builds that one body and that one pair.

    Both give the same problem (and the same solution, to the last bit). A problem has one
    body with one or several pairs, each its own slave boundary, rigid master and Coulomb
    coefficient (their contact points are stacked in the pairs' order, one constraint per
    slave point and pair: :meth:`slave_nodes`; at finite deformation: frictionless, fixed
    masters); or several bodies joined by pairs whose master is the
    :class:`~alcontact.contact.BodySurface` of a body of ``bodies`` (two-body mortar contact
    at small deformation, frictionless or with Coulomb friction, 2D P1/P2), beside which
    pairs with rigid masters may act on any of the bodies; the model is then the bodies'
    :class:`~alcontact.fem.MultiBody` and boundary names are ``"body0/top"``,
    ``"body1/bottom"``, ... Frictional pairs at finite deformation and two-body pairs at
    finite deformation are refused with an :class:`~alcontact.errors.InputError` (see
    ``docs/architecture.md``).

    Parameters
    ----------
    model : alcontact.fem.LinearElasticity or alcontact.fem.Body, optional
        Shorthand: the one discretized body.
    obstacle : Master, optional
        Shorthand: the rigid obstacle (see :mod:`alcontact.contact.obstacles`), master of the pair.
    contact_boundary : str, optional
        Shorthand: name of the candidate contact boundary :math:`\\Gamma` of ``model``, slave of the pair.
    supports : sequence of Support
    loads : sequence of Traction, Pressure or BodyForce
    friction : float, optional
        Shorthand: Coulomb coefficient of the pair (default 0 = frictionless).
    name : str
        Label used in reports.
    reference : object, optional
        Analytical reference (e.g. :class:`alcontact.problems.hertz.HertzReference`).
    meta : dict, optional
    kinematics : {"small", "finite"}
        ``"small"`` (default): linearized gap (6.15). ``"finite"``: gap at the current
        position, solved in load steps by :func:`alcontact.contact.solve`; needs a
        geometrically nonlinear body (a hyperelastic one), a linear body is refused.
    bodies : sequence, keyword-only
        Pair form: the discretized bodies (one, or two or more joined by a pair with a
        :class:`~alcontact.contact.BodySurface` master).
    pairs : sequence of ContactPair, keyword-only
        Pair form: the contact pairs on the body.

    Attributes
    ----------
    bodies : tuple
    pairs : tuple of ContactPair
    model, obstacle, contact_boundary, friction
        Views of the one body and the first pair: ``bodies[0]``, ``pairs[0].master`` (with
        several pairs, the :class:`~alcontact.contact.masters.StackedMaster` of all of them),
        ``pairs[0].slave.name``, ``pairs[0].friction`` (each pair has its own: :meth:`point_friction`).

    Notes
    -----
    Given with ``bodies`` and ``pairs`` (as :func:`dataclasses.replace` does), a shorthand
    argument replaces that part of the one body or pair:
    ``dataclasses.replace(problem, obstacle=other)`` swaps the master of the pair.

    Examples
    --------
    >>> from alcontact.contact import obstacles
    >>> from alcontact.problems import hertz
    >>> short = hertz.hertz_2d(level=0)
    >>> pair = ContactPair(Boundary(short.model, "top"), short.obstacle)
    >>> full = ContactProblem(bodies=[short.model], pairs=[pair], supports=short.supports, loads=short.loads)
    >>> full.model is short.model, full.contact_boundary
    (True, 'top')
    """

    bodies: tuple[Any, ...]
    pairs: tuple[ContactPair, ...]
    supports: Sequence[Support] = ()
    loads: Sequence[Any] = ()
    name: str = "contact"
    reference: Any = None
    meta: dict = field(default_factory=dict)
    kinematics: str = "small"

    def __init__(self, model: Any = _UNSET, obstacle: Any = _UNSET, contact_boundary: Any = _UNSET,
                 supports: Sequence[Support] = (), loads: Sequence[Any] = (), friction: Any = _UNSET,
                 name: str = "contact", reference: Any = None, meta: Any = _UNSET, kinematics: str = "small",
                 *, bodies: Any = None, pairs: Any = None) -> None:
        given = {k: v for k, v in (("model", model), ("obstacle", obstacle), ("contact_boundary", contact_boundary),
                                   ("friction", friction)) if v is not _UNSET}
        if bodies is None and pairs is None:
            missing = [k for k in ("model", "obstacle", "contact_boundary") if k not in given]
            if missing:
                raise InputError(f"ContactProblem: missing {', '.join(missing)}: give ContactProblem(model, obstacle, "
                                 "contact_boundary, ...) or ContactProblem(bodies=[body], pairs=[ContactPair("
                                 "Boundary(body, 'contact'), obstacle)], ...).")
            base = {"friction": 0.0}
        else:
            base = self._from_pairs(bodies, pairs)
        raw = {**base, **given}
        object.__setattr__(self, "supports", supports)
        object.__setattr__(self, "loads", loads)
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "reference", reference)
        object.__setattr__(self, "meta", {} if meta is _UNSET else meta)
        object.__setattr__(self, "kinematics", kinematics)
        self._check_types(raw)
        self._check_kinematics(raw["model"])
        old = base.get("pair")
        if old is not None and all(raw[k] is base[k] for k in ("model", "obstacle", "contact_boundary", "friction")):
            pair = old  # nothing replaced: keep the caller's pair
        else:
            pair = ContactPair(Boundary(raw["model"], raw["contact_boundary"]), raw["obstacle"], raw["friction"])
        others = tuple(base.get("others", ()))
        if others and raw["friction"] is not base["friction"]:
            raise InputError("ContactProblem: friction given with several pairs: set the coefficient of each "
                             "ContactPair(..., friction=mu) instead.")
        if "bodies" in base:  # several bodies (a deformable master): the model is their stack
            if any(k in given for k in ("model", "contact_boundary")):
                raise InputError("ContactProblem: model or contact_boundary given with several bodies; give the "
                                 "bodies and pairs only.")
            object.__setattr__(self, "_model", raw["model"])
            object.__setattr__(self, "_contact_boundary", raw["contact_boundary"])
            object.__setattr__(self, "bodies", base["bodies"])
        else:
            object.__setattr__(self, "bodies", (raw["model"],))
        object.__setattr__(self, "pairs", (pair,) + others)
        self._validate()
        object.__setattr__(self, "_stacked", self._stack())

    @staticmethod
    def _from_pairs(bodies: Any, pairs: Any) -> dict[str, Any]:
        """The one body and pair of the pair form; a clear refusal of what is not supported yet."""
        kind = "ContactProblem"
        for name, value, other in (("bodies", bodies, "pairs"), ("pairs", pairs, "bodies")):
            if value is None:
                raise InputError(f"{kind}: {other} given without {name}: the pair form needs both, "
                                 "ContactProblem(bodies=[body], pairs=[ContactPair(Boundary(body, 'contact'), "
                                 "obstacle)], ...).")
        bodies = _sequence(kind, "bodies", bodies, _is_body, "[body]")
        for i, b in enumerate(bodies):
            if not _is_body(b):
                raise _bad(kind, f"bodies[{i}]", b, _BODY_WANT)
        pairs = _sequence(kind, "pairs", pairs, lambda p: isinstance(p, ContactPair),
                          "[ContactPair(Boundary(body, 'contact'), obstacle)]")
        for i, p in enumerate(pairs):
            if not isinstance(p, ContactPair):
                raise _bad(kind, f"pairs[{i}]", p, "a ContactPair(slave=Boundary(body, name), master=obstacle)")
        if len(bodies) > 1 and all(p.rigid for p in pairs):
            raise InputError(f"{kind}: bodies has {len(bodies)} bodies but no pair joins two of them: give a pair "
                             "whose master is a boundary of another body, ContactPair(Boundary(a, 'bottom'), "
                             f"BodySurface(b, 'top')). See {ROADMAP}.")
        if len(bodies) > 1 or not all(p.rigid for p in pairs):
            for i, pair in enumerate(pairs):
                if not any(pair.slave.body is b for b in bodies):
                    raise InputError(f"{kind}: pairs[{i}].slave is the boundary {pair.slave.name!r} of a body that is "
                                     "not in bodies; build it as Boundary(body, name) with a body of bodies.")
            return _two_body(kind, bodies, pairs)
        for i, pair in enumerate(pairs):
            if pair.slave.body is not bodies[0]:
                raise InputError(f"{kind}: pairs[{i}].slave is the boundary {pair.slave.name!r} of a body that is not "
                                 "in bodies; build it as Boundary(body, name) with a body of bodies.")
        pair = pairs[0]
        return {"model": bodies[0], "obstacle": pair.master, "contact_boundary": pair.slave.name,
                "friction": pair.friction, "pair": pair, "others": pairs[1:]}

    # ------------------------------------------------------------ views of the one body and pair
    @property
    def model(self) -> Any:
        """The discretized body: ``bodies[0]``; with several bodies their :class:`~alcontact.fem.MultiBody`."""
        return self.__dict__.get("_model", self.bodies[0])

    @property
    def obstacle(self) -> Any:
        """The rigid obstacle, master of the contact pair: ``pairs[0].master``.

        With several pairs, the master of the stacked contact points
        (:class:`~alcontact.contact.masters._stacked.StackedMaster`: each pair's block of
        points against that pair's master).
        """
        if len(self.pairs) == 1:
            return self.pairs[0].master
        return self._stacked[2]

    # ------------------------------------------------------------ the stacked contact points of all pairs
    def _stack(self):
        """Points, DOFs and weights of every pair's slave boundary, stacked in the pairs' order; their master."""
        if len(self.pairs) == 1:
            return None
        from ..masters._stacked import StackedMaster

        nodes = [self.model.node_dofs(self.slave_name(p)) for p in self.pairs]
        pts = np.concatenate([n[0] for n in nodes])
        dofs = np.concatenate([n[1] for n in nodes])
        sizes = [n[0].shape[0] for n in nodes]
        return pts, dofs, StackedMaster([p.master for p in self.pairs], sizes)

    def slave_nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """Contact points ``(points (m, d), dofs (m, d))`` of all pairs, stacked in the pairs' order.

        One pair: ``model.node_dofs(contact_boundary)``. Several pairs: the points of
        ``pairs[0].slave``, then those of ``pairs[1].slave``, ... (one constraint per slave
        point and pair; :meth:`pair_of_points` gives the pair of each).
        """
        if len(self.pairs) == 1:
            return self.model.node_dofs(self.contact_boundary)
        return self._stacked[0].copy(), self._stacked[1].copy()

    def slave_weights(self) -> np.ndarray:
        """Tributary length/area of each stacked contact point (:meth:`slave_nodes` order)."""
        if len(self.pairs) == 1:
            return self.model.boundary_weights(self.contact_boundary)
        return np.concatenate([self.model.boundary_weights(self.slave_name(p)) for p in self.pairs])

    def slave_pressure(self, forces: Any) -> np.ndarray:
        """Pressure at the stacked contact points from their nodal normal forces (per pair's boundary)."""
        if len(self.pairs) == 1:
            return self.model.boundary_pressure(self.contact_boundary, forces)
        forces = np.asarray(forces, dtype=float)
        b = self._stacked[2].bounds
        return np.concatenate([self.model.boundary_pressure(self.slave_name(p), forces[b[k]:b[k + 1]])
                               for k, p in enumerate(self.pairs)])

    def slave_name(self, pair: ContactPair) -> str:
        """The name of ``pair``'s slave boundary in :attr:`model` (qualified by its body's name between several
        bodies: ``"body1/bottom"``)."""
        if len(self.bodies) > 1:
            return self.model.qualify(pair.slave.body, pair.slave.name)
        return pair.slave.name

    def pair_of_points(self) -> np.ndarray:
        """Index of the pair of each stacked contact point, shape ``(m,)`` (all 0 for one pair)."""
        if len(self.pairs) == 1:
            return np.zeros(self.model.node_dofs(self.contact_boundary)[0].shape[0], dtype=np.int64)
        return self._stacked[2].owner.copy()

    def point_friction(self) -> np.ndarray:
        """Coulomb coefficient of each stacked contact point: its pair's ``friction``, shape ``(m,)``."""
        return np.asarray([float(p.friction) for p in self.pairs])[self.pair_of_points()]

    @property
    def contact_boundary(self) -> str:
        """Name of the candidate contact boundary of the body, slave of the pair: ``pairs[0].slave.name``
        (with several bodies, qualified by the slave body's name in :attr:`model`: ``"body0/bottom"``)."""
        return self.__dict__.get("_contact_boundary", self.pairs[0].slave.name)

    @property
    def friction(self) -> float:
        """Coulomb coefficient of the contact pair: ``pairs[0].friction`` (several pairs: :meth:`point_friction`)."""
        return self.pairs[0].friction

    def _check_kinematics(self, model: Any) -> None:
        """A known kinematics, and finite deformation only with a geometrically nonlinear body."""
        if self.kinematics not in KINEMATICS:
            raise UnknownNameError("kinematics", self.kinematics, list(KINEMATICS))
        if self.kinematics == "finite" and getattr(model, "linear", False):
            raise InputError(
                f"kinematics='finite' needs a geometrically nonlinear body; got {type(model).__name__} "
                "(linear, small strains: a finite-deformation gap with it is not finite deformation). "
                "Use a hyperelastic body (alcontact.fem.hyperelastic) or kinematics='small'."
            )
        if self.kinematics == "small" and isinstance(model, MixedHyperelastic):
            raise InputError(
                "kinematics='small' needs a body with a linear stiffness; a MixedHyperelastic (mixed u-p) body "
                "has a nonlinear residual with its pressure unknowns and runs at finite deformation only: use "
                "kinematics='finite' (or a LinearElasticity body for small deformation)."
            )
        if self.kinematics == "small" and getattr(model, "linear", True) is False:
            # the small-deformation solvers take the body's stiffness as constant: with a hyperelastic body
            # the returned state would fail its equilibrium check (status NOT_VERIFIED) after the whole solve
            raise InputError(
                f"kinematics='small' needs a body with a linear stiffness; got {type(model).__name__} (geometrically "
                "nonlinear). Use kinematics='finite' with it, or a LinearElasticity body for small deformation."
            )

    def _validate(self) -> None:
        """Values that need the mesh: boundary names, dimensions, supports."""
        # MeshError naming the known boundaries (one pair: the model's name of it, qualified by its body between
        # two bodies; several pairs are on one body)
        for name in [self.contact_boundary] if len(self.pairs) == 1 else [self.slave_name(p) for p in self.pairs]:
            self.model.facets(name)
        if self.kinematics != "small" and not all(p.rigid for p in self.pairs):
            if any(p.rigid for p in self.pairs):
                raise InputError(f"ContactProblem: {len(self.pairs)} contact pairs at kinematics={self.kinematics!r}, one "
                                 "between two bodies beside pairs with rigid obstacles: not supported yet at finite "
                                 "deformation; give pairs between bodies only, or kinematics='small'.")
            if any(p.friction > 0 for p in self.pairs):
                raise InputError(f"ContactProblem: friction between two deformable bodies at kinematics="
                                 f"{self.kinematics!r} is not supported yet; use friction = 0, or kinematics='small'.")
        if len(self.pairs) > 1 and self.kinematics != "small" and any(p.friction > 0 for p in self.pairs):
            raise InputError(f"ContactProblem: {len(self.pairs)} contact pairs with friction at kinematics="
                             f"{self.kinematics!r}: several frictional pairs are supported at small deformation only "
                             "so far; use kinematics='small', friction 0, or one pair.")
        for s in self.supports:
            self.model.facets(s.boundary)
        for ld in self.loads:
            if hasattr(ld, "boundary"):
                self.model.facets(ld.boundary)
        for p in self.pairs:
            p.master.check_dim(self.model.dim)
        self.dirichlet()  # InputError on two supports prescribing different values to one DOF

    def _check_types(self, raw: dict[str, Any]) -> None:
        """Wrong types of the fields: an :class:`InputError` naming the field and the fix (not an AttributeError)."""
        kind = "ContactProblem"
        if not _is_body(raw["model"]):
            raise _bad(kind, "model", raw["model"], _BODY_WANT)
        if not _is_obstacle(raw["obstacle"]):
            raise _bad(kind, "obstacle", raw["obstacle"], "a rigid obstacle, e.g. alcontact.contact.obstacles."
                                                          "make('half-space', point=..., normal=...)")
        if not isinstance(raw["contact_boundary"], str):
            raise _bad(kind, "contact_boundary", raw["contact_boundary"], "the name of a boundary of the mesh")
        for name, items, types, example in (("supports", self.supports, (Support,), "[Support('bottom')]"),
                                            ("loads", self.loads, (Traction, Pressure, BodyForce),
                                             "[Pressure('top', 1.0)]")):
            if isinstance(items, types):
                raise InputError(f"{kind}: {name} = {type(items).__name__}(...): expected a list; wrap the single "
                                 f"item in a list, e.g. {name}={example}.")
            if isinstance(items, (str, bytes, dict, np.ndarray)) or not np.iterable(items):
                raise _bad(kind, name, items, f"a list of {' / '.join(t.__name__ for t in types)}, e.g. {example}")
            for i, item in enumerate(items):
                if not isinstance(item, types):
                    raise _bad(kind, f"{name}[{i}]", item, f"a {' / '.join(t.__name__ for t in types)}")
        if not _is_real(raw["friction"]) or abs(float(raw["friction"])) > 1e100:
            raise _bad(kind, "friction", raw["friction"], "a finite number in [0, 1e100] (0 = frictionless)")
        if not isinstance(self.name, str):
            raise _bad(kind, "name", self.name, "a string")
        if not isinstance(self.kinematics, str):
            raise _bad(kind, "kinematics", self.kinematics, f"one of {', '.join(map(repr, KINEMATICS))}")
        if not isinstance(self.meta, dict):
            raise _bad(kind, "meta", self.meta, "a dict")

    # ------------------------------------------------------------ assembly
    def dirichlet(self) -> tuple[np.ndarray, np.ndarray]:
        """Fixed DOFs and their values.

        A DOF prescribed by several supports must get the same value from each
        (to a relative ``1e-9``); the first value is kept.

        Raises
        ------
        alcontact.errors.InputError
            Two supports prescribe different values to the same component of a
            node; the message names both boundaries, the component, the node and
            the values.
        """
        return merge_supports(self.model, self.supports)

    def load_vector(self) -> np.ndarray:
        """Assembled external load vector."""
        f = np.zeros(self.model.ndofs)
        for ld in self.loads:
            if isinstance(ld, Traction):
                f += self.model.traction_load(ld.boundary, ld.vector)
            elif isinstance(ld, Pressure):
                f += self.model.pressure_load(ld.boundary, ld.value)
            elif isinstance(ld, BodyForce):
                f += self.model.body_load(ld.vector)
            else:
                raise InputError(f"unknown load {ld!r}; use Traction, Pressure or BodyForce.")
        return f


#: the stack of the same bodies is the same object (its stiffness and factorization are kept): a problem
#: rebuilt by dataclasses.replace (load steps, problem_at) reuses it
_STACKS: weakref.WeakValueDictionary = weakref.WeakValueDictionary()


def _two_body(kind: str, bodies: tuple, pairs: tuple) -> dict[str, Any]:
    """The model (the bodies' :class:`~alcontact.fem.MultiBody`) and names of pairs of which one (or more) has a
    deformable master (the others rigid ones, each on a boundary of any of the bodies)."""
    from ...fem import MultiBody
    from ..masters._rigid_body import RigidBody

    for i, pair in enumerate(pairs):
        if pair.rigid:
            continue
        master_body = getattr(pair.master, "body", None)
        if not any(master_body is b for b in bodies):
            raise InputError(f"{kind}: pairs[{i}].master = {pair.master.describe()} is not rigid and is not the "
                             "surface of a body in bodies: a deformable master is alcontact.contact.BodySurface(body, "
                             f"boundary) with that body in bodies. See {ROADMAP}.")
        if master_body is pair.slave.body and getattr(pair.master, "boundary", None) == pair.slave.name:
            raise InputError(f"{kind}: pairs[{i}] uses the boundary {pair.slave.name!r} as both slave and master; "
                             "give the master another boundary (of another body).")
        if pair.friction > 0 and isinstance(pair.master, RigidBody):
            raise InputError(f"{kind}: pairs[{i}].friction = {pair.friction!r} against a rigid body whose pose is "
                             "solved for (contact.RigidBody): not supported yet; use friction = 0, or a rigid "
                             "obstacle moved along a path (obstacles.move) for friction.")
    pair = pairs[0]
    if len(bodies) == 1:
        model, slave = bodies[0], pair.slave.name
    else:
        key = tuple(id(b) for b in bodies)
        model = _STACKS.get(key)
        if model is None or any(a is not b for a, b in zip(model.bodies, bodies)):
            model = MultiBody(bodies)
            _STACKS[key] = model
        slave = model.qualify(pair.slave.body, pair.slave.name)
    return {"model": model, "obstacle": pair.master, "contact_boundary": slave, "friction": pair.friction,
            "pair": pair, "bodies": bodies, "others": tuple(pairs[1:])}


_AXES = "xyz"


def merge_supports(model, supports: Sequence[Support], labels: Sequence[str] | None = None,
                   *, scales: Sequence[float] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Fixed DOFs and values of ``supports``; an error if two of them disagree on a DOF.

    Parameters
    ----------
    model : alcontact.fem.LinearElasticity
    supports : sequence of Support
    labels : sequence of str, optional
        Names of the supports in messages (default ``support on 'BOUNDARY'``),
        e.g. the key paths of a problem file (``support[2]``).
    scales : sequence of float, optional
        Amplitude of each support (ramped supports at one step time); default 1.

    Returns
    -------
    dofs : ndarray of int
        Sorted fixed DOFs.
    values : ndarray
        Their prescribed values.

    Raises
    ------
    alcontact.errors.InputError
        Two supports prescribe different values (beyond a relative ``1e-9`` of
        the largest prescribed value) to the same component of a node.
    """
    if not supports:
        return _with_axis(model, np.empty(0, dtype=np.int64), np.empty(0))
    labels = list(labels) if labels is not None else [f"support on {s.boundary!r}" for s in supports]
    scales = list(scales) if scales is not None else [1.0] * len(supports)
    dofs_l, vals_l, own_l = [], [], []
    for k, s in enumerate(supports):
        d, v = model.dirichlet(s.boundary, None if s.components is None else list(s.components), s.value)
        dofs_l.append(d)
        vals_l.append(scales[k] * v)
        own_l.append(np.full(d.size, k))
    dofs = np.concatenate(dofs_l)
    vals = np.concatenate(vals_l)
    owner = np.concatenate(own_l)
    order = np.argsort(dofs, kind="stable")  # first prescription first among equal DOFs
    dofs, vals, owner = dofs[order], vals[order], owner[order]
    uniq, first = np.unique(dofs, return_index=True)
    ref = vals[first][np.searchsorted(uniq, dofs)]
    scale = max(float(np.max(np.abs(vals), initial=0.0)), 1e-300)
    bad = np.flatnonzero(np.abs(vals - ref) > 1e-9 * scale)
    if bad.size:
        j = int(bad[0])
        i = int(first[np.searchsorted(uniq, dofs[j])])
        dof = int(dofs[j])
        pts, dmap = model.all_node_dofs()
        node, comp = np.argwhere(dmap == dof)[0]
        a, b = supports[owner[i]], supports[owner[j]]
        n_bad = np.unique(dofs[bad]).size
        raise InputError(
            f"{labels[owner[i]]} and {labels[owner[j]]} prescribe different values to component {comp} "
            f"({_AXES[comp]}) at node {np.round(pts[node], 6).tolist()}: {vals[i]:g} on {a.boundary!r} and "
            f"{vals[j]:g} on {b.boundary!r} ({n_bad} DOF(s) in conflict). Make the values agree, or restrict "
            "one support to other components (components = [...]) so that the boundaries do not overlap."
        )
    return _with_axis(model, uniq, vals[first])


def _with_axis(model, dofs: np.ndarray, vals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``dofs, vals`` plus the body's own zero DOFs: :math:`u_r = 0` on the axis of a body of revolution
    (``model.axis_dofs``, empty for a Cartesian body; a support prescribing another value there is refused
    by ``model.dirichlet``)."""
    axis = np.setdiff1d(np.asarray(model.axis_dofs, dtype=np.int64), dofs)
    if axis.size == 0:
        return dofs, vals
    out = np.concatenate([dofs, axis])
    order = np.argsort(out, kind="stable")
    return out[order], np.concatenate([vals, np.zeros(axis.size)])[order]
