"""Block problems with simple contact: patch test and Signorini block with lift-off."""

from __future__ import annotations

from .._options import VALUE_RANGE, Option, check_args
from ..contact import ContactProblem, Pressure, Support
from ..contact.obstacles import HalfSpace
from ..fem import LinearElasticity, Material, meshes

__all__ = ["patch_block", "signorini_block", "patch_pressure"]


def patch_pressure(E: float, nu: float, dim: int, d: float, H: float) -> float:
    """Exact contact pressure of the patch test: uniaxial stress in y, free lateral faces.

    2D plane strain: ``E/(1-nu^2) d/H``; 3D: ``E d/H``.
    """
    lo, hi = VALUE_RANGE
    E, nu, dim, d, H = check_args("patch_pressure", [
        (Option("E", "float", 1000.0, "Young's modulus.", low=lo, high=hi), E),
        (Option("nu", "float", 0.3, "Poisson's ratio.", low=-1.0, high=0.5, low_open=True, high_open=True), nu),
        (Option("dim", "int", 2, "Dimension.", low=2, high=3), dim),
        (Option("d", "float", 0.01, "Push.", low=-hi, high=hi), d),
        (Option("H", "float", 1.0, "Height.", low=lo, high=hi), H)])
    return (E / (1 - nu * nu) if dim == 2 else E) * d / H


def patch_block(dim: int = 2, order: int = 1, n: int = 4, *, E: float = 1000.0, nu: float = 0.3,
                d: float = 0.01, width: float = 1.0, height: float = 1.0) -> ContactProblem:
    """Block on a flat rigid obstacle, top pushed down by ``d``: uniform contact pressure.

    The bottom face touches the plane ``y = 0`` (``z = 0`` in 3D) with zero
    initial gap; the top face has a prescribed vertical displacement ``-d``;
    symmetry rollers on ``left`` (and ``front``) stop the rigid sliding. The
    exact pressure is :func:`patch_pressure`, uniform along the contact face.
    """
    lo, hi = VALUE_RANGE
    dim, order, n, d, width, height = check_args("patch_block", [
        (Option("dim", "int", 2, "Dimension.", low=2, high=3), dim),
        (Option("order", "int", 1, "Order.", low=1, high=2), order),
        (Option("n", "int", 4, "Cells per side.", low=1, high=1000), n),
        (Option("d", "float", 0.01, "Push.", low=-hi, high=hi), d),
        (Option("width", "float", 1.0, "Width.", low=lo, high=hi), width),
        (Option("height", "float", 1.0, "Height.", low=lo, high=hi), height)])
    mat = Material(E=E, nu=nu, plane="strain")
    if dim == 2:
        mesh = meshes.rectangle(0.0, width, 0.0, height, n, n)
        obstacle = HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0))
        supports = (Support("top", components=(1,), value=-d), Support("left", components=(0,)))
    else:
        mesh = meshes.box(0.0, width, 0.0, width, 0.0, height, n, n, n)
        obstacle = HalfSpace(point=(0.0, 0.0, 0.0), normal=(0.0, 0.0, 1.0))
        supports = (Support("top", components=(2,), value=-d), Support("left", components=(0,)),
                    Support("front", components=(1,)))
    model = LinearElasticity(mesh, mat, order=order)
    return ContactProblem(model=model, obstacle=obstacle, contact_boundary="bottom", supports=supports,
                          name=f"patch test {dim}D P{order}",
                          meta={"pressure_exact": patch_pressure(E, nu, dim, d, height)})


def signorini_block(order: int = 1, n: int = 8, *, E: float = 1000.0, nu: float = 0.3, gap: float = 0.01,
                    pressure: float = 2.0) -> ContactProblem:
    """Cantilever block ``[0, 4] x [0, 1]`` clamped on the left, pressed onto a plane below.

    The bottom starts at distance ``gap`` above the plane ``y = -gap``; a uniform
    pressure on the top bends the block down so that only the part near the
    free end touches: contact with lift-off (the contact zone is found by the
    solver). Used to check that every algorithm reproduces the semi-smooth
    Newton reference.
    """
    lo, hi = VALUE_RANGE
    order, n, gap, pressure = check_args("signorini_block", [
        (Option("order", "int", 1, "Order.", low=1, high=2), order),
        (Option("n", "int", 8, "Cells across.", low=1, high=1000), n),
        (Option("gap", "float", 0.01, "Initial gap.", low=-hi, high=hi), gap),
        (Option("pressure", "float", 2.0, "Pressure.", low=-hi, high=hi), pressure)])
    mat = Material(E=E, nu=nu, plane="strain")
    mesh = meshes.rectangle(0.0, 4.0, 0.0, 1.0, 4 * n, n)
    model = LinearElasticity(mesh, mat, order=order)
    obstacle = HalfSpace(point=(0.0, -gap), normal=(0.0, 1.0))
    return ContactProblem(model=model, obstacle=obstacle, contact_boundary="bottom",
                          supports=(Support("left"),), loads=(Pressure("top", pressure),),
                          name=f"Signorini cantilever P{order}")
