"""The problem-file schema: every TOML option with its type, default and one line of documentation.

This module is the single place where the options of a problem file are
declared. :mod:`alcontact.io.config` validates files against it and
``docs/problem-file.md`` is generated from it (:func:`render_markdown`)::

    python -m alcontact.io.schema            # rewrites docs/problem-file.md
    alcontact docs                           # the same from the command line

A table is a :class:`Table` of :class:`Option` objects; ``array=True`` marks an
array of tables (``[[support]]``), ``open=True`` a table that also takes keys
not listed (the obstacle's parameters, checked against the obstacle factory).
The ``[solver]`` options *are* the declarations of :class:`alcontact.contact.ContactOptions`,
the one options type of every solver (type, range, default and doc, see
:mod:`alcontact._options`); ``[solver.friction]`` repeats its friction-only ones. So the
file format, the Python API and the documentation cannot drift apart.

Examples
--------
>>> opt = option("solver.penalty_scale")
>>> opt.type, opt.default
('float', 100.0)
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

from .._options import (LINEAR_MODEL, MAX_CUTBACKS, MAX_STEPS, OBSTACLE_PATH, REQUIRED, TYPES, UNITS_OPTIONS,
                        VALUE_RANGE, Option, declarations)
from ._rigid import RIGID_OPTIONS

__all__ = [
    "REQUIRED",
    "TYPES",
    "Option",
    "Table",
    "table",
    "option",
    "render_markdown",
    "write_markdown",
    "repo_root",
    "DOCS_PATH",
    "MAX_STEPS",
    "VALUE_RANGE",
    "declarations",
]


# Option, REQUIRED and TYPES live in alcontact._options: the options dataclasses of the
# solvers declare their fields with the same Option, so each option is declared once.
@dataclass(frozen=True)
class Table:
    """A TOML table (``[path]``) or array of tables (``[[path]]``)."""

    path: str
    doc: str
    options: tuple[Option, ...]
    array: bool = False
    open: bool = False
    required: bool = False

    def get(self, name: str) -> Option | None:
        return next((o for o in self.options if o.name == name), None)

    @property
    def names(self) -> list[str]:
        return [o.name for o in self.options]


def _solver_options() -> tuple[tuple[Option, ...], tuple[Option, ...]]:
    """``[solver]`` and ``[solver.friction]`` options: the declarations of :class:`~alcontact.contact.ContactOptions`.

    Every field of the one options type is a ``[solver]`` key; the friction-only ones
    (declared ``only="friction"``) are also ``[solver.friction]`` keys, where problem files
    written before issue 9 set them.
    """
    from ..contact import ContactOptions

    contact = declarations(ContactOptions)
    return contact, tuple(o for o in contact if o.only == "friction")


def _algorithms(friction: bool = False) -> tuple[str, ...]:
    """Names of the registered algorithms (frictionless or frictional, small deformation)."""
    from ..contact import available_algorithms, friction_algorithms

    return tuple(friction_algorithms() if friction else available_algorithms())


def _volumetric() -> tuple[str, ...]:
    from ..fem.elasticity import VOLUMETRIC_FORMULATIONS

    return tuple(VOLUMETRIC_FORMULATIONS)


def _geometries() -> tuple[str, ...]:
    from ..fem import GEOMETRIES

    return tuple(GEOMETRIES)


def _penalties() -> tuple[str, ...]:
    from ..contact import contact_penalties

    return tuple(contact_penalties())


def _kinematics_option() -> Option:
    """``[contact] kinematics``: the contact kinematics (registry :data:`alcontact.contact.KINEMATICS`)."""
    from ..contact import KINEMATICS

    return Option("kinematics", "str", "small", "`small` (linearized gap, one solve per step) or `finite` (gap at "
                  "the deformed position, Newton in load steps with cut-backs; needs a hyperelastic "
                  "`material.model`).", choices=tuple(KINEMATICS))


def _formulations() -> tuple[str, ...]:
    from ..fem.mixed import FORMULATIONS

    return FORMULATIONS


def _material_model_option() -> Option:
    """``[material] model``: ``linear`` or a registered hyperelastic law (:func:`alcontact.fem.available_materials`)."""
    from ..fem import available_materials

    return Option("model", "str", None, "Constitutive law: `linear` (small strains) or a hyperelastic law for "
                  "`kinematics = \"finite\"` (default: `linear` for small, `neo-hookean` for finite kinematics); "
                  "its parameters go in `[material.parameters]`, see the tables below.",
                  choices=(LINEAR_MODEL,) + tuple(available_materials()))


def _build_schema() -> tuple[Table, ...]:
    from ..fem.meshes import MAX_CELLS_PER_AXIS

    contact, friction = _solver_options()
    O = Option  # noqa: E741 - short name for the table below
    knots = "list of `[t, factor]` pairs (increasing t), held constant before the first and after the last"
    return (
        Table("problem", "Name and description used in reports.", (
            O("name", "str", "contact", "Label in the summary, the plots and the report."),
            O("description", "str", "", "Free text copied into report.md."),
        )),
        Table("mesh", "The body: a built-in generator or a Gmsh file.", mesh_options := (
            O("generator", "str", "rectangle", "`rectangle` (2D triangles), `box` (3D tetrahedra) or `file`.",
              choices=("rectangle", "box", "file")),
            O("bounds", "floats", None, "Generators: `[x0, x1, y0, y1]` (rectangle) or `[x0, x1, y0, y1, z0, z1]` "
              "(box); boundaries left/right/bottom/top (+ front/back in 3D).", lengths=(4, 6)),
            O("cells", "ints", None, "Generators: cells per direction `[nx, ny]` / `[nx, ny, nz]` (the largest "
              "spacing when `[mesh.refine]` is given).", low=1, high=MAX_CELLS_PER_AXIS, lengths=(2, 3)),
            O("file", "str", "", "`file`: a Gmsh `.msh` (or `.geo` with the gmsh module), relative to the problem "
              "file; physical groups name the boundaries and regions."),
            O("group", "str", "", "`file`: the body is the cells of this physical group of the file (a surface "
              "in 2D, a volume in 3D), with the boundary groups that lie on it: several `[[body]]` tables read "
              "one file with several bodies, each its own `group` (a boundary group shared by several bodies, "
              "e.g. `top`, names each body's own part: `body0/top`, `body1/top`)."),
            O("order", "int", 1, "Polynomial order of the elements: 1 (P1) or 2 (P2).", low=1, high=2),
            O("volumetric", "str", "full", "Volumetric term of linear elasticity: `full` (standard element) or "
              "`p0` (order 2 only: the volumetric strain projected onto element-wise constants, the locking-free "
              "P2-P0 element; use it for nu near 0.5).", choices=_volumetric()),
            O("geometry", "str", "cartesian", "`cartesian` or `axisymmetric`: a 2D mesh in the r-z half-plane "
              "(x = r >= 0, y = z the axis) as a body of revolution, with the hoop strain u_r/r and 2 pi r in "
              "every integral; u_r = 0 on the axis is imposed, forces are totals over the revolution (the summary "
              "adds them per radian). Obstacles are then surfaces of revolution (a `circle` is a sphere, a "
              "`half-space` a plane normal to the axis, a cylinder, or, with an inclined normal, a cone with its apex "
              "on the axis; a `convex-polygon` a cylinder end or a groove). 2D only.", choices=_geometries()),
        ), required=True),
        Table("mesh.refine", "Optional grading of a generated mesh toward a point of its top face "
              "(the contact zone).", refine_options := (
            O("center", "floats", REQUIRED, "Point on the top face (`[x, y]` or `[x, y, z]`).", lengths=(2, 3)),
            O("h_min", "float", REQUIRED, "Element size in the fine zone.", low=0, low_open=True),
            O("width", "float", REQUIRED, "Half-width of the fine zone along the face.", low=0),
            O("depth", "float", REQUIRED, "Depth of the fine zone below the face.", low=0),
            O("growth", "float", 1.2, "Size ratio of neighbouring elements outside the fine zone.", low=1),
            O("h_max", "float", None, "Largest element size (default: the spacing of `cells`).",
              low=0, low_open=True),
        )),
        Table("material", "Isotropic elastic material of the whole body: linear elastic, or hyperelastic "
              "(`model`) for finite kinematics.", material_options := (
            O("E", "float", None, "Young's modulus (stress units, e.g. MPa). Required, except for a law whose "
              "parameters fix the shear modulus mu0 (`mooney-rivlin`, `yeoh`, `ogden`: default E = 2 mu0 (1 + nu), "
              "and a given E must equal it) and for `energy` (E and nu follow from it).", low=0, low_open=True),
            O("nu", "float", None, "Poisson's ratio (it sets the bulk modulus K = E / (3 (1 - 2 nu)) of the "
              "volumetric term). `0.5` is the exactly incompressible solid, whose pressure is a Lagrange "
              "multiplier: `formulation = \"mixed\"` only (finite kinematics, `mesh.order = 2`); every other "
              "body needs nu < 0.5. Required, except with `energy`.", low=-1, high=0.5, low_open=True),
            O("plane", "str", "strain", "2D assumption: `strain` or `stress` (ignored in 3D; hyperelastic: "
              "`strain` only).", choices=("strain", "stress")),
            _material_model_option(),
            O("formulation", "str", None, "Finite-element formulation of a hyperelastic body: `displacement` "
              "(the displacement element) or `mixed` (Taylor-Hood: P2 displacement and P1 pressure, for nearly "
              "incompressible rubber and nu = 0.5; finite kinematics, `mesh.order = 2`; straight-sided or curved "
              "second-order meshes, Cartesian or axisymmetric). Default: `mixed` where those hold and "
              "nu >= 0.49, else `displacement`.",
              choices=_formulations()),
            O("energy", "str", None, "A user hyperelastic law: its strain energy W as an expression of the "
              "invariants `I1`, `I2`, `I3`, `J`, `I1b`, `I2b`, the names of `[material.parameters]`, numbers, "
              "`+ - * / **` and `log`, `exp`, `sqrt`, e.g. `\"c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2\"` "
              "(finite kinematics; replaces `model`; parsed, never executed)."),
        ), required=True),
        Table("material.parameters", "Parameters of the hyperelastic law: the declared ones of `model` (tables "
              "below), or the names used in `energy`, e.g. `parameters = { c10 = 0.4, c01 = 0.1 }`.", (),
              open=True),
        Table("material.region", "Material of a mesh region (Gmsh physical group of cells). Names are checked "
              "against the mesh; constants different from `[material]` are rejected until the FEM layer "
              "supports several materials.", (
            O("name", "str", REQUIRED, "Physical name of the region in the mesh file."),
            O("E", "float", REQUIRED, "Young's modulus of the region.", low=0, low_open=True),
            O("nu", "float", REQUIRED, "Poisson's ratio of the region; `0.5` (exactly incompressible) where "
              "`[material]` says it too (the mixed body only, as `material.nu`).", low=-1, high=0.5,
              low_open=True),
            O("plane", "str", "strain", "2D assumption of the region.", choices=("strain", "stress")),
        ), array=True),
        Table("support", "Prescribed displacement on a named boundary (one table per support).", support_options := (
            O("boundary", "str", REQUIRED, "Boundary name of the mesh."),
            O("components", "ints", None, "Displacement components to prescribe, 0 = x, 1 = y, 2 = z "
              "(default: all).", low=0, high=2),
            O("value", "number-or-floats", 0.0, "Prescribed value: a number, one per listed component, or one per "
              "space dimension."),
            O("ramp", "knots", None, f"Amplitude over pseudo-time: {knots} (default: full value at every step)."),
            O("tangential", "bool", False, "Friction: marks a tangential (shearing) action, applied only once "
              "contact exists."),
        ), array=True),
        Table("load", "Surface or body load (one table per load).", load_options := (
            O("type", "str", REQUIRED, "`traction` (vector per area), `pressure` (normal, positive into the "
              "body) or `body-force` (vector per volume).", choices=("traction", "pressure", "body-force")),
            O("boundary", "str", "", "Boundary name (traction, pressure)."),
            O("vector", "floats", None, "Traction or body force vector, one number per space dimension.",
              lengths=(2, 3)),
            O("value", "float", None, "Pressure value."),
            O("ramp", "knots", None, f"Amplitude over pseudo-time: {knots} (default: full value at every step)."),
            O("tangential", "bool", False, "Friction: marks a tangential (shearing) load."),
        ), array=True),
        Table("body", "One of several deformable bodies (one table per body; replaces `[mesh]`, `[material]` "
              "and `[obstacle]`): the bodies are named `body0`, `body1`, ... in the order of the tables, and "
              "their boundaries `\"body0/top\"`, `\"body1/bottom\"`, ... in `[[support]]`, `[[load]]` and "
              "`[contact]` (a boundary name that only one body has may be given bare; `[[body.support]]` and "
              "`[[body.load]]` name the body's own boundaries bare). `[contact] boundary` "
              "(the slave) and `[contact] master` name the pair's two boundaries. Two-body contact is mortar "
              "(dual multipliers): at small kinematics linear elastic bodies, 2D (P1, P2 with straight edges; "
              "frictionless or with Coulomb friction, `[contact] friction`: the slip is the relative tangential "
              "displacement of the two surfaces) or 3D (linear tetrahedra, `order = 1`; frictionless); at "
              "`kinematics = \"finite\"` hyperelastic 2D P1 bodies, frictionless (the gap at the current "
              "configuration, large sliding).", (), array=True),
        Table("body.mesh", "The body's mesh: the keys of `[mesh]`.", mesh_options),
        Table("body.mesh.refine", "Grading of the body's generated mesh: the keys of `[mesh.refine]`.",
              refine_options),
        Table("body.material", "The body's material: `E`, `nu`, `plane` and `model` of `[material]` (`model` a "
              "hyperelastic law with `[contact] kinematics = \"finite\"`, default `neo-hookean` there, `linear` "
              "for small kinematics).", material_options[:4]),
        Table("body.material.parameters", "Parameters of the body's hyperelastic law: the keys of "
              "`[material.parameters]`.", (), open=True),
        Table("body.support", "A support of the body: the keys of `[[support]]`, the boundary one of this body's "
              "(bare name).", support_options, array=True),
        Table("body.load", "A traction or pressure on a boundary of the body: the keys of `[[load]]` (a body force "
              "goes in the top-level `[[load]]`, where it acts on every body).", load_options, array=True),
        Table("loading", "Load history: the pseudo-times of the load steps (supports and loads with a `ramp` "
              "are scaled by it).", (
            O("steps", "int", 1, "Number of equal load steps on (0, t_end] (ignored when `times` is given).",
              low=1, high=MAX_STEPS),
            O("t_end", "float", 1.0, "Last pseudo-time of equal steps.", low=0, low_open=True),
            O("times", "floats", None, "Explicit step times, positive and strictly increasing.",
              low=0, low_open=True),
            O("friction_ramp", "knots", None, f"Factor of the friction coefficient: {knots} (default 1)."),
            MAX_CUTBACKS,
        )),
        Table("obstacle", "Rigid obstacle from the registry (`alcontact list obstacles`); every other key is a "
              "parameter of that obstacle, e.g. `center`, `radius`, `point`, `normal`, `vertices`. With "
              "`reference` the obstacle is a rigid body: each component of its pose (translation of the reference "
              "point, rotation about it) is prescribed (`displacement_x`, ..., `rotation`), force driven and solved "
              "for (`force_x`, ..., `moment`) or, given neither, held at zero; its pose, contact force and moment "
              "and reaction are in `summary.json` (`rigid_bodies`), `steps.csv` and `reaction_force.csv` "
              "(`rigid_body1_*` columns). The body is then `body0`, the rigid body `body1`.", (
            O("type", "str", REQUIRED, "Registered obstacle name, e.g. `circle`, `sphere`, `half-space`, "
              "`convex-polygon`, `surface` (a meshed rigid surface, non-convex allowed: `file` = an STL or Gmsh "
              "file relative to this file, optional `group` = a Gmsh physical group)."),
            OBSTACLE_PATH,
            *RIGID_OPTIONS,
        ), open=True, required=True),
        Table("pair", "A further contact pair (one table per pair): its own contact boundary against its own "
              "rigid obstacle, e.g. a block squeezed between two plates. `type` and every other key are the "
              "obstacle's, as in `[obstacle]` (which is the obstacle of `[contact] boundary`); with `[[body]]` "
              "tables a pair may instead join two bodies (`master`, a boundary of another body, as `[contact] "
              "master`), and a rigid pair acts on the body of its `boundary` (e.g. `\"body1/top\"`). Each pair has "
              "its own Coulomb coefficient (`friction`, default `[contact] friction`), `kinematics` applies to "
              "every pair (at finite kinematics: frictionless, no `[obstacle] path`; with `[[body]]` tables only "
              "pairs between bodies, e.g. a ring squeezed between two plates).", (
            O("boundary", "str", REQUIRED, "Boundary of the body that may touch this pair's obstacle (the slave)."),
            O("type", "str", "", "Registered obstacle name, as `[obstacle] type` (required unless `master` is "
              "given)."),
            O("master", "str", "", "With `[[body]]`: the master boundary of a pair between two bodies, a boundary "
              "of another body (instead of `type`)."),
            O("friction", "float", None, "Coulomb coefficient mu of this pair (default: `[contact] friction`; 0: "
              "frictionless).", low=0, high=VALUE_RANGE[1]),
        ), array=True, open=True),
        Table("contact", "Contact boundary and friction.", (
            O("boundary", "str", REQUIRED, "Boundary of the body that may touch the obstacle (with `[[body]]`: "
              "the slave boundary of the two-body pair, e.g. `\"body1/bottom\"`)."),
            O("master", "str", "", "With `[[body]]`: the master boundary of the pair, a boundary of another "
              "body (or another boundary of the same body), e.g. `\"body0/top\"`; it replaces `[obstacle]`."),
            O("friction", "float", 0.0, "Coulomb coefficient mu of the pair of `boundary` (0: frictionless; > 0 "
              "uses the frictional solver over the load steps; `[[pair]]` tables may give their own).", low=0),
            _kinematics_option(),
        ), required=True),
        Table("solver", "Contact algorithm, penalty and their parameters.", (
            O("algorithm", "str", "simo-laursen", "Contact algorithm (friction: "
              f"{', '.join(f'`{a}`' for a in _algorithms(friction=True))}; `alcontact list` shows what each "
              "supports).", choices=_algorithms()),
            O("penalty", "str", "", "Penalty of `family-p` (default `exp-met1`); the other algorithms fix it.",
              choices=("",) + _penalties()),
        ) + contact),
        Table("solver.petsc_options", "PETSc options passed through to the PETSc linear solver that runs "
              "(`linear_solver = \"petsc\"` or `\"petsc-direct\"`), names without the leading dash, e.g. "
              "`petsc_options = { ksp_type = \"cg\", pc_type = \"gamg\", ksp_rtol = 1e-10 }`; values are strings, "
              "numbers or `true` (a flag). An option PETSc does not use (a typo) is reported as a warning.", (),
              open=True),
        Table("solver.friction", "The friction-only options of `[solver]` (used when `contact.friction > 0`), "
              "also accepted here; a key set in both tables must have the same value.", friction),
        Table("reference", "Analytical reference drawn in the plots and compared in the summary.", (
            O("kind", "str", "none", "`none`, `hertz` (cylinder in 2D, sphere in 3D) or `cattaneo-mindlin` "
              "(2D, friction).", choices=("none", "hertz", "cattaneo-mindlin")),
            O("radius", "float", None, "Radius R of the indenter (hertz, cattaneo-mindlin); the formulas divide "
              "by it and square it, so it lies in 1e-100 .. 1e100.", low=VALUE_RANGE[0], high=VALUE_RANGE[1]),
            O("symmetry", "float", 1.0, "Total load / model load: 2 for a half model, 4 for a quarter model "
              "(1e-100 .. 1e100).", low=VALUE_RANGE[0], high=VALUE_RANGE[1]),
            O("center", "floats", None, "First contact point (default: the origin); contact widths are "
              "measured from it.", lengths=(2, 3)),
            O("axis", "int", 0, "Coordinate along which the contact width is measured.", low=0, high=2),
        )),
        Table("units", "Units of the numbers in this file, for the labels of every plot, table and summary "
              "(nothing is converted: the numbers must form a consistent set, force = stress x length^2). "
              "Without it the labels say `L` (length) and `[E]` (the unit of Young's modulus).", UNITS_OPTIONS),
        Table("output", "What to write into the results folder.", (
            O("folder", "str", "results", "Results folder when `--out` is not given (relative to the current "
              "directory)."),
            O("vtu", "bool", True, "solution.vtu: displacement, stress, contact pressure, gap (+ slip, state)."),
            O("series", "bool", True, "Load-stepped runs: one VTU per step and solution.pvd (ParaView time "
              "series)."),
            O("csv", "bool", True, "history.csv (iterations) and steps.csv (load steps)."),
            O("plots", "bool", True, "pressure.png, convergence.png and load_displacement.png (stepped runs)."),
            O("report", "bool", True, "report.md: a one-page summary tying the files together."),
        )),
    )


_SCHEMA: tuple[Table, ...] | None = None


def schema() -> tuple[Table, ...]:
    """The tables of a problem file (built on first use: it reads the solver registries)."""
    global _SCHEMA
    if _SCHEMA is None:
        _SCHEMA = _build_schema()
    return _SCHEMA


def __getattr__(name: str):  # SCHEMA is built lazily (module attribute access)
    if name == "SCHEMA":
        return schema()
    raise AttributeError(name)


def table(path: str) -> Table:
    """The table at ``path`` (e.g. ``"solver.friction"``); ``KeyError`` if unknown."""
    for t in schema():
        if t.path == path:
            return t
    raise KeyError(path)


def option(dotted: str) -> Option:
    """The option at ``"table.key"`` (e.g. ``"solver.penalty_scale"``)."""
    path, _, name = dotted.rpartition(".")
    opt = table(path).get(name)
    if opt is None:
        raise KeyError(dotted)
    return opt


def _default_text(o: Option) -> str:
    if o.required:
        return "**required**"
    if o.default is None:
        return "automatic"
    if isinstance(o.default, bool):
        return f"`{str(o.default).lower()}`"
    if isinstance(o.default, str):
        return f'`"{o.default}"`'
    return f"`{o.default!r}`"


_EXAMPLE = """\
[problem]
name = "hertz-2d"

[mesh]
generator = "rectangle"
bounds = [0.0, 20.0, -20.0, 0.0]      # half model x >= 0
cells = [8, 8]
refine = { center = [0.0, 0.0], h_min = 0.0625, width = 1.6, depth = 1.0, growth = 1.15 }

[material]
E = 200e3
nu = 0.3

[[support]]
boundary = "bottom"                    # all components fixed

[[support]]
boundary = "left"                      # symmetry: u_x = 0
components = [0]

[obstacle]
type = "circle"
center = [0.0, 9.9]
radius = 10.0

[contact]
boundary = "top"

[solver]
algorithm = "simo-laursen"

[reference]
kind = "hertz"
radius = 10.0
symmetry = 2.0
"""


def render_markdown() -> str:
    """``docs/problem-file.md``: every table and option of the schema."""
    lines = [
        "# Problem files",
        "",
        "<!-- generated by `python -m alcontact.io.schema` (or `alcontact docs`) from",
        "     src/alcontact/io/schema.py; do not edit by hand -->",
        "",
        "A problem file is TOML. Run it with `alcontact run PROBLEM.toml --out DIR`; check it without",
        "solving with `alcontact check PROBLEM.toml`. Unknown keys, wrong types, values out of range,",
        "boundary names the mesh does not have and unreadable meshes are all reported together, each",
        "with its key path (e.g. `solver.penalty_scale`), before anything is solved. Examples are in",
        "`examples/`.",
        "",
        "```toml",
        _EXAMPLE.rstrip(),
        "```",
        "",
        "Load steps: supports and loads without a `ramp` act at full value at every step; those with a",
        "`ramp = [[t0, f0], [t1, f1], ...]` are scaled by the piecewise-linear factor at each step time",
        "(`[loading]`). Frictionless problems are solved independently at each step (they are path",
        "independent); with `contact.friction > 0` the frictional solver follows the steps in order.",
        "",
        "Materials: one `[material]` for the whole body. `[[material.region]]` entries are validated",
        "(the region must exist in the mesh) but a region whose constants differ from `[material]` is",
        "rejected with an error: the FEM layer uses one material per body for now.",
        "",
        "TOML holds data and registry names only (no code): the `user` obstacle cannot be used from a file.",
        "",
        "Finite deformation: `[contact] kinematics = \"finite\"` with a hyperelastic `[material] model`",
        "(the laws of `[material.parameters]` below, or a user `energy`) solves the frictionless problem in the load steps of",
        "`[loading]`, each from the last one, with Newton on the deformed configuration; a step that",
        "fails is cut back (`loading.max_cutbacks` halvings). Supports and loads with a `ramp` follow it;",
        "when nothing has a ramp, every support value and load grows in proportion to t. `[obstacle] path`",
        "moves the obstacle rigidly by `t * path`. The results hold the deformed configuration of every",
        "step (`solution.pvd`), the reaction-force curve (`steps.csv`, `reaction_force.png`) and the",
        "Newton iterations of every step (`summary.json`: `step_newton_iterations`). With",
        "`[contact] friction > 0` the same steps solve Coulomb friction in the deformed configuration",
        "(Algorithms 6.2 / 6.4, `[solver.friction]` options; no `friction_ramp`): the results add the",
        "slip and stick/slip state of every step, the tangential reaction and the frictional",
        "dissipation (`summary.json`: `step_dissipation`).",
        "",
        "Linear solver at finite deformation (`[solver] linear_solver`): `direct` (default; one MKL PARDISO",
        "factorization per Newton iteration, symmetric indefinite) or `amg` for `penalty`, `simo-laursen`",
        "and `family-p`: each Newton system by CG preconditioned with smoothed-aggregation AMG (rigid-body",
        "modes of the current configuration), the hierarchy kept while the CG iteration counts stay low,",
        "the CG tolerance following the Newton residual (Eisenstat-Walker); a Newton matrix that is not",
        "positive definite is solved directly (`summary.json`: `direct_fallbacks`). No factor is stored,",
        "so memory stays near that of the matrix; `ssn` (saddle-point systems) is direct-only and",
        "`ssn` with `amg` is refused. `summary.json` names the path (`linear_solver`) with `cg_iterations`,",
        "`cg_per_newton` and `amg_setups`; measurements in `docs/benchmarks/finite_amg.md`.",
        "",
    ]
    for t in schema():
        head = f"[[{t.path}]]" if t.array else f"[{t.path}]"
        flags = []
        if t.required:
            flags.append("required")
        if t.array:
            flags.append("repeatable")
        lines += [f"## `{head}`" + (f" ({', '.join(flags)})" if flags else ""), "", t.doc, ""]
        if t.options:
            lines += ["| key | type | default | allowed | description |", "|---|---|---|---|---|"]
            for o in t.options:
                lines.append(f"| `{o.name}` | {o.type} | {_default_text(o)} | {o.range_text()} | {o.doc} |")
            lines.append("")
        if t.path == "material.parameters":
            lines += _law_parameter_tables()
    return "\n".join(lines)


def _law_parameter_tables() -> list[str]:
    """One table of declared parameters per hyperelastic law that has any (from the registry)."""
    from ..fem import available_materials, example_material_parameters, make_material, material_parameters

    lines = ["Every hyperelastic law is compressible: the volumetric term K/2 (J - 1)^2 of the laws with",
             "parameters uses the bulk modulus K = E / (3 (1 - 2 nu)); at F = I each law linearizes to the",
             "linear elasticity of E and nu (checked when the body is built). I1b = J^(-2/3) I1 and",
             "I2b = J^(-4/3) I2 are the isochoric invariants of C = F^T F, J = det F.", ""]
    for name in available_materials():
        decl = material_parameters(name)
        summary = type(make_material(name, **example_material_parameters(name))).SUMMARY
        if not decl:
            lines += [f"### `model = \"{name}\"`", "", summary, ""]
            continue
        lines += [f"### `model = \"{name}\"`", "", summary, "", "| key | type | default | allowed | description |",
                  "|---|---|---|---|---|"]
        for o in decl:
            lines.append(f"| `{o.name}` | {o.type} | {_default_text(o)} | {o.range_text()} | {o.doc} |")
        example = ", ".join(f"{k} = {v!r}" for k, v in example_material_parameters(name).items())
        lines += ["", f"Example: `parameters = {{ {example} }}`.", ""]
    lines += ["A user law: `energy = \"...\"` (instead of `model`) with its constants in `[material.parameters]`;",
              "the expression is the whole energy (add a volumetric term such as `K/2*(J-1)**2`), must be",
              "stress free at F = I, and fixes E and nu through its initial shear and bulk moduli.", ""]
    return lines


def repo_root() -> Path:
    """The root of the source checkout (the folder of ``examples/``, ``benchmarks/`` and ``docs/``)."""
    return Path(__file__).resolve().parents[3]




#: Where the generated documentation lives in the repository.
DOCS_PATH = Path("docs") / "problem-file.md"


def write_markdown(path: str | Path | None = None) -> Path:
    """Write :func:`render_markdown` to ``path`` (default ``<repository>/docs/problem-file.md``)."""
    from .results import write_text_atomic

    target = Path(path) if path is not None else repo_root() / DOCS_PATH
    target.parent.mkdir(parents=True, exist_ok=True)
    return write_text_atomic(target, render_markdown())


if __name__ == "__main__":  # pragma: no cover - exercised through `alcontact docs`
    out = write_markdown(sys.argv[1] if len(sys.argv) > 1 else None)
    print(f"wrote {out}")
