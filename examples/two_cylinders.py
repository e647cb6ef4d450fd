"""Two elastic cylinders of different materials pressed together (2D plane strain, mortar contact).

A steel cylinder (E = 200 GPa, nu = 0.3, R1 = 20 mm) under an aluminium one (E = 70 GPa,
nu = 0.35, R2 = 20 mm), half model x >= 0. Each cylinder is modelled near the contact by a
block whose contact face has the cylinder's profile x^2 / (2 R_i) (Hertz's half-spaces); the
upper block's top is pushed down, the lower block's bottom is fixed. The contact between the
two deformable bodies is the mortar pair of a ``BodySurface`` master (dual multipliers, one
constraint per slave node), on non-matching meshes.

Reference: Johnson, Contact Mechanics (1985), eq. 4.45-4.47 with
1/R = 1/R1 + 1/R2 and 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.

Run::

    python examples/two_cylinders.py [results_folder]

The built-in ``alcontact run --problem hertz-2body`` solves the same problem
(:func:`alcontact.problems.two_body.hertz_cylinders`).
"""

from __future__ import annotations

import dataclasses
import math
import sys

import numpy as np
import skfem

from alcontact.app import run_problem
from alcontact.contact import BodySurface, Boundary, ContactPair, ContactProblem, Support
from alcontact.fem import LinearElasticity, Material, meshes


def curved_block(y0: float, y1: float, radius: float, face: str, n_per_a: float, a: float = 1.0,
                 size: float = 20.0):
    """A block ``[0, size a] x [y0, y1]`` graded towards ``(0, 0)``, its face ``y = 0`` bent to ``x^2 / (2R)``."""
    H = size * a
    # the graded block mesh of the rigid Hertz problem, mirrored for the upper body
    base = meshes.rectangle(0.0, H, -H, 0.0, 8, 8, refine=dict(center=[0.0, 0.0], h_min=a / n_per_a,
                                                               width=1.6 * a, depth=a, growth=1.15))
    x, y = np.unique(base.p[0]), np.unique(base.p[1])
    if face == "bottom":  # the upper body: fine at its bottom
        y = -y[::-1]
    grid = skfem.MeshTri.init_tensor(x, y)
    bf = grid.boundary_facets()
    mid = grid.p[:, grid.facets[:, bf]].mean(axis=1)
    tol = 1e-9 * H
    sides = {"left": (0, 0.0), "right": (0, H), "bottom": (1, y[0]), "top": (1, y[-1])}
    grid = grid.with_boundaries({k: bf[np.abs(mid[i] - v) <= tol] for k, (i, v) in sides.items()})
    p = np.array(grid.p, dtype=float)
    xc = 0.5 * radius  # beyond it, far from the contact, the profile goes on along its tangent
    prof = np.where(p[0] <= xc, p[0] ** 2 / (2 * radius), xc ** 2 / (2 * radius) + xc / radius * (p[0] - xc))
    p[1] += (1.0 if face == "bottom" else -1.0) * prof * np.clip(1.0 - np.abs(p[1]) / H, 0.0, 1.0)
    return dataclasses.replace(grid, doflocs=p)


def main(out: str | None = None) -> dict:
    E1, nu1, R1 = 200e3, 0.30, 20.0  # lower cylinder: steel (MPa, mm)
    E2, nu2, R2 = 70e3, 0.35, 20.0  # upper cylinder: aluminium
    e_star = 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)
    R = 1.0 / (1.0 / R1 + 1.0 / R2)
    a, H = 1.0, 20.0  # intended half-width, block size
    load = math.pi * a * a * e_star / (4 * R)
    delta = 2 * load / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)  # the approach that gives a ~ 1

    lower = LinearElasticity(curved_block(-H, 0.0, R1, "top", n_per_a=24), Material(E=E1, nu=nu1, plane="strain"))
    upper = LinearElasticity(curved_block(0.0, H, R2, "bottom", n_per_a=32), Material(E=E2, nu=nu2, plane="strain"))
    problem = ContactProblem(
        bodies=[lower, upper],  # named body0, body1: boundaries "body0/top", "body1/bottom", ...
        pairs=[ContactPair(Boundary(upper, "bottom"), BodySurface(lower, "top"))],
        supports=[Support("body0/bottom"), Support("body0/left", components=[0]),
                  Support("body1/left", components=[0]), Support("body1/top", components=[1], value=-delta)],
        name="two elastic cylinders (steel / aluminium)", meta={"center": (0.0, 0.0), "symmetry_axis": 0})
    sol, summary = run_problem(problem, out, algorithm="ssn", force=True)
    P = 2.0 * sol.normal_force  # the half model carries half the load
    a_ex = math.sqrt(4 * P * R / (math.pi * e_star))
    p0_ex = 2 * P / (math.pi * a_ex)
    a_num = sol.contact_half_width(axis=0, center=(0.0, 0.0))
    print(f"{problem.model.ndofs} DOFs, status {sol.result.status.label}")
    print(f"half-width  a  = {a_num:.4f} mm (Hertz {a_ex:.4f}, {100 * (a_num / a_ex - 1):+.2f} %)")
    print(f"peak pressure p0 = {sol.peak_pressure_nodal_max:.1f} MPa (Hertz {p0_ex:.1f}, "
          f"{100 * (sol.peak_pressure_nodal_max / p0_ex - 1):+.2f} %)")
    print(f"action = reaction: |F_slave + F_master| / |F_slave| = {sol.extra['contact_force_balance']:.1e}")
    return {"a": a_num / a_ex - 1, "p0": sol.peak_pressure_nodal_max / p0_ex - 1,
            "balance": sol.extra["contact_force_balance"], "success": sol.result.success}


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
