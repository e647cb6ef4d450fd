r"""Ironing at finite deformation: a rigid cylinder (2D) or sphere (3D) pressed into a neo-Hookean
block and slid along it (large sliding, issue 18).

The block :math:`[0, L] \times [0, H]` (plane strain) or :math:`[0, L] \times [0, W] \times [0, H]`
(3D, the half :math:`y \ge 0` of a sphere ploughing a block, symmetry face ``"front"``,
:math:`u_y = 0`) is clamped at its bottom; its top face is the contact boundary. The rigid
indenter of radius :math:`R` touches the top face at :math:`x = x_0` at :math:`t = 0`, is pressed
down by ``depth`` in ``press_steps`` equal load steps, then slid along :math:`x` by ``slide_step``
per load step for ``slide_steps`` steps (the obstacle path of :func:`ironing_schedule`, for
:func:`alcontact.contact.solve`). Frictionless steady sliding of an elastic body dissipates
nothing: the horizontal force tends to zero far from the block's ends (a benchmark property,
no closed-form reference at finite deformation).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..contact import ContactProblem, Support
from ..contact.obstacles import Circle, Sphere
from ..errors import InputError
from ..fem import Material, meshes
from ..fem.hyperelastic import Hyperelastic

__all__ = ["ironing", "ironing_schedule"]


def ironing(dim: int = 2, n: int = 10, *, order: int = 1, radius: float = 1.0, depth: float = 0.2,
            slide: float = 2.0, slide_step: float = 0.05, press_steps: int = 4, height: float = 2.0,
            half_width: float = 1.5, margin: float = 1.5, E: float = 1000.0, nu: float = 0.3,
            model: str = "neo-hookean") -> ContactProblem:
    """The ironing problem (module doc).

    Parameters
    ----------
    dim : {2, 3}
    n : int
        Elements per unit length (the mesh size is ``1/n``).
    order : {1, 2}
    radius, depth : float
        Indenter radius :math:`R` and indentation depth.
    slide, slide_step : float
        Sliding distance and sliding per load step.
    press_steps : int
        Load steps of the indentation.
    height, half_width, margin : float
        Block height, half width (3D: the modelled width ``W``), and the block's length beyond the
        indenter's start and end positions (``L = 2 margin + slide``).
    E, nu : float
    model : str
        Hyperelastic law (:func:`alcontact.fem.available_materials`).
    """
    if dim not in (2, 3):
        raise InputError(f"dim must be 2 or 3; got {dim!r}.")
    length = 2.0 * margin + slide
    cells = lambda ext: max(1, int(round(ext * n)))  # noqa: E731
    if dim == 2:
        mesh = meshes.rectangle(0.0, length, 0.0, height, cells(length), cells(height))
        obstacle = Circle([margin, height + radius], radius)
        supports = (Support("bottom", components=(0, 1)),)
        material = Material(E=E, nu=nu, plane="strain")
    else:
        mesh = meshes.box(0.0, length, 0.0, half_width, 0.0, height, cells(length), cells(half_width),
                          cells(height))
        obstacle = Sphere([margin, 0.0, height + radius], radius)
        supports = (Support("bottom", components=(0, 1, 2)), Support("front", components=(1,)))
        material = Material(E=E, nu=nu)
    body = Hyperelastic(mesh, material, order=order, model=model)
    slide_steps = int(round(slide / slide_step))
    return ContactProblem(
        model=body, obstacle=obstacle, contact_boundary="top", supports=supports,
        name=f"ironing {dim}D (R={radius:g}, depth={depth:g}, n={n}, P{order}, {model})",
        kinematics="finite",
        meta={"radius": radius, "depth": depth, "n": n, "press_steps": int(press_steps),
              "slide_step": float(slide_step), "slide_steps": slide_steps, "dim": dim},
    )


def ironing_schedule(problem: ContactProblem) -> tuple[list[float], Callable[[float], np.ndarray]]:
    """Step times ``1, 2, ...`` and the obstacle path of an :func:`ironing` problem.

    Steps ``1 .. press_steps`` press the indenter down (vertical axis: the last coordinate),
    the following ``slide_steps`` slide it along :math:`x` by ``slide_step`` each.
    """
    meta = problem.meta
    dim, npress, ds, depth = meta["dim"], meta["press_steps"], meta["slide_step"], meta["depth"]
    times = [float(k) for k in range(1, npress + meta["slide_steps"] + 1)]

    def path(t: float) -> np.ndarray:
        off = np.zeros(dim)
        off[-1] = -depth * min(t, npress) / npress
        off[0] = ds * max(t - npress, 0.0)
        return off

    return times, path
