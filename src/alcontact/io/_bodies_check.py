"""``alcontact check`` of a problem of several bodies (``[[body]]`` tables, or ``[obstacle] reference``).

Before any solve, from the pair's reference gaps (:func:`alcontact.contact.pair_start`):

- **overlap at the start**: bodies that overlap by more than :data:`OVERLAP_ERROR` slave element
  sizes are refused (the geometry is probably misplaced, and a small-deformation gap is not
  meaningful across elements), naming the deepest slave point and the overlap; a smaller
  overlap beyond the touching tolerance is a warning (an interference fit);
- **a body held by nothing**: a rigid motion of a body that no support stops and no touching
  contact point holds (frictionless contact holds the normal motion only) is refused, naming the
  body and its free motions (a rigid body's force-driven components included);
- **no contact possible**: a pair whose master has no segment within the search distance of the
  slave is a warning naming the pair (it would solve as a pair that never touches), and a master
  whose segments there all face away from the slave (the other side of its body) is refused.

The orientation of a body's surface as a master comes from the body (outward normals of its
elements), so it cannot be inconsistent; a meshed rigid surface with inconsistent facets is
refused when it is read (:class:`~alcontact.contact.MeshedSurface`).
"""

from __future__ import annotations

import logging

import numpy as np

from ..errors import InputError
from ._issues import Issue

logger = logging.getLogger(__name__)

#: overlap at the start (in slave element sizes) beyond which ``check`` refuses the bodies' placement
OVERLAP_ERROR = 1.0


def _where(setup, b: int) -> str:
    """The key of body ``b`` in the file: ``body[k]`` of ``[[body]]`` tables, ``obstacle`` for the rigid body of
    ``[obstacle] reference``, ``mesh`` for the one body then."""
    if setup.data.get("body"):
        return f"body[{b + 1}]"
    return "obstacle" if b == 1 else "mesh"


def bodies_issues(setup, fixed) -> list[Issue]:
    """The issues of a problem of several bodies (module doc); warnings are logged. ``fixed``: the prescribed
    DOFs, ramped supports included."""
    from ..contact import pair_start

    problem = setup.problem
    model = problem.model
    try:
        start = pair_start(problem)
    except InputError as exc:
        return [Issue("contact", str(exc))]
    if start is None:
        return []
    issues = []
    if start.facing_away:
        issues.append(Issue("contact.master", f"the contact pair {start.label}: the master's segments near the slave "
                                              "all face away from it (their outward normals point away from the "
                                              "slave's), so the pair can never touch: the master is the other side "
                                              "of its body; name the boundary that faces the slave."))
    elif not np.any(start.covered):
        logger.warning("the contact pair %s: no master segment lies within the search distance of the slave, so "
                       "this pair cannot come into contact (it solves as open); check the boundaries, or move the "
                       "bodies closer", start.label)
    deepest = start.deepest
    if deepest is not None and deepest[0] > start.overlap_tol:
        depth, at = deepest
        text = (f"the bodies overlap at the start: the slave point {np.round(at, 6).tolist()} of the pair "
                f"{start.label} lies {depth:.3g} inside the master ({depth / start.h:.2g} element sizes)")
        if depth > OVERLAP_ERROR * start.h:
            issues.append(Issue("contact", f"{text}; move the bodies apart (check their coordinates) so that they "
                                           f"overlap by less than {OVERLAP_ERROR:g} element size, or touch."))
        else:
            logger.warning("%s; the contact pushes them apart (an interference fit)", text)
    for b, motions in start.free_motions(model, fixed):
        body = model.bodies[b]
        name = model.names[b]
        kind = "the rigid body" if body.mesh is None else "body"
        own = [f"{name}/{n}" for n in body.boundary_names]
        how = ("prescribe them (Support on its pose: displacement_* / rotation in [obstacle]) or load it into "
               "contact" if body.mesh is None else
               f"add a support on one of its boundaries ({', '.join(own[:6])}) or move it into contact")
        issues.append(Issue(_where(setup, b), f"{kind} {name!r} is held by nothing in {', '.join(motions)}: no "
                                              "support stops that motion and no contact point touching another body "
                                              "holds it (frictionless contact holds the normal motion only), so its "
                                              f"equations are singular; {how}."))
    return issues
