"""Build a Gmsh mesh with physical groups and solve it: an elastic punch with a rounded corner.

An elastic punch (plane strain, half model x >= 0) of half-width ``b`` and height ``H``
whose bottom corner at x = b is rounded with radius ``r`` is pressed onto a rigid flat
foundation (the half-space y <= 0) by pushing its top face down by ``delta`` in four load
steps (1 % nominal strain). The flat part of the bottom, x in [0, b - r], comes fully into
contact and the contact zone grows onto the rounded corner with the load (to x = 0.77 of
b = 1, r = 0.25 at the last step), instead of stopping at a sharp corner with a singular
pressure; the pressure peaks where the flat part meets the corner.

What the script does:

1. builds the geometry with the Gmsh Python API (built-in kernel: lines and a circle arc),
   refines the mesh towards the bottom, and names the parts with physical groups:
   ``contact`` (flat bottom + rounded corner), ``top``, ``symmetry`` (x = 0), ``side``
   (x = b) and ``body`` (the surface);
2. writes ``punch.msh`` (Gmsh format 4.1) and a problem file ``punch.toml`` that uses it
   (``[mesh] generator = "file"``, supports and contact on the physical group names);
3. solves it as ``alcontact run punch.toml`` would (:func:`alcontact.io.load_problem`,
   :func:`alcontact.app.run_setup`) and writes the results folder ``results/``.

Run from the repository root::

    python examples/gmsh_punch.py --out results-gmsh-punch          # about 5 s
    python examples/gmsh_punch.py --out results-gmsh-punch --h 0.01 # finer mesh
    alcontact run results-gmsh-punch/punch.toml --out other-folder   # the same problem from the CLI

Units: mm and MPa (E = 200 GPa steel on a rigid foundation).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

#: Geometry (mm), material (MPa) and load of the example.
B, H, R, DELTA = 1.0, 1.0, 0.25, 0.01
E, NU = 200e3, 0.3

TOML = """\
# Written by examples/gmsh_punch.py: elastic punch with a rounded corner on a rigid foundation.
[problem]
name = "gmsh-punch"
description = "Elastic punch (half-width {b}, corner radius {r}, Gmsh mesh) pressed onto a rigid plane by {delta}."

[mesh]
generator = "file"
file = "punch.msh"                         # physical groups: contact, top, symmetry, side, body

[material]
E = {E}
nu = {nu}
plane = "strain"

[[support]]
boundary = "symmetry"                      # u_x = 0 on x = 0
components = [0]

[[support]]
boundary = "top"                           # pushed down by delta
components = [1]
value = -{delta}
ramp = [[0.0, 0.0], [1.0, 1.0]]

[loading]
steps = 4

[obstacle]
type = "half-space"
point = [0.0, 0.0]
normal = [0.0, 1.0]

[contact]
boundary = "contact"

[solver]
algorithm = "simo-laursen"
"""


def build_mesh(path: str | Path, *, h: float = 0.02, b: float = B, height: float = H, r: float = R) -> Path:
    """Mesh the half punch with Gmsh and write it with physical groups to ``path`` (.msh 4.1).

    Parameters
    ----------
    path : path-like
        Target ``.msh`` file.
    h : float
        Element size along the bottom (contact) face; it grows to ``10 h`` (at most
        ``height / 4``) at the top.
    b, height, r : float
        Half-width, height and corner radius (``0 < r < min(b, height)``).

    Returns
    -------
    Path
        ``path``.
    """
    import gmsh

    if not (0.0 < r < min(b, height)) or h <= 0.0:
        raise ValueError(f"need 0 < r < min(b, height) and h > 0; got r={r}, b={b}, height={height}, h={h}")
    h_top = min(10.0 * h, height / 4.0)
    path = Path(path)
    gmsh.initialize(readConfigFiles=False, interruptible=False)  # no user config, keep our signal handlers
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("punch")
        geo = gmsh.model.geo
        p0 = geo.addPoint(0.0, 0.0, 0.0, h)            # bottom, on the symmetry plane
        p1 = geo.addPoint(b - r, 0.0, 0.0, h)          # start of the rounded corner
        pc = geo.addPoint(b - r, r, 0.0, h)            # centre of the corner arc
        p2 = geo.addPoint(b, r, 0.0, h)                # end of the rounded corner
        p3 = geo.addPoint(b, height, 0.0, h_top)
        p4 = geo.addPoint(0.0, height, 0.0, h_top)
        bottom = geo.addLine(p0, p1)
        corner = geo.addCircleArc(p1, pc, p2)
        side = geo.addLine(p2, p3)
        top = geo.addLine(p3, p4)
        sym = geo.addLine(p4, p0)
        loop = geo.addCurveLoop([bottom, corner, side, top, sym])
        surf = geo.addPlaneSurface([loop])
        geo.synchronize()
        for name, dim, tags in (("contact", 1, [bottom, corner]), ("top", 1, [top]), ("symmetry", 1, [sym]),
                                ("side", 1, [side]), ("body", 2, [surf])):
            gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        path.parent.mkdir(parents=True, exist_ok=True)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def write_problem(folder: str | Path, *, h: float = 0.02) -> Path:
    """Write ``punch.msh`` and ``punch.toml`` into ``folder``; return the problem file."""
    folder = Path(folder)
    build_mesh(folder / "punch.msh", h=h)
    toml = folder / "punch.toml"
    toml.write_text(TOML.format(b=B, r=R, delta=DELTA, E=E, nu=NU), encoding="utf-8")
    return toml


def main(argv: list[str] | None = None) -> int:
    from alcontact.io import load_problem
    from alcontact.app import run_setup

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="results-gmsh-punch", help="folder for punch.msh, punch.toml and results/")
    ap.add_argument("--h", type=float, default=0.02, help="element size on the contact face (mm)")
    ap.add_argument("--force", action="store_true", help="overwrite an earlier results/ folder")
    args = ap.parse_args(argv)

    toml = write_problem(args.out, h=args.h)
    setup = load_problem(toml)
    print(setup.summary_line())
    res = run_setup(setup, Path(args.out) / "results", force=args.force)
    s = res.summary
    final = res.frames[-1]
    x = final.points[final.active, 0]
    print(f"status {s['status']}; contact zone x in [{x.min():.4g}, {x.max():.4g}] mm "
          f"(flat part ends at x = {B - R:g}, corner at x = {B:g}); total contact force "
          f"{s['total_contact_force']:.5g} N/mm; results in {Path(args.out) / 'results'}")
    return 0 if s["status"] == "converged" else 1


if __name__ == "__main__":
    sys.exit(main())
