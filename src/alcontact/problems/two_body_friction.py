r"""Coulomb friction between two deformable bodies (2D, plane strain, mortar pair), with references.

The pairs are those of :mod:`alcontact.problems.two_body` (the upper body's bottom, slave,
against the lower body's top, :class:`~alcontact.contact.BodySurface` master; bodies
``body0`` = the base, ``body1`` = the upper one); the slip is the relative tangential
displacement of the two surfaces (:mod:`alcontact.contact.kinematics._mortar_tangent`).

``dragged_block``
    A block pressed on a wider deformable base through its top (a prescribed approach, first
    half of the history), then dragged sideways by a prescribed displacement of its top (second
    half). Once every slave node slides, each carries :math:`|t_T| = \mu t_N` along the slip, so the
    tangential force is :math:`Q = \mu N` exactly, whatever the pressure distribution (the
    two-body counterpart of :func:`alcontact.problems.friction.block_on_plane`).
``cattaneo_mindlin_cylinders``
    Two identical elastic cylinders (the same :math:`E`, :math:`\nu`, radius) pressed together, then
    loaded by a tangential force :math:`Q < \mu P`. For identical materials the normal and the
    tangential problems decouple exactly (Dundurs' :math:`\beta = 0`), so Cattaneo-Mindlin holds for any
    :math:`\nu` (Johnson, *Contact Mechanics*, 1985, sections 7.1 and 7.2): the contact :math:`|x| < a`
    has a central stick zone :math:`|x| < c` with

    .. math::

        \frac{c}{a} = \sqrt{1 - \frac{Q}{\mu P}}, \qquad
        a = \sqrt{\frac{4PR}{\pi E^*}}, \quad \frac1R = \frac2{R_1}, \quad \frac1{E^*} = \frac{2(1-\nu^2)}{E},

    and the shear traction of :class:`~alcontact.problems.friction.MindlinReference`. As in
    :func:`alcontact.problems.two_body.hertz_cylinders`, each cylinder is a block of size
    ``size * a`` whose contact face has the cylinder's parabolic profile (here the full width,
    the tangential load being antisymmetric).
``rigid_limit_drag``
    The block of ``dragged_block`` sheared into partial slip on a base that is rigid (a
    half-space, node-to-surface gaps (6.15)) and on the same base as an elastic body ``stiffening``
    times stiffer (a mortar pair): against a flat master the mortar gap and slip are the
    node-to-surface ones, so the elastic pair tends to the rigid one as the base stiffens.
"""

from __future__ import annotations

import math

import numpy as np

from ..contact import BodySurface, Boundary, ContactPair, ContactProblem, LoadCase, LoadHistory, Ramp, Support
from ..contact.obstacles import HalfSpace
from ..fem import LinearElasticity, Material, meshes
from .friction import MindlinReference
from .hertz import HertzReference, mesh_spec
from .two_body import _block, _curved

__all__ = ["dragged_block", "cattaneo_mindlin_cylinders", "rigid_limit_drag", "drag_history"]


def drag_history(top: str, approach: float, slide: float, steps: int) -> LoadHistory:
    """A boundary ``top`` moved down by ``approach`` over t in [0, 1/2] (its ``x`` held), then sideways by ``slide``
    over [1/2, 1] (a tangential load case), in ``steps`` equal steps."""
    press = LoadCase(Support(top, components=(1,), value=-approach), Ramp((0.0, 0.5), (0.0, 1.0), hold_after=True),
                     name="normal approach")
    drag = LoadCase(Support(top, components=(0,), value=slide), Ramp((0.5, 1.0), (0.0, 1.0)), tangential=True,
                    name="tangential displacement")
    return LoadHistory((press, drag), LoadHistory.uniform(steps))


def _check(where: str, **values):
    from .._options import VALUE_RANGE, Option, check_args

    lo, hi = VALUE_RANGE
    spec = {"n": ("int", "Cells across the block.", 1, 1000), "mu": ("float", "Friction coefficient.", 0.0, hi),
            "slide_ratio": ("float", "Slide / limit.", -hi, hi), "steps": ("int", "Load steps.", 2, 100_000),
            "strain": ("float", "Approach / height.", lo, 0.5), "stiffening": ("float", "Base stiffening.", lo, hi),
            "n_per_a": ("float", "Elements per a.", 0.01, 4096), "q_ratio": ("float", "Q / (mu P).", -hi, hi),
            "radius": ("float", "Radius.", lo, hi), "size": ("float", "Block size / a.", 1.0, 1e6),
            "master_ratio": ("float", "Master / slave elements.", 0.01, 100.0),
            "normal_steps": ("int", "Normal steps.", 1, 100_000), "tangential_steps": ("int", "Tangential steps.", 1,
                                                                                         100_000)}
    return check_args(where, [(Option(k, spec[k][0], None, spec[k][1], low=spec[k][2], high=spec[k][3]), v)
                              for k, v in values.items()])


def _drag_blocks(n: int, E, nu, base_width: float, order: int = 1):
    """Base ``[-w/2, w/2] x [0, 1/2]`` (``n`` cells per unit) and block ``[-1/2, 1/2] x [1/2, 1]`` (``n + 1``)."""
    half = 0.5 * base_width
    base = LinearElasticity(meshes.rectangle(-half, half, 0.0, 0.5, int(round(n * base_width)), max(2, n // 2)),
                            Material(E=E[0], nu=nu[0], plane="strain"), order=order)
    top = LinearElasticity(meshes.rectangle(-0.5, 0.5, 0.5, 1.0, n + 1, max(2, (n + 1) // 2)),
                           Material(E=E[1], nu=nu[1], plane="strain"), order=order)
    return base, top


def dragged_block(n: int = 8, *, E=(1000.0, 1000.0), nu=(0.3, 0.3), mu: float = 0.3, strain: float = 0.01,
                  slide_ratio: float = 3.0, steps: int = 4, base_width: float = 2.0, order: int = 1):
    r"""A block dragged over a deformable base (module doc): ``(problem, history)``.

    Parameters
    ----------
    n : int
        Cells per unit length of the base (the block gets ``n + 1`` across: non-matching meshes).
    E, nu : pair of float
        Constants of the base (``body0``, the master) and of the block (``body1``, the slave).
    mu : float
        Coulomb coefficient of the pair.
    strain : float
        Approach of the block's top over its height (1/2): :math:`d = \text{strain}/2`.
    slide_ratio : float
        Tangential displacement of the top over :math:`s^* = 2\mu d (1+\nu_1)`, the one that brings a
        uniformly sheared block alone to :math:`Q = \mu N`: well above 1 the block slides.
    steps : int
        Equal load steps (half of them press, half drag).
    base_width : float
        Width of the base (the block is 1 wide, centred): wider, so that every slave node stays covered.
    order : {1, 2}
        P1 or P2 elements in both bodies.
    """
    n, mu, strain, slide_ratio, steps = _check("dragged_block", n=n, mu=mu, strain=strain, slide_ratio=slide_ratio,
                                               steps=steps)
    if order not in (1, 2):
        from ..errors import InputError

        raise InputError(f"dragged_block: order = {order!r}: expected 1 or 2.")
    base, top = _drag_blocks(n, E, nu, base_width, order)
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"), friction=mu)
    d = 0.5 * strain
    s = slide_ratio * 2.0 * mu * d * (1.0 + nu[1])
    problem = ContactProblem(bodies=[base, top], pairs=[pair], supports=[Support("body0/bottom")],
                             name=f"block dragged on a deformable base (n={n}, mu={mu:g})",
                             meta={"d": d, "s": s, "direction": np.array([1.0])})
    return problem, drag_history("body1/top", d, s, steps)


def rigid_limit_drag(n: int = 8, *, E: float = 1000.0, nu: float = 0.3, mu: float = 0.3, strain: float = 0.01,
                     slide_ratio: float = 0.6, steps: int = 4, stiffening: float = 1e6):
    """The dragged block on a rigid base and on a base ``stiffening`` times stiffer (module doc).

    Returns ``((rigid, rigid_history), (elastic, elastic_history))``: the same block, loads and steps,
    against the half-space ``y <= 1/2`` and against the top of the base block ``[-1, 1] x [0, 1/2]``
    (fixed at its bottom). ``slide_ratio`` as in :func:`dragged_block` (0.6: partial slip, from the
    edges of the block).
    """
    n, mu, strain, slide_ratio, steps, stiffening = _check(
        "rigid_limit_drag", n=n, mu=mu, strain=strain, slide_ratio=slide_ratio, steps=steps, stiffening=stiffening)
    base, top = _drag_blocks(n, (stiffening * E, E), (nu, nu), 2.0)
    d = 0.5 * strain
    s = slide_ratio * 2.0 * mu * d * (1.0 + nu)
    block = LinearElasticity(top.mesh, top.material)
    rigid = ContactProblem(model=block, obstacle=HalfSpace(point=(0.0, 0.5), normal=(0.0, 1.0)),
                           contact_boundary="bottom", friction=mu, name="block dragged on a rigid base")
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"), friction=mu)
    elastic = ContactProblem(bodies=[base, top], pairs=[pair], supports=[Support("body0/bottom")],
                             name=f"block dragged on a base {stiffening:g} times stiffer")
    return (rigid, drag_history("top", d, s, steps)), (elastic, drag_history("body1/top", d, s, steps))


def cattaneo_mindlin_cylinders(n_per_a: float = 16, *, E: float = 200e3, nu: float = 0.3, radius: float = 20.0,
                               a_target: float = 1.0, size: float = 20.0, mu: float = 0.3, q_ratio: float = 0.5,
                               normal_steps: int = 2, tangential_steps: int = 2, master_ratio: float = 1.0,
                               growth: float = 1.15, frictionless_approach: bool = True):
    r"""Two identical elastic cylinders, pressed, then sheared into partial slip (module doc): ``(problem, history)``.

    The base (``body0``, master, profile :math:`-x^2/(2R_1)`) is fixed at its bottom; the upper
    cylinder (``body1``, slave, profile :math:`+x^2/(2R_2)`, :math:`R_1 = R_2` = ``radius``) is pressed
    by a prescribed approach :math:`\delta` of its top over t in [0, 1/2] (the approach of
    :func:`alcontact.problems.two_body.hertz_cylinders` for ``a_target``), then moved sideways by
    :math:`s` over [1/2, 1], estimated from the full-stick compliance to give
    :math:`Q \approx` ``q_ratio`` :math:`\mu P`; the reference uses the P and Q the model carries.

    Parameters
    ----------
    n_per_a : float
        Elements per ``a`` on the slave in the fine zone (P1).
    master_ratio : float
        Elements per ``a`` of the master over the slave's (1: matching nodes; else non-matching meshes).
    frictionless_approach : bool
        Friction factor 0 during the normal phase (the Cattaneo-Mindlin hypothesis that the normal
        load makes no shear; for identical bodies it holds anyway, up to the discretization, since
        both surfaces move alike).
    normal_steps, tangential_steps : int
        Load steps of each phase.

    Returns
    -------
    problem : ContactProblem
        ``problem.reference`` is a :class:`~alcontact.problems.friction.MindlinReference` with
        :math:`E^*`, :math:`R` of the two cylinders.
    history : LoadHistory
    """
    n_per_a, radius, size, mu, q_ratio, master_ratio, normal_steps, tangential_steps = _check(
        "cattaneo_mindlin_cylinders", n_per_a=n_per_a, radius=radius, size=size, mu=mu, q_ratio=q_ratio,
        master_ratio=master_ratio, normal_steps=normal_steps, tangential_steps=tangential_steps)
    mat = Material(E=E, nu=nu, plane="strain")
    e_star = 0.5 * mat.plane_strain_modulus
    R = 0.5 * radius
    a = a_target
    H = size * a

    def grid(n):
        md = mesh_spec(2, n, 1, a_target=a, size=size, growth=growth)
        m = meshes.rectangle(*md["bounds"], *md["cells"], refine=md["refine"])
        x, y = np.unique(m.p[0]), np.unique(m.p[1])  # x in [0, H], y in [-H, 0], fine near (0, 0)
        return np.concatenate([-x[:0:-1], x]), y

    xs, ys = grid(n_per_a)
    xm, ym = grid(max(1.0, master_ratio * n_per_a))
    base = LinearElasticity(_curved(_block(xm, ym), radius, H, -1.0), mat)
    top = LinearElasticity(_curved(_block(xs, -ys[::-1]), radius, H, +1.0), mat)
    P = math.pi * a * a * e_star / (4 * R)  # the Hertz load of a_target
    compliance = 2.0 / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)
    delta = P * compliance
    s = 1.8 * q_ratio * mu * P * compliance  # full-stick tangential compliance ~ the normal one; partial slip x1.8
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"), friction=mu)
    t_half = 0.5
    times = tuple(np.linspace(0, t_half, normal_steps + 1)[1:]) + tuple(
        np.linspace(t_half, 1.0, tangential_steps + 1)[1:])
    press = LoadCase(Support("body1/top", components=(1,), value=-delta),
                     Ramp((0.0, t_half), (0.0, 1.0), hold_after=True), name="approach")
    shear = LoadCase(Support("body1/top", components=(0,), value=s), Ramp((t_half, 1.0), (0.0, 1.0)),
                     tangential=True, name="tangential displacement")
    ref = MindlinReference(HertzReference("cylinder", R, e_star, symmetry=1.0), mu)
    problem = ContactProblem(
        bodies=[base, top], pairs=[pair], supports=[Support("body0/bottom")], reference=ref,
        name=f"Cattaneo-Mindlin, two identical cylinders (R1=R2={radius:g}, {n_per_a:g} elements per a, mu={mu:g})",
        meta={"delta": delta, "s": s, "h": a / n_per_a, "center": (0.0, 0.0), "e_star": e_star, "radius": R})
    fric = Ramp((t_half, t_half + 1e-9), (0.0, 1.0), hold_after=True) if frictionless_approach else None
    return problem, LoadHistory((press, shear), times, fric)
