"""A curved second-order (``tetra10``) Gmsh mesh: a rubber hemisphere pressed onto a rigid plane.

A neo-Hookean hemisphere of radius ``R`` (flat face on top, curved face down, touching the
plane y = 0 at the origin) is pushed down by ``delta`` in load steps at finite deformation.
One quarter is modelled (x <= 0, z >= 0, symmetry faces). The mesh is of second order:
Gmsh places the edge nodes of the ``tetra10`` elements on the sphere, and the P2 body uses
the isoparametric map of these nodes (``alcontact.fem.meshes.read`` gives a ``MeshTet2``),
so the contact surface is curved and not a polyhedron. With ``--order 1`` the same file is
run on its vertices (straight-sided P1 elements) for comparison.

What the script does:

1. builds the quarter ball with the Gmsh Python API (OpenCASCADE kernel: a sphere cut by a
   box), refines it towards the contact point, meshes it with second-order tetrahedra and
   names the parts with physical groups: ``curved``, ``top``, ``symmetry_x``, ``symmetry_z``
   and ``body``;
2. writes ``ball.msh`` (Gmsh format 4.1) and a problem file ``ball.toml`` that uses it
   (``[mesh] generator = "file"``, ``order = 2``);
3. solves it as ``alcontact run ball.toml`` would (:func:`alcontact.io.load_problem`,
   :func:`alcontact.app.run_setup`) and writes the results folder ``results/``; the VTU
   files hold ``tetra10`` cells, so ParaView shows the curved surface.

Run from the repository root::

    python examples/gmsh_curved_ball.py --out results-curved-ball            # about 10 s
    python examples/gmsh_curved_ball.py --out results-curved-ball --h 0.12   # finer mesh
    alcontact run results-curved-ball/ball.toml --out other-folder             # the same from the CLI

Reference: the same problem built from the mapped cube of
:func:`alcontact.problems.hemisphere.hemisphere` (P2, curved by default) gives 13.83 N at
``n = 6`` (6591 DOFs); this mesh gives 13.96 N at ``--h 0.25`` (447 DOFs) and 13.85 N at
``--h 0.15``. Hertz's small-deformation force of a quarter sphere on a half-space,
:math:`\\tfrac{1}{3} E^* R^{1/2} \\delta^{3/2}` = 11.58 N, is printed for scale only: the
hemisphere is of finite height and its flat face is held, so it is not that problem.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

#: Geometry, material (E in MPa) and load of the example.
RADIUS, DELTA = 1.0, 0.1
E, NU = 1000.0, 0.3

TOML = """\
# Written by examples/gmsh_curved_ball.py: neo-Hookean hemisphere (quarter) on a rigid plane,
# curved second-order tetra10 Gmsh mesh.
[problem]
name = "gmsh-curved-ball"
description = "Neo-Hookean hemisphere (R = {R}, quarter model, curved tetra10 mesh) pressed onto a rigid plane by {delta}."

[mesh]
generator = "file"
file = "ball.msh"                          # physical groups: curved, top, symmetry_x, symmetry_z, body
order = {order}

[material]
E = {E}
nu = {nu}
model = "neo-hookean"

[[support]]
boundary = "symmetry_x"                    # u_x = 0 on x = 0
components = [0]

[[support]]
boundary = "symmetry_z"                    # u_z = 0 on z = 0
components = [2]

[[support]]
boundary = "top"                           # flat face pushed down by delta
components = [1]
value = -{delta}
ramp = [[0.0, 0.0], [1.0, 1.0]]

[loading]
steps = {steps}

[obstacle]
type = "half-space"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]

[contact]
boundary = "curved"
kinematics = "finite"
"""


def build_mesh(path: str | Path, *, h: float = 0.25, radius: float = RADIUS, order: int = 2) -> Path:
    """Mesh the quarter hemisphere with Gmsh (second order by default) and write it to ``path``.

    Parameters
    ----------
    path : path-like
        Target ``.msh`` file (format 4.1).
    h : float
        Element size at the contact point (the origin); it grows to ``2.5 h`` away from it.
    radius : float
        Radius of the hemisphere.
    order : {1, 2}
        Element order of the mesh (2: ``tetra10`` with the edge nodes on the geometry).

    Returns
    -------
    Path
        ``path``.
    """
    import gmsh

    if h <= 0.0 or radius <= 0.0 or order not in (1, 2):
        raise ValueError(f"need h > 0, radius > 0 and order 1 or 2; got h={h}, radius={radius}, order={order}")
    path = Path(path)
    gmsh.initialize(readConfigFiles=False, interruptible=False)  # no user config, keep our signal handlers
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("ball")
        occ = gmsh.model.occ
        ball = occ.addSphere(0.0, radius, 0.0, radius)
        box = occ.addBox(-radius, 0.0, 0.0, radius, radius, radius)
        vol, _ = occ.intersect([(3, ball)], [(3, box)])
        occ.synchronize()
        tol = 1e-6 * radius
        faces = {"curved": [], "top": [], "symmetry_x": [], "symmetry_z": []}
        for _, tag in gmsh.model.getBoundary(vol, oriented=False):
            x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(2, tag)
            if x0 > -tol:
                faces["symmetry_x"].append(tag)
            elif z1 < tol:
                faces["symmetry_z"].append(tag)
            elif y0 > radius - tol:
                faces["top"].append(tag)
            else:
                faces["curved"].append(tag)
        for name, tags in faces.items():
            gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, tags), name)
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [t for _, t in vol]), "body")
        # size h at the contact point, growing to 2.5 h at distance R
        field = gmsh.model.mesh.field
        dist = field.add("MathEval")
        field.setString(dist, "F", f"{h} * (1 + 1.5 * Sqrt(x^2 + y^2 + z^2) / {radius})")
        field.setAsBackgroundMesh(dist)
        for key in ("Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature", "Mesh.MeshSizeExtendFromBoundary"):
            gmsh.option.setNumber(key, 0)
        gmsh.model.mesh.generate(3)
        if order == 2:
            gmsh.model.mesh.setOrder(2)  # edge nodes placed on the sphere
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        path.parent.mkdir(parents=True, exist_ok=True)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def write_problem(folder: str | Path, *, h: float = 0.25, order: int = 2, steps: int = 4) -> Path:
    """Write ``ball.msh`` (second order) and ``ball.toml`` into ``folder``; return the problem file."""
    folder = Path(folder)
    build_mesh(folder / "ball.msh", h=h)
    toml = folder / "ball.toml"
    toml.write_text(TOML.format(R=RADIUS, delta=DELTA, E=E, nu=NU, order=order, steps=steps), encoding="utf-8")
    return toml


def hertz_quarter_force(delta: float = DELTA, radius: float = RADIUS, e: float = E, nu: float = NU) -> float:
    """Hertz's small-deformation force of a quarter sphere, :math:`\\tfrac{1}{3} E^* R^{1/2} \\delta^{3/2}`."""
    return e / (1.0 - nu**2) * radius**0.5 * delta**1.5 / 3.0


def main(argv: list[str] | None = None) -> int:
    from alcontact.io import load_problem
    from alcontact.app import run_setup

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="results-curved-ball", help="folder for ball.msh, ball.toml and results/")
    ap.add_argument("--h", type=float, default=0.25, help="element size at the contact point")
    ap.add_argument("--order", type=int, default=2, choices=(1, 2), help="element order of the body (2: curved P2)")
    ap.add_argument("--steps", type=int, default=4, help="load steps")
    ap.add_argument("--force", action="store_true", help="overwrite an earlier results/ folder")
    args = ap.parse_args(argv)

    toml = write_problem(args.out, h=args.h, order=args.order, steps=args.steps)
    setup = load_problem(toml)
    print(setup.summary_line())
    res = run_setup(setup, Path(args.out) / "results", force=args.force)
    s = res.summary
    print(f"status {s['status']}; contact force {s['total_contact_force']:.5g} N (quarter model; Hertz, small "
          f"deformation: {hertz_quarter_force():.5g} N); results in {Path(args.out) / 'results'}")
    return 0 if s["status"] == "converged" else 1


if __name__ == "__main__":
    sys.exit(main())
