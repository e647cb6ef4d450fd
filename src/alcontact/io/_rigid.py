"""``[obstacle]`` as a rigid body: a reference point, a prescribed motion and a force and a moment.

With ``reference`` the obstacle of a one-body problem file becomes a
:class:`~alcontact.contact.RigidBody`: its pose (the translation of the reference point and the
rotation about it) has one component per axis and rotation, each either

- prescribed: ``displacement_x``, ``displacement_y`` (``displacement_z``), ``rotation`` (2D,
  radians, counter-clockwise) or ``rotation_x``, ``rotation_y``, ``rotation_z`` (3D);
- or force driven (an unknown of the contact problem): ``force_x``, ``force_y`` (``force_z``),
  ``moment`` (2D) or ``moment_x``, ``moment_y``, ``moment_z`` (3D), about the reference point;
- or, when neither is given, held at zero.

``ramp`` scales the prescribed motion and the loads over the load steps (default: full at every
step). The problem is then the body and the rigid body (``body0`` and ``body1``; supports and
loads of the body keep their bare boundary names), one pair between them, small deformation,
frictionless (:mod:`alcontact.contact.masters._rigid_body`). Each rigid-body key is checked here:
a component both prescribed and loaded, keys of the other dimension, a rigid body at finite
kinematics, with friction, with ``[[pair]]`` tables, with ``path``, or on a body of revolution.
"""

from __future__ import annotations

from typing import Any

from .._options import BAD, Option
from ._issues import Issue, _num

_DOC_ROT = "radians, counter-clockwise about the reference point"

#: the keys of ``[obstacle]`` that make it a rigid body (module doc)
RIGID_OPTIONS = (
    Option("reference", "floats", None, "Makes the obstacle a rigid body with this reference point, `[x, y]` / "
           "`[x, y, z]`: its translation and rotation about it are prescribed (`displacement_*`, `rotation*`) or "
           "solved for under a force and a moment (`force_*`, `moment*`); a component given neither is held at "
           "zero. Small deformation, frictionless.", lengths=(2, 3)),
    *(Option(f"displacement_{c}", "float", None, f"Rigid body: prescribed translation of the reference point "
             f"along {c}.") for c in "xyz"),
    Option("rotation", "float", None, f"Rigid body, 2D: prescribed rotation ({_DOC_ROT})."),
    *(Option(f"rotation_{c}", "float", None, f"Rigid body, 3D: prescribed rotation about {c} ({_DOC_ROT}).")
      for c in "xyz"),
    *(Option(f"force_{c}", "float", None, f"Rigid body: force along {c} on the reference point (that "
             "translation is then solved for).") for c in "xyz"),
    Option("moment", "float", None, "Rigid body, 2D: moment about the reference point, counter-clockwise (the "
           "rotation is then solved for)."),
    *(Option(f"moment_{c}", "float", None, f"Rigid body, 3D: moment about {c} at the reference point (that "
             "rotation is then solved for).") for c in "xyz"),
    Option("ramp", "knots", None, "Rigid body: amplitude over pseudo-time of its prescribed motion and its "
           "loads, a list of `[t, factor]` pairs (default: full value at every step)."),
)

_KEYS = tuple(o.name for o in RIGID_OPTIONS)


def _components(dim: int) -> list[tuple[str, str]]:
    """``(prescribed key, load key)`` of each pose component, in the rigid body's DOF order."""
    if dim == 2:
        return [("displacement_x", "force_x"), ("displacement_y", "force_y"), ("rotation", "moment")]
    return [(f"displacement_{c}", f"force_{c}") for c in "xyz"] + [(f"rotation_{c}", f"moment_{c}") for c in "xyz"]


def is_rigid(od: Any) -> bool:
    """``[obstacle]`` has a rigid-body key (module doc)."""
    return isinstance(od, dict) and any(od.get(k) is not None for k in _KEYS)


def rigid_issues(data: dict, dim: int | None, kinematics: str, mu: float, issues: list[Issue]) -> None:
    """The rigid-body keys of ``[obstacle]`` that do not fit (module doc), each an issue naming its key."""
    od = data.get("obstacle")
    if not is_rigid(od):
        return
    if od.get("reference") is None:
        given = [k for k in _KEYS if od.get(k) not in (None, BAD)]
        issues.append(Issue("obstacle.reference", f"missing: {', '.join(given)} make the obstacle a rigid body, "
                                                  "which needs its reference point, reference = [x, y] (the "
                                                  "centre of its rotation, where the force and moment act)."))
        return
    if od["reference"] is BAD:
        return
    if dim is not None and len(od["reference"]) != dim:
        issues.append(Issue("obstacle.reference", f"= {od['reference']!r}: {len(od['reference'])} coordinates but "
                                                  f"the mesh is {dim}D; give {dim}."))
        return
    d = dim if dim is not None else len(od["reference"])
    used = {k for pair in _components(d) for k in pair} | {"reference", "ramp"}
    for k in _KEYS:
        if k not in used and od.get(k) not in (None, BAD):
            other = [x for pair in _components(d) for x in pair if x.split("_")[0] == k.split("_")[0]]
            issues.append(Issue(f"obstacle.{k}", f"= {od[k]!r}: not a key of a {d}D rigid body; use "
                                                 f"{', '.join(other)}."))
    for pk, lk in _components(d):
        if od.get(pk) is not None and od.get(lk) is not None:
            issues.append(Issue(f"obstacle.{lk}", f"= {od[lk]!r} and obstacle.{pk} = {od[pk]!r}: a pose component "
                                                  "is either prescribed or loaded (its reaction is reported); give "
                                                  "one of them."))
    why = []
    if kinematics != "small":
        why.append(("contact.kinematics", "= 'finite': a rigid body with a reference point is small deformation "
                                          "so far; set kinematics = 'small', or give the obstacle a path instead."))
    if mu > 0:
        why.append(("contact.friction", f"= {mu:g}: contact with a rigid body whose pose is solved for is "
                                        "frictionless so far; set friction = 0.0."))
    if data.get("pair"):
        why.append(("pair", "[[pair]] tables beside a rigid body ([obstacle] reference): a pair with a moving "
                            "master beside other pairs is not supported yet; remove the [[pair]] tables."))
    if od.get("path") not in (None, BAD):
        why.append(("obstacle.path", "given with obstacle.reference: a rigid body is moved by its "
                                     "displacement_* / rotation keys; remove path."))
    md = data.get("mesh")
    if isinstance(md, dict) and md.get("geometry") not in (None, BAD, "cartesian"):
        why.append(("mesh.geometry", f"= {md['geometry']!r}: a rigid body with a reference point needs a "
                                     "Cartesian body; remove reference, or geometry."))
    issues.extend(Issue(k, m) for k, m in why)


def rigid_problem(data: dict, problem, history, times, issues: list[Issue]):
    """``(problem, history)`` with the obstacle made a rigid body (module doc); the inputs without one.

    ``problem`` is the one-body problem of the file, ``times`` its load-step times; the rigid
    body's drive joins its supports and loads (its ramped drive joins ``history``'s cases).
    """
    from ..contact import (Boundary, ContactPair, ContactProblem, LoadCase, LoadHistory, Ramp, RigidBody,
                           RigidLoad, Support)

    od = data.get("obstacle")
    if not is_rigid(od) or problem is None:
        return problem, history
    model = problem.model
    body = _num(issues, "obstacle.reference", RigidBody, problem.obstacle, od["reference"])
    if body is None:
        return None, None
    comps = _components(model.dim)
    held = [k for k, (pk, lk) in enumerate(comps) if od.get(lk) is None]
    value = [float(od.get(pk) or 0.0) for pk, _ in comps]  # the whole pose (the held components are taken)
    load = [float(od.get(lk) or 0.0) if od.get(lk) is not None else 0.0 for _, lk in comps]
    drive = [Support("body1", components=held, value=value)] if held else []
    loads = [RigidLoad("body1", load)] if any(od.get(lk) is not None for _, lk in comps) else []
    supports, extra = list(problem.supports), list(loads)
    cases = list(history.cases) if history is not None else []
    if od.get("ramp") is None:
        supports += drive
    else:
        ramp = Ramp(tuple(k[0] for k in od["ramp"]), tuple(k[1] for k in od["ramp"]), hold_before=True,
                    hold_after=True)
        moving = [s for s in drive if any(s.value)]
        supports += [s for s in drive if not any(s.value)]
        cases += [LoadCase(item, ramp, name=f"obstacle {kind}") for item, kind in
                  [(s, "motion") for s in moving] + [(ld, "load") for ld in extra]]
        extra = []
    pair = ContactPair(Boundary(model, problem.contact_boundary), body)
    rigid = _num(issues, "obstacle", ContactProblem, bodies=[model, body], pairs=[pair], supports=tuple(supports),
                 loads=tuple(problem.loads) + tuple(extra), name=problem.name, reference=problem.reference,
                 meta=problem.meta, kinematics=problem.kinematics)
    if rigid is None:
        return None, None
    if cases:
        friction = history.friction if history is not None else None
        history = _num(issues, "loading", LoadHistory, tuple(cases), tuple(times), friction)
    return rigid, history
