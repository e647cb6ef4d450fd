"""One builder per section of a problem file.

:func:`alcontact.io.config.load_problem` validates a file against the schema, then
builds it here, section by section and in this order (the order of the issues):

====================  ==========================================  =========================
section               builder                                     builds
====================  ==========================================  =========================
``[mesh]``            :func:`build_mesh`                          the mesh, its dimension
``[contact]``         :func:`build_kinematics`                    kinematics, material model
``[material]``        :func:`build_material`                      material, hyperelastic law
``[contact]``         :func:`check_contact_boundary`              the contact boundary
``[[support]]``       :func:`build_supports`                      fixed and ramped supports
``[[load]]``          :func:`build_loads`                         fixed and ramped loads
``[loading]``         :func:`build_loading`                       step times, friction ramp
``[obstacle]``        :func:`build_obstacle`                      the rigid obstacle
``[[pair]]``          :func:`build_pairs`                         further contact pairs
``[solver]``          :func:`build_solver`                        algorithm, penalty, options
``[units]``           :func:`build_units`                         the unit labels
``[reference]``       :func:`build_reference`                     Hertz / Cattaneo-Mindlin
``[[body]]``          :func:`build_bodies`                        several bodies, their pair
(all)                 :func:`build_model`, :func:`build_problem`  model, problem, history
====================  ==========================================  =========================

Every builder takes the section's normalized table (defaults filled in, values
that failed the schema pass marked :data:`~alcontact._options.BAD`) and the list
of issues; it appends an :class:`~alcontact.io._issues.Issue` for each problem
(key path and the way out) and returns what it could build (``None`` where
nothing could be built), so that one run reports every problem of the file.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._options import BAD, ENERGY_MODEL, LINEAR_MODEL, declarations, units_issues
from ..errors import InputError, MeshError, UnknownNameError
from ._issues import Issue, _did_you_mean, _known, _num, _ok

__all__ = ["Sections", "build_sections", "build_model", "build_problem"]


def _quiet():
    """Keep meshio's and scikit-fem's prints (and meshio's ``sys.exit``) away from the user."""
    stack = contextlib.ExitStack()
    stack.enter_context(contextlib.redirect_stdout(io.StringIO()))
    stack.enter_context(contextlib.redirect_stderr(io.StringIO()))
    return stack


# --------------------------------------------------------------------------- [mesh]
def _read_mesh_file(d: dict, base: Path, issues: list[Issue]):
    """``generator = "file"``: the mesh read from ``file`` (relative to the problem file's folder)."""
    from ..fem import meshes

    if d["file"] is BAD:  # the schema pass recorded the issue
        return None
    if not d["file"]:
        issues.append(Issue("mesh.file", "missing: generator = 'file' needs file = 'body.msh'."))
        return None
    for key in ("bounds", "cells", "refine"):
        if d[key] is not None:
            issues.append(Issue(f"mesh.{key}", "not used with generator = 'file'; remove it (or use "
                                               "generator = 'rectangle' / 'box')."))
    p = Path(d["file"])
    p = p if p.is_absolute() else base / p
    try:
        with _quiet():  # meshio prints and calls sys.exit(1) on some unreadable files
            mesh = meshes.read(p)
    except MeshError as exc:
        issues.append(Issue("mesh.file", f"= {d['file']!r}: {exc}"))
    except SystemExit:
        issues.append(Issue("mesh.file", f"= {d['file']!r}: cannot read mesh file {str(p)!r} (meshio gave up). "
                                         "Export it from Gmsh as .msh (format 2.2 or 4.1)."))
    else:
        if not d.get("group"):
            return mesh
        try:  # one body of a file of several (fem.meshes.select_group)
            return meshes.select_group(mesh, d["group"])
        except MeshError as exc:
            issues.append(Issue("mesh.group", f"= {d['group']!r}: {d['file']!r}: {exc}"))
    return None


def _grid_ok(d: dict, gen: str, dim: int, issues: list[Issue]) -> bool:
    """``bounds`` and ``cells`` of a generated mesh: present, of the right length, non-empty ranges."""
    ok = True
    for key in ("file", "group"):
        if d.get(key):
            issues.append(Issue(f"mesh.{key}", f"not used with generator = {gen!r}; remove it or set "
                                               "generator = 'file'."))
            ok = False
    for key, n, example in (("bounds", 2 * dim, "[0.0, 1.0, 0.0, 1.0]" if dim == 2 else "[0, 1, 0, 1, 0, 1]"),
                            ("cells", dim, "[8, 8]" if dim == 2 else "[4, 4, 4]")):
        v = d[key]
        if v is BAD:
            ok = False
        elif v is None:
            issues.append(Issue(f"mesh.{key}", f"missing: generator = {gen!r} needs {key} = {example}."))
            ok = False
        elif len(v) != n:
            issues.append(Issue(f"mesh.{key}", f"= {v!r}: generator = {gen!r} needs {n} entries, e.g. "
                                               f"{key} = {example}."))
            ok = False
    if ok:
        b = d["bounds"]
        for k, ax in enumerate("xyz"[:dim]):
            if not b[2 * k] < b[2 * k + 1]:
                issues.append(Issue("mesh.bounds", f"= {b!r}: the {ax} range [{b[2 * k]:g}, {b[2 * k + 1]:g}] is "
                                                   f"empty; give lower < upper."))
                ok = False
    return ok


def _refine_ok(refine: dict | None, dim: int, issues: list[Issue]) -> bool:
    """``[mesh.refine]`` (absent, or valid with a centre of ``dim`` coordinates)."""
    if refine is None:
        return True
    if refine is BAD or any(v is BAD for v in refine.values()):
        return False
    if len(refine["center"]) != dim:
        issues.append(Issue("mesh.refine.center", f"= {refine['center']!r}: needs {dim} coordinates for a "
                                                  f"{dim}D mesh."))
        return False
    return True


def _generate_mesh(d: dict, issues: list[Issue]):
    """``generator = "rectangle"`` / ``"box"``: the structured mesh of ``bounds`` and ``cells``."""
    from ..fem import meshes

    gen = d["generator"]
    dim = 2 if gen == "rectangle" else 3
    grid = _grid_ok(d, gen, dim, issues)
    refine = d["refine"]
    if not (_refine_ok(refine, dim, issues) and grid):
        return None
    r = None if refine is None else {k: v for k, v in refine.items() if v is not None}
    fn = meshes.rectangle if dim == 2 else meshes.box
    return _num(issues, "mesh", fn, *d["bounds"], *d["cells"], refine=r)


def low_dim_issue(md: dict, base: Path, issue: Issue) -> Issue:
    """Say which physical groups a Gmsh file has and how to add one for the body."""
    from ..fem import meshes

    p = Path(md["file"])
    p = p if p.is_absolute() else base / p
    try:
        with _quiet():
            mesh = meshes.read(p)
    except (MeshError, SystemExit):
        return issue
    dim = int(mesh.dim())
    groups = sorted(set((mesh.boundaries or {}).keys()) | set((mesh.subdomains or {}).keys()))
    kind = {0: "points", 1: "curves"}.get(dim, "cells")
    body = "Physical Surface(\"body\") = {...};  (Physical Volume in 3D)"
    return Issue("mesh.file", f"= {md['file']!r}: the file holds only {dim}D elements ({kind}); its physical "
                              f"groups are {', '.join(map(repr, groups)) or '(none)'}. Gmsh saves only the "
                              "elements of physical groups once any is defined, so the body's triangles/"
                              f"tetrahedra were left out: add a physical group for the body, e.g. {body} in "
                              "the .geo file (or in the GUI: Modules > Geometry > Physical groups > Add > "
                              "Surface/Volume), or save all elements (gmsh -save_all, Mesh.SaveAll = 1), "
                              "then re-mesh.")


def build_mesh(md: dict | None, base: Path, issues: list[Issue]) -> tuple[Any, int | None]:
    """``[mesh]``: ``(mesh, dim)``, read (``generator = "file"``) or generated; ``(None, None)`` on an issue.

    A mesh that is not 2D or 3D is an issue too (a Gmsh file: the issue names its
    physical groups and how to add one for the body, :func:`low_dim_issue`).
    """
    if md is None or md is BAD or md["generator"] is BAD:
        return None, None
    mesh = _read_mesh_file(md, base, issues) if md["generator"] == "file" else _generate_mesh(md, issues)
    if mesh is None:
        return None, None
    dim = int(mesh.dim())
    if dim in (2, 3):
        return mesh, dim
    issue = Issue("mesh", f"the mesh is {dim}D; contact problems need a 2D or 3D mesh.")
    if md.get("generator") == "file":  # a Gmsh file without a body group: say which groups it has
        issue = low_dim_issue(md, base, issue)
    issues.append(issue)
    return None, None


def boundary_ok(mesh, name: str, path: str, issues: list[Issue]) -> bool:
    """``name`` is a boundary of ``mesh`` (else an issue at ``path`` with the mesh's boundary names)."""
    known = sorted((mesh.boundaries or {}).keys())
    if name in known:
        return True
    issues.append(Issue(path, f"= {name!r}: the mesh has no boundary {name!r}.{_did_you_mean(name, known)} "
                              f"Mesh boundaries: {_known(known)}."))
    return False


def _ramp(knots):
    from ..contact import Ramp

    return Ramp(tuple(k[0] for k in knots), tuple(k[1] for k in knots), hold_before=True, hold_after=True)


# --------------------------------------------------------------------------- kinematics and [material]
def _model_name(mt: Any, kin: str, issues: list[Issue]) -> tuple[str | None, bool]:
    """``(material model or None, go on)``: ``model``, or the user law of ``energy`` (which needs finite
    kinematics: ``go on`` is ``False`` after that issue)."""
    model = mt.get("model") if isinstance(mt, dict) else None
    if model is BAD:
        model = None
    energy = mt.get("energy") if isinstance(mt, dict) else None
    if energy is None or energy is BAD:
        return model, True
    if model is not None:
        issues.append(Issue("material.energy", f"given together with model = {model!r}: a user energy is "
                                               "its own law; remove one of model and energy."))
    if kin != "finite":
        issues.append(Issue("contact.kinematics", "= 'small': a user material.energy is a hyperelastic law "
                                                  "and needs kinematics = 'finite'."))
        return ENERGY_MODEL, False
    return ENERGY_MODEL, True


def _finite_issues(mt: Any, cd: Any, dim: int | None, data: dict, issues: list[Issue]) -> None:
    """Finite kinematics: no friction amplitude with friction, plane strain in 2D."""
    mu = cd.get("friction") if isinstance(cd, dict) else 0.0
    lo = data.get("loading")
    ramp = lo.get("friction_ramp") if isinstance(lo, dict) else None
    if isinstance(mu, float) and mu > 0 and ramp is not None and ramp is not BAD:
        issues.append(Issue("loading.friction_ramp", "a friction amplitude is not available with "
                                                     "contact.kinematics = 'finite' (the coefficient is "
                                                     "constant); remove friction_ramp, or use kinematics = "
                                                     "'small'."))
    if dim == 2 and isinstance(mt, dict) and mt.get("plane") == "stress":
        issues.append(Issue("material.plane", "= 'stress': hyperelastic bodies in 2D are plane strain only; "
                                              "set plane = 'strain' or use a 3D mesh."))


def _path_issues(od: Any, finite: bool, dim: int | None, issues: list[Issue]) -> None:
    """``[obstacle] path``: finite kinematics only, one entry per space dimension."""
    path = od.get("path") if isinstance(od, dict) else None
    if path is None or path is BAD:
        return
    if not finite:
        issues.append(Issue("obstacle.path", "a moving obstacle needs contact.kinematics = 'finite'; remove "
                                             "path (small kinematics: move the body with a ramped support)."))
    elif dim is not None and len(path) != dim:
        issues.append(Issue("obstacle.path", f"= {path!r}: needs {dim} numbers (a translation per unit "
                                             f"pseudo-time) for a {dim}D mesh."))


def build_kinematics(mt, cd, dim, data: dict, issues: list[Issue]) -> tuple[str, str]:
    """``[contact] kinematics`` and ``[material] model``: ``(kinematics, material model)``, with an issue for
    each combination that cannot run.

    Finite kinematics needs a hyperelastic law (plane strain in 2D) and, with friction
    (Coulomb at finite deformation, :func:`~alcontact.contact.solve`), no
    ``friction_ramp``; a hyperelastic law needs finite kinematics; ``[obstacle] path``
    needs finite kinematics and one entry per space dimension.
    """
    kin = cd.get("kinematics") if isinstance(cd, dict) else "small"
    kin = "small" if kin is BAD or kin is None else kin
    model, go_on = _model_name(mt, kin, issues)
    if not go_on:
        return kin, model
    if model is None:
        model = "neo-hookean" if kin == "finite" else LINEAR_MODEL
    finite = kin == "finite"
    if finite and model == LINEAR_MODEL:
        issues.append(Issue("material.model", "= 'linear': kinematics = 'finite' needs a hyperelastic law; set "
                                              "model = 'neo-hookean' (or 'saint-venant-kirchhoff'), or use "
                                              "contact.kinematics = 'small'."))
    if not finite and model != LINEAR_MODEL:
        issues.append(Issue("contact.kinematics", f"= 'small': the hyperelastic material.model = {model!r} needs "
                                                  "kinematics = 'finite'; set it, or use material.model = 'linear'."))
    if finite:
        _finite_issues(mt, cd, dim, data, issues)
    _path_issues(data.get("obstacle"), finite, dim, issues)
    return kin, model


#: Poisson's ratio from which a finite-deformation P2 body defaults to ``formulation = "mixed"``
MIXED_DEFAULT_NU = 0.49
#: ``material.nu`` of the exactly incompressible solid (the mixed body's Lagrange-multiplier pressure)
INCOMPRESSIBLE_NU = 0.5


def build_formulation(mt: Any, md: Any, s: "Sections", issues: list[Issue]) -> str:
    """``[material] formulation``: ``"mixed"`` (Taylor-Hood P2/P1 u-p body) or ``"displacement"``.

    Given, ``mixed`` needs finite kinematics with a hyperelastic law and ``[mesh] order = 2`` (straight-sided
    or curved second-order meshes, Cartesian or axisymmetric). Not given, it is ``mixed`` where that holds and
    ``nu >= 0.49`` (:data:`MIXED_DEFAULT_NU`: nearly incompressible rubber, where the displacement element
    locks), else ``displacement``. ``nu = 0.5`` (:data:`INCOMPRESSIBLE_NU`, exactly incompressible) needs the
    mixed body: with any other formulation it is an issue naming ``material.nu`` and the way out.
    """
    form = mt.get("formulation") if isinstance(mt, dict) else None
    form = None if form is BAD else form
    order = md.get("order") if isinstance(md, dict) else None
    hyper = s.kinematics == "finite" and s.law not in (None, LINEAR_MODEL)
    nu = mt.get("nu") if isinstance(mt, dict) else None
    exact = isinstance(nu, float) and nu == INCOMPRESSIBLE_NU
    if form is None:
        nu = getattr(s.material, "nu", None)
        auto = hyper and order == 2 and nu is not None and nu >= MIXED_DEFAULT_NU
        if exact and not auto:
            issues.append(Issue("material.nu", "= 0.5: the exactly incompressible solid needs the mixed "
                                               "displacement-pressure body (its pressure is the Lagrange multiplier "
                                               "of J = 1), which is a hyperelastic body with contact.kinematics = "
                                               "'finite' and mesh.order = 2; set those, or use nu < 0.5 (e.g. "
                                               "0.4999; small kinematics: mesh.volumetric = 'p0')."))
        return "mixed" if auto else "displacement"
    if form != "mixed":
        if exact:
            issues.append(Issue("material.nu", f"= 0.5 with formulation = {form!r}: a displacement element cannot "
                                               "hold J = 1 (infinite bulk modulus); set formulation = 'mixed' (or "
                                               "leave it out), or use nu < 0.5, e.g. 0.4999."))
        return form
    if not hyper:
        issues.append(Issue("material.formulation", "= 'mixed': the mixed displacement-pressure body is a "
                                                    "hyperelastic body; set contact.kinematics = 'finite' with a "
                                                    "hyperelastic material.model, or use formulation = "
                                                    "'displacement' (small kinematics near nu = 0.5: "
                                                    "mesh.volumetric = 'p0')."))
    if order is not None and order is not BAD and order != 2:
        issues.append(Issue("mesh.order", f"= {order!r}: formulation = 'mixed' is the Taylor-Hood element "
                                          "(P2 displacement, P1 pressure); set mesh.order = 2."))
    return form


def _split_message(msg: str, default: str) -> Issue:
    """An :class:`Issue` from an InputError message that starts with its key path (``key = ...`` / ``key: ...``)."""
    m = re.match(r"^([A-Za-z_][\w.\[\]]*)( = |: )(.*)$", msg, flags=re.S)
    if m is None or not m.group(1).startswith("material."):
        return Issue(default, msg)
    return Issue(m.group(1), ("= " if m.group(2) == " = " else "") + m.group(3))


def _require(key: str, why: str, issues: list[Issue]) -> None:
    issues.append(Issue(f"material.{key}", f"missing (required {why})."))


def _linear_law(params: dict, E, nu, issues: list[Issue]):
    """The linear elastic model: ``E`` and ``nu`` required, no ``[material.parameters]``."""
    if params:
        issues.append(Issue("material.parameters", f"= {sorted(params)}: not used by the linear elastic model "
                                                   "(its constants are E and nu); remove [material.parameters] "
                                                   "or choose a hyperelastic model."))
    for key, v in (("E", E), ("nu", nu)):
        if v is None:
            _require(key, "for the linear elastic model", issues)
    return None, E, nu


def _hyperelastic_law(mt: dict, law: str, params: dict, issues: list[Issue]):
    """The law object of ``model`` and ``[material.parameters]`` (or of ``energy``), or ``None``."""
    from ..fem import EnergyExpression, check_material_parameters, make_material

    if law == ENERGY_MODEL:
        try:
            return EnergyExpression(mt["energy"], params, key="material.energy", params_key="material.parameters")
        except InputError as exc:
            issues.append(_split_message(str(exc), "material.energy"))
            return None
    values, found = check_material_parameters(law, params)
    issues.extend(_split_message(f"material.parameters.{k} {m}" if m.startswith("= ")
                                 else f"material.parameters.{k}: {m}", "material.parameters")
                  for k, m in found)
    return None if found else make_material(law, **values)


def _fixed_moduli(obj, law: str, E, nu, issues: list[Issue]):
    """``(E, nu)`` completed from the moduli the law fixes and checked against them (``None`` with an issue)."""
    mu0, K0 = obj.fixed_moduli()
    if mu0 is None:  # the law takes its moduli from E and nu
        for key, v in (("E", E), ("nu", nu)):
            if v is None:
                _require(key, f"for model {law!r}, which takes its shear and bulk moduli from E and nu", issues)
        return E, nu
    if K0 is None:  # mu0 fixed, the bulk modulus from nu
        if nu is None:
            _require("nu", f"for model {law!r}: it sets the bulk modulus of the volumetric term", issues)
            return E, None
        E0 = 2.0 * mu0 * (1.0 + nu)
        what = f"model {law!r} with these parameters has initial shear modulus mu0 = {mu0:.6g}"
    else:  # the user energy fixes both
        E0 = 9.0 * K0 * mu0 / (3.0 * K0 + mu0)
        nu0 = (3.0 * K0 - 2.0 * mu0) / (2.0 * (3.0 * K0 + mu0))
        what = f"the energy has initial moduli mu0 = {mu0:.6g}, K0 = {K0:.6g}"
        if nu is not None and abs(nu - nu0) > 1e-6:
            issues.append(Issue("material.nu", f"= {nu!r}: {what}, so nu = {nu0:.9g}; remove nu (it is derived) "
                                               "or make it agree."))
            return E, None
        nu = nu0
    if E is not None and abs(E - E0) > 1e-6 * E0:
        issues.append(Issue("material.E", f"= {E!r}: {what}, so E = 2 mu0 (1 + nu) = {E0:.9g} (consistency with "
                                          "linear elasticity); remove E (it is derived) or make it agree."
                            if K0 is None else f"= {E!r}: {what}, so E = {E0:.9g}; remove E (it is derived) or "
                                               "make it agree."))
        return None, nu
    return E0 if E is None else E, nu


def material_law(mt: dict, law: str, issues: list[Issue]):
    """``(law instance or None, E, nu)`` of ``[material]``: the law built from ``model`` and
    ``[material.parameters]`` (or ``energy``), and the constants, completed from the moduli
    the law fixes (:meth:`~alcontact.fem.HyperelasticLaw.fixed_moduli`) and checked against them.

    ``E`` or ``nu`` is ``None`` (with an issue) when it is missing or cannot be derived.
    """
    sub = mt.get("parameters")
    params = dict(sub.get("params") or {}) if isinstance(sub, dict) else {}
    E, nu = mt["E"], mt["nu"]
    if law == LINEAR_MODEL or law is None:
        return _linear_law(params, E, nu, issues)
    obj = _hyperelastic_law(mt, law, params, issues)
    if obj is None:
        return None, E, nu
    return (obj, *_fixed_moduli(obj, law, E, nu, issues))


def _region_issues(mt: dict, mesh, mat, nu, issues: list[Issue]) -> None:
    """``[[material.region]]``: a region of the mesh, with the constants of ``[material]`` (one material).

    ``nu`` is ``[material]``'s Poisson's ratio as given (``0.5`` stays 0.5: the exactly incompressible mixed
    body, whose :class:`~alcontact.fem.Material` holds ``0.5 - 1e-9``); a region may say ``nu = 0.5`` where
    ``[material]`` does, and the body's check of ``nu = 0.5`` (``material.nu``, mixed only) then applies."""
    for i, reg in enumerate(mt["region"] or []):
        rp = f"material.region[{i + 1}]"
        if not _ok(reg):
            continue
        if mesh is not None:
            regions = sorted((getattr(mesh, "subdomains", None) or {}).keys())
            if reg["name"] not in regions:
                issues.append(Issue(f"{rp}.name", f"= {reg['name']!r}: the mesh has no region {reg['name']!r}."
                                                  f"{_did_you_mean(reg['name'], regions)} Mesh regions: "
                                                  f"{_known(regions)} (Gmsh physical groups of cells)."))
                continue
        if mat is not None and (reg["E"], reg["nu"], reg["plane"]) != (mat.E, nu, mat.plane):
            issues.append(Issue(rp, f"region {reg['name']!r} has E={reg['E']:g}, nu={reg['nu']:g}, "
                                    f"plane={reg['plane']!r}, different from [material]: several materials "
                                    "in one body are not supported yet (the FEM layer takes one material); "
                                    "use one [material] for the whole body."))


def build_material(mt: dict | None, law: str, mesh, issues: list[Issue]) -> tuple[Any, Any]:
    """``[material]``: ``(Material or None, hyperelastic law or None)``; the regions checked against the mesh."""
    from ..fem import Material, material_issues

    mat = law_obj = None
    if not (_ok({k: v for k, v in (mt or {}).items() if k != "region"}) and mt is not None):
        return mat, law_obj
    law_obj, E, nu = material_law(mt, law, issues)
    # nu = 0.5 (exactly incompressible) is for the mixed body only (build_formulation checks that it is the one
    # built); the linearized constants it carries hold 0.5 - 1e-9, as MixedHyperelastic.material does
    exact = nu == INCOMPRESSIBLE_NU
    bad = [] if E is None or nu is None else material_issues(E, 0.25 if exact else nu, mt["plane"])  # keyed as the file
    issues.extend(Issue(f"material.{key}", msg) for key, msg in bad)
    if not bad and E is not None and nu is not None:
        mat = _num(issues, "material", Material, E=E, nu=INCOMPRESSIBLE_NU - 1e-9 if exact else nu,
                   plane=mt["plane"])
    _region_issues(mt, mesh, mat, nu, issues)
    return mat, law_obj


# --------------------------------------------------------------------------- [contact], [[support]], [[load]]
def check_contact_boundary(cd: dict | None, mesh, issues: list[Issue]) -> bool:
    """``[contact] boundary``: the table is valid and (with a mesh) names one of its boundaries."""
    contact_ok = _ok(cd)
    if contact_ok and mesh is not None:
        contact_ok = boundary_ok(mesh, cd["boundary"], "contact.boundary", issues)
    return contact_ok


def _support_value(s: dict, dim: int, path: str, issues: list[Issue]):
    v = s["value"]
    comps = s["components"]
    if isinstance(v, float):
        return v
    n = len(v)
    if n == dim:
        return tuple(v)
    if comps is not None and n == len(comps):
        full = [0.0] * dim
        for c, x in zip(comps, v):
            full[c] = x
        return tuple(full)
    want = f"{dim}" if comps is None else f"{len(comps)} (one per listed component) or {dim}"
    issues.append(Issue(f"{path}.value", f"= {v!r}: needs a number or {want} numbers, got {n}."))
    return None


def _support(s: dict, sp: str, mesh, dim: int, issues: list[Issue]):
    """One ``[[support]]`` as a :class:`~alcontact.contact.Support`, or ``None`` (with its issues)."""
    from ..contact import Support

    good = boundary_ok(mesh, s["boundary"], f"{sp}.boundary", issues)
    comps = s["components"]
    if comps is not None:
        bad = [c for c in comps if c >= dim]
        if bad or len(set(comps)) != len(comps) or not comps:
            issues.append(Issue(f"{sp}.components", f"= {comps!r}: give distinct components in 0..{dim - 1} "
                                                    f"(0 = x, 1 = y{', 2 = z' if dim == 3 else ''}) for a "
                                                    f"{dim}D mesh."))
            good = False
    value = _support_value(s, dim, sp, issues)
    if value is None or not good:
        return None
    return Support(s["boundary"], None if comps is None else tuple(comps), value)


def build_supports(entries: list, mesh, dim: int | None, issues: list[Issue]) -> tuple[list, list]:
    """``[[support]]``: ``(fixed supports, ramped ones as LoadCase)``."""
    from ..contact import LoadCase

    fixed, cases = [], []
    for i, s in enumerate(entries or []):
        sp = f"support[{i + 1}]"
        if not _ok(s) or dim is None:
            continue
        item = _support(s, sp, mesh, dim, issues)
        if item is None:
            continue
        if s["ramp"] is None:
            fixed.append(item)
        else:
            cases.append(LoadCase(item, _ramp(s["ramp"]), tangential=s["tangential"], name=sp))
    return fixed, cases


def _load_boundary_ok(ld: dict, lp: str, mesh, issues: list[Issue]) -> bool:
    """Tractions and pressures act on a boundary of the mesh; body forces on the whole body (no boundary)."""
    kind = ld["type"]
    if kind in ("traction", "pressure"):
        if not ld["boundary"]:
            issues.append(Issue(f"{lp}.boundary", f"missing: a {kind} load needs boundary = 'NAME'."))
            return False
        return boundary_ok(mesh, ld["boundary"], f"{lp}.boundary", issues)
    if ld["boundary"]:
        issues.append(Issue(f"{lp}.boundary", "not used by a body-force load (it acts on the whole body); "
                                              "remove it."))
        return False
    return True


def _load_value_ok(ld: dict, lp: str, dim: int, issues: list[Issue]) -> bool:
    """A pressure has ``value``; a traction or body force has ``vector`` with ``dim`` entries."""
    kind = ld["type"]
    good = True
    if kind == "pressure":
        if ld["value"] is None:
            issues.append(Issue(f"{lp}.value", "missing: a pressure load needs value = NUMBER."))
            good = False
        if ld["vector"] is not None:
            issues.append(Issue(f"{lp}.vector", "not used by a pressure load; give value = NUMBER instead."))
            good = False
        return good
    if ld["value"] is not None:
        issues.append(Issue(f"{lp}.value", f"not used by a {kind} load; give vector = [...] instead."))
        good = False
    if ld["vector"] is None:
        issues.append(Issue(f"{lp}.vector", f"missing: a {kind} load needs vector = [...] with {dim} "
                                            "numbers."))
        good = False
    elif len(ld["vector"]) != dim:
        issues.append(Issue(f"{lp}.vector", f"= {ld['vector']!r}: needs {dim} numbers for a {dim}D mesh."))
        good = False
    return good


def _load_item(ld: dict):
    from ..contact import BodyForce, Pressure, Traction

    if ld["type"] == "traction":
        return Traction(ld["boundary"], tuple(ld["vector"]))
    if ld["type"] == "pressure":
        return Pressure(ld["boundary"], float(ld["value"]))
    return BodyForce(tuple(ld["vector"]))


def build_loads(entries: list, mesh, dim: int | None, issues: list[Issue]) -> tuple[list, list]:
    """``[[load]]``: ``(fixed loads, ramped ones as LoadCase)``."""
    from ..contact import LoadCase

    loads, cases = [], []
    for i, ld in enumerate(entries or []):
        lp = f"load[{i + 1}]"
        if not _ok(ld) or dim is None:
            continue
        good = _load_boundary_ok(ld, lp, mesh, issues)
        if not (_load_value_ok(ld, lp, dim, issues) and good):
            continue
        item = _load_item(ld)
        if ld["ramp"] is None:
            loads.append(item)
        else:
            cases.append(LoadCase(item, _ramp(ld["ramp"]), tangential=ld["tangential"], name=lp))
    return loads, cases


# --------------------------------------------------------------------------- [loading], [obstacle]
def build_loading(lo: dict | None, issues: list[Issue]) -> tuple[tuple[float, ...] | None, Any]:
    """``[loading]``: ``(step times or None, friction amplitude Ramp or None)``."""
    from ..contact import LoadHistory

    times: tuple[float, ...] | None = None
    friction_ramp = None
    if not _ok(lo):
        return times, friction_ramp
    if lo["times"] is not None:
        t = lo["times"]
        if not t or t[0] <= 0 or any(b <= a for a, b in zip(t, t[1:])):
            issues.append(Issue("loading.times", f"= {t!r}: give positive, strictly increasing pseudo-times, "
                                                 "e.g. [0.25, 0.5, 0.75, 1.0]."))
        else:
            times = tuple(float(x) for x in t)
    else:
        times = LoadHistory.uniform(lo["steps"], lo["t_end"])
    if lo["friction_ramp"] is not None:
        if any(v < 0 for _, v in lo["friction_ramp"]):
            issues.append(Issue("loading.friction_ramp", f"= {lo['friction_ramp']!r}: factors must be >= 0."))
        else:
            friction_ramp = _ramp(lo["friction_ramp"])
    return times, friction_ramp


def _obstacle_type_ok(name: str, issues: list[Issue], key: str = "obstacle") -> bool:
    """``type`` names a registered obstacle that a problem file can build (not ``user``)."""
    from ..contact import obstacles

    if name == "user":
        issues.append(Issue(f"{key}.type", "= 'user': a user obstacle needs Python functions; problem files "
                                           "hold data only. Use a registered shape, or build the problem in "
                                           "Python with alcontact.contact.obstacles.UserObstacle."))
        return False
    if name not in obstacles.available():
        known = [n for n in obstacles.available() if n != "user"]
        issues.append(Issue(f"{key}.type", f"= {name!r}: unknown obstacle.{_did_you_mean(name, known)} "
                                           f"Known obstacles: {_known(known)}."))
        return False
    return True


def _obstacle_params_ok(name: str, params: dict, accepted: list[str], sig, issues: list[Issue],
                        key: str = "obstacle") -> bool:
    """Every parameter is one the factory accepts, and every required one is given."""
    import inspect

    ok = True
    for k in params:
        if k not in accepted:
            issues.append(Issue(f"{key}.{k}", f"unknown parameter of obstacle {name!r}."
                                              f"{_did_you_mean(k, accepted)} Accepted: {_known(accepted)}."))
            ok = False
    for p in sig.parameters.values():
        if p.default is inspect.Parameter.empty and p.name not in params:
            issues.append(Issue(f"{key}.{p.name}", f"missing: obstacle {name!r} needs {p.name} "
                                                   f"(parameters: {_known(accepted)})."))
            ok = False
    return ok


def build_obstacle(od: dict | None, dim: int | None, issues: list[Issue], *, key: str = "obstacle",
                   base: Path | None = None):
    """``[obstacle]`` (or the obstacle of one ``[[pair]]``, ``key`` its path): the registered obstacle
    built from its parameters (checked against the factory's signature,
    :func:`alcontact.contact.obstacles.signature`), or ``None``. A relative ``file`` parameter (a
    meshed surface) is read relative to ``base``, the problem file's folder."""
    from ..contact import obstacles

    if od is None or od is BAD:
        return None
    name = od["type"]
    if name is BAD or not _obstacle_type_ok(name, issues, key):
        return None
    params = dict(od["params"])
    sig = obstacles.signature(name)
    accepted = [p for p in sig.parameters]
    if not _obstacle_params_ok(name, params, accepted, sig, issues, key):
        return None
    if base is not None and isinstance(params.get("file"), str) and not Path(params["file"]).is_absolute():
        params["file"] = str(Path(base) / params["file"])
    try:
        ob = obstacles.make(name, **params)
    except (InputError, TypeError, ValueError, ArithmeticError) as exc:
        text = str(exc) or type(exc).__name__
        param = next((p for p in accepted if text.startswith(f"{name}: {p} = ")), None)
        if param is not None:  # the factory named the parameter and the way out: key it by that parameter
            issues.append(Issue(f"{key}.{param}", text[len(name) + len(param) + 3:]))
        elif text.startswith(f"{name}"):  # the factory's own message, which names the obstacle and the way out
            issues.append(Issue(key, text))
        else:
            issues.append(Issue(key, f"{name}: {text}. Check the parameters "
                                     f"({_known(accepted)}): finite numbers of a sensible size."))
        return None
    if dim is not None:
        try:
            ob.check_dim(dim)
        except InputError as exc:
            issues.append(Issue(f"{key}.type", f"= {name!r}: {exc} (the mesh is {dim}D)."))
            return None
    return ob


def build_pairs(pds: list | None, mesh, dim: int | None, base: Path | None, issues: list[Issue]) -> list | None:
    """``[[pair]]``: ``(boundary, obstacle, friction)`` of each further contact pair (``friction`` ``None``: that of
    ``[contact]``), or ``None`` when one failed."""
    if not pds:
        return []
    out: list = []
    for i, pd in enumerate(pds):
        key = f"pair[{i + 1}]"
        if not _ok(pd) or not _pair_kind_ok(pd, key, issues, bodies=False):
            out = None
            continue
        if pd.get("master"):
            issues.append(Issue(f"{key}.master", f"= {pd['master']!r}: a master boundary is for pairs between "
                                                 "bodies ([[body]] tables); on one body give the pair's rigid "
                                                 "obstacle, e.g. type = 'half-space'."))
            out = None
            continue
        if not pd["type"]:
            issues.append(Issue(f"{key}.type", "missing: the pair's rigid obstacle, a registered obstacle name, "
                                               "e.g. type = 'half-space' (as [obstacle] type)."))
            out = None
            continue
        ok = mesh is None or boundary_ok(mesh, pd["boundary"], f"{key}.boundary", issues)
        ob = build_obstacle(pd, dim, issues, key=key, base=base)
        if ob is None or not ok:
            out = None
        elif out is not None:
            out.append((pd["boundary"], ob, pd["friction"]))
    return out


def _pair_kind_ok(pd: dict, key: str, issues: list[Issue], *, bodies: bool) -> bool:
    """A ``[[pair]]`` names its master once: an obstacle ``type`` (with its parameters) or, with ``[[body]]``
    tables (``bodies``), the ``master`` boundary of another body."""
    if pd["master"] and not bodies:
        issues.append(Issue(f"{key}.master", f"= {pd['master']!r}: a pair between two bodies needs [[body]] tables; "
                                             "against a rigid obstacle give its type (and parameters) instead."))
        return False
    if pd["master"] and (pd["type"] or pd["params"]):
        extra = _known((["type"] if pd["type"] else []) + sorted(pd["params"]))
        issues.append(Issue(key, f"master = {pd['master']!r} and obstacle keys ({extra}): a pair has one master, "
                                 "a boundary of another body or a rigid obstacle; remove one."))
        return False
    if not pd["master"] and not pd["type"]:
        issues.append(Issue(f"{key}.type", "missing (required): Registered obstacle name, as `[obstacle] type`"
                                           + (" (or master = 'body0/top', a boundary of another body)." if bodies
                                              else ".")))
        return False
    return True


def _pairs_issues(s: Sections, od: Any, issues: list[Issue]) -> None:
    """Several pairs at finite kinematics run frictionless with fixed obstacles (``[obstacle] path`` moves one)."""
    moving = isinstance(od, dict) and od.get("path") not in (None, BAD)
    if s.pairs and s.kinematics == "finite" and (s.mu_max > 0 or moving):
        rough = [f"pair[{k + 1}].friction > 0" for k, (_, _, m) in enumerate(s.pairs) if isinstance(m, float) and m > 0]
        what = "contact.friction > 0" if s.mu > 0 else (rough[0] if rough else "obstacle.path")
        issues.append(Issue("pair", f"{len(s.pairs)} [[pair]] table(s) at contact.kinematics = 'finite' with {what}: "
                                    "several contact pairs at finite kinematics run frictionless with fixed obstacles "
                                    "so far; remove it, use kinematics = 'small' (friction), or one pair ([contact] "
                                    "and [obstacle])."))
        s.pairs = None


# --------------------------------------------------------------------------- [solver]
def _algorithm_issues(algorithm: str, penalty: str | None, mu: float, issues: list[Issue]) -> None:
    """The penalty is the algorithm's to choose (``family-p``) and the algorithm handles friction if needed."""
    from ..contact import find_algorithm, friction_algorithms

    own_penalty = find_algorithm(algorithm).penalty
    if penalty is not None and own_penalty is not None and penalty != own_penalty:
        issues.append(Issue("solver.penalty", f"= {penalty!r}: algorithm {algorithm!r} uses its own penalty; "
                                              "set algorithm = 'family-p' to choose one, or remove penalty."))
    if mu > 0 and algorithm not in friction_algorithms():
        issues.append(Issue("solver.algorithm", f"= {algorithm!r}: not available with friction (contact.friction"
                                                f" = {mu:g}); use one of {_known(friction_algorithms())}."))


def _options_issues(given: dict, algorithm: str, mu: float, kinematics: str, issues: list[Issue]) -> None:
    """The ``[solver]`` options together, and the linear-solver path against the algorithm's registry entry."""
    from ..contact import ContactOptions, find_algorithm

    try:
        ContactOptions(**given).validate()
    except InputError as exc:
        issues.append(Issue("solver", str(exc)))
        return
    try:  # the linear-solver path must be one the algorithm's registry entry has at these kinematics
        find_algorithm(algorithm, friction=mu > 0,
                       kinematics=kinematics if kinematics in ("small", "finite") else "small"
                       ).check_options(ContactOptions(**given))
    except UnknownNameError:
        pass  # an algorithm without friction support is reported by _algorithm_issues
    except InputError as exc:
        issues.append(Issue("solver.linear_solver", str(exc)))


def _friction_options(sv: dict, given: dict, issues: list[Issue]) -> dict:
    """The options of frictional runs: every ``[solver]`` key, and the friction-only ones that
    ``[solver.friction]`` sets (a value other than the default there wins; both set: they must agree)."""
    from ..contact import ContactOptions, FrictionOptions

    fopts = dict(given)
    fr = sv.get("friction")
    defaults = {o.name: o.default for o in declarations(ContactOptions)}
    if fr is not None and _ok(fr):
        for k, v in fr.items():
            if v is None or v == defaults[k]:
                continue
            if given.get(k, defaults[k]) not in (defaults[k], v):
                issues.append(Issue(f"solver.friction.{k}", f"= {v!r}: solver.{k} = {given[k]!r} says "
                                                            "otherwise; set it once, in [solver]."))
            fopts[k] = v
    try:
        FrictionOptions(**fopts).validate()
    except InputError as exc:
        issues.append(Issue("solver.friction", str(exc)))
    return fopts


@dataclass
class Solver:
    """The built ``[solver]`` table: algorithm, penalty and the options of frictionless and frictional runs."""

    algorithm: str = "simo-laursen"
    penalty: str | None = None
    options: dict = field(default_factory=dict)
    friction_options: dict = field(default_factory=dict)
    petsc_options: dict = field(default_factory=dict)


def _petsc_options(sv: dict, given: dict, issues: list[Issue]) -> dict:
    """``[solver.petsc_options]``: names and values checked; they must go to a solver that takes them."""
    from ..linalg import check_backend_options, takes_backend_options

    params = dict((sv.get("petsc_options") or {}).get("params", {}))
    if not params:
        return {}
    try:
        check_backend_options(params)
    except InputError as exc:
        issues.append(Issue("solver.petsc_options", str(exc)))
        return {}
    solver = given.get("linear_solver", "auto")
    try:
        takes = takes_backend_options(solver)
    except UnknownNameError:  # "auto", "direct", or an unknown name (reported with [solver])
        takes = False
    if not takes:
        issues.append(Issue("solver.petsc_options", f"given, but linear_solver = {solver!r} does not run PETSc, so "
                                                    "they would have no effect; set linear_solver = \"petsc\" (KSP + "
                                                    "GAMG) or \"petsc-direct\" (MUMPS), or remove petsc_options."))
        return {}
    return params


def build_solver(sv: dict | None, mu: float, kinematics: str, issues: list[Issue]) -> Solver:
    """``[solver]`` and ``[solver.friction]``: one options type; the frictionless runs' options leave the
    friction-only fields out (:func:`alcontact.contact.friction_only_options`)."""
    from ..contact import friction_only_options

    if sv is None or not _ok({k: v for k, v in sv.items() if k != "friction"}):
        return Solver()
    algorithm = sv["algorithm"]
    penalty = sv["penalty"] or None
    _algorithm_issues(algorithm, penalty, mu, issues)
    skip = {"algorithm", "penalty", "friction", "petsc_options"}
    given = {k: v for k, v in sv.items() if k not in skip and v is not None}
    _options_issues(given, algorithm, mu, kinematics, issues)
    fopts = _friction_options(sv, given, issues)
    friction_only = set(friction_only_options())
    options = {k: v for k, v in given.items() if k not in friction_only}  # the frictionless runs' options
    return Solver(algorithm, penalty, options, fopts, _petsc_options(sv, given, issues))


# --------------------------------------------------------------------------- [units], [reference]
def build_units(ud: dict | None, issues: list[Issue]) -> tuple:
    """``[units]``: ``(length, stress, force)`` labels (only labels; the set must be consistent)."""
    if not _ok(ud):
        return (None, None, None)
    units = (ud["length"], ud["stress"], ud["force"])
    issues.extend(Issue(f"units.{key}", msg) for key, msg in units_issues(*units))
    return units


def _reference_ok(rd: dict, dim: int | None, mu: float, issues: list[Issue]) -> bool:
    """The reference's radius, centre and axis fit the mesh; Cattaneo-Mindlin needs 2D and friction."""
    if rd["radius"] is None:
        issues.append(Issue("reference.radius", f"missing: reference kind {rd['kind']!r} needs the indenter "
                                                "radius, e.g. radius = 10.0."))
    elif dim is not None and rd["center"] is not None and len(rd["center"]) != dim:
        issues.append(Issue("reference.center", f"= {rd['center']!r}: needs {dim} coordinates."))
    elif dim is not None and rd["axis"] >= dim:
        issues.append(Issue("reference.axis", f"= {rd['axis']}: must be < {dim} for a {dim}D mesh."))
    elif rd["kind"] == "cattaneo-mindlin" and (dim == 3 or not mu > 0):
        issues.append(Issue("reference.kind", "= 'cattaneo-mindlin': needs a 2D mesh and contact.friction > 0."))
    else:
        return True
    return False


def build_reference(rd: dict | None, dim: int | None, mat, mu: float, issues: list[Issue]) -> tuple[Any, Any]:
    """``[reference]``: ``(HertzReference or None, MindlinReference or None)``."""
    if not _ok(rd) or rd["kind"] == "none" or not _reference_ok(rd, dim, mu, issues):
        return None, None
    if mat is None or dim is None:
        return None, None
    from ..problems.hertz import HertzReference

    e_star = mat.E if (dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus
    ref = HertzReference("cylinder" if dim == 2 else "sphere", rd["radius"], e_star, rd["symmetry"])
    if rd["kind"] != "cattaneo-mindlin":
        return ref, None
    from ..problems.friction import MindlinReference

    return ref, MindlinReference(ref, float(mu))


# --------------------------------------------------------------------------- every section, then the problem
@dataclass
class Sections:
    """What the sections of a problem file built (``None`` where a section could not be built)."""

    mesh: Any = None
    dim: int | None = None
    kinematics: str = "small"
    law: str | None = None
    formulation: str = "displacement"
    #: ``material.nu = 0.5``: the mixed body gets the exact 0.5 (``material`` holds 0.5 - 1e-9)
    incompressible: bool = False
    material: Any = None
    law_obj: Any = None
    contact_ok: bool = False
    fixed: list = field(default_factory=list)
    loads: list = field(default_factory=list)
    cases: list = field(default_factory=list)
    times: tuple[float, ...] | None = None
    friction_ramp: Any = None
    obstacle: Any = None
    pairs: Any = field(default_factory=list)
    mu: float = 0.0
    #: the largest Coulomb coefficient of the pairs (``[contact]`` and ``[[pair]]``): frictional when positive
    mu_max: float = 0.0
    solver: Solver = field(default_factory=Solver)
    units: tuple = (None, None, None)
    reference: Any = None
    mindlin: Any = None

    def complete(self) -> bool:
        """Every part a problem needs was built."""
        return not (self.mesh is None or self.material is None or self.obstacle is None or not self.contact_ok
                    or self.times is None or self.pairs is None)


def build_sections(data: dict, base: Path, issues: list[Issue]) -> Sections:
    """Build every section of the normalized file ``data`` in order, recording the issues."""
    s = Sections()
    s.mesh, s.dim = build_mesh(data.get("mesh"), base, issues)
    mt, cd = data.get("material"), data.get("contact")
    s.kinematics, s.law = build_kinematics(mt, cd, s.dim, data, issues)
    s.material, s.law_obj = build_material(mt, s.law, s.mesh, issues)
    s.formulation = build_formulation(mt, data.get("mesh"), s, issues)
    s.incompressible = isinstance(mt, dict) and isinstance(mt.get("nu"), float) and mt["nu"] == INCOMPRESSIBLE_NU
    s.contact_ok = check_contact_boundary(cd, s.mesh, issues)
    s.fixed, support_cases = build_supports(data.get("support"), s.mesh, s.dim, issues)
    s.loads, load_cases = build_loads(data.get("load"), s.mesh, s.dim, issues)
    s.cases = support_cases + load_cases
    s.times, s.friction_ramp = build_loading(data.get("loading"), issues)
    s.obstacle = build_obstacle(data.get("obstacle"), s.dim, issues, base=base)
    s.pairs = build_pairs(data.get("pair"), s.mesh, s.dim, base, issues)
    s.mu = cd["friction"] if isinstance(cd, dict) and isinstance(cd.get("friction"), float) else 0.0
    s.mu_max = max([s.mu] + [m for _, _, m in (s.pairs or ()) if isinstance(m, float)])
    _pairs_issues(s, data.get("obstacle"), issues)
    s.solver = build_solver(data.get("solver"), s.mu_max, s.kinematics, issues)
    s.units = build_units(data.get("units"), issues)
    s.reference, s.mindlin = build_reference(data.get("reference"), s.dim, s.material, s.mu, issues)
    return s


def build_model(md: dict, s: Sections, issues: list[Issue]):
    """The body: linear elasticity, or the hyperelastic law at finite kinematics (``[mesh] order``)."""
    from ..fem import LinearElasticity, check_geometry
    from ..fem.hyperelastic import Hyperelastic

    if s.material is not None and _num(issues, "mesh.geometry", check_geometry, md["geometry"], s.dim, s.mesh.p,
                                       plane=s.material.plane) is None:
        return None
    if s.law == LINEAR_MODEL:
        return _num(issues, "mesh.order", LinearElasticity, s.mesh, s.material, order=md["order"],
                    volumetric=md["volumetric"], geometry=md["geometry"])
    if md["volumetric"] != "full":
        issues.append(Issue("mesh.volumetric", f"= {md['volumetric']!r} applies to linear elasticity only; the "
                            f"hyperelastic model {s.law!r} uses the standard element: remove mesh.volumetric."))
        return None
    # the path of LinearElasticity: its mesh-quality errors are rewritten by alcontact.io.preflight
    if s.law_obj is None:
        return None
    if s.formulation == "mixed":
        from ..fem.mixed import MixedHyperelastic

        nu = INCOMPRESSIBLE_NU if s.incompressible else s.material.nu
        return _num(issues, "material.formulation", MixedHyperelastic, s.mesh, E=s.material.E, nu=nu,
                    model=s.law_obj, geometry=md["geometry"])
    return _num(issues, "mesh.order", Hyperelastic, s.mesh, s.material, order=md["order"], model=s.law_obj,
                geometry=md["geometry"])


def _proportional(fixed: list, loads: list) -> tuple[list, list]:
    """Finite kinematics without any ``ramp``: every nonzero support value and every load as a
    :class:`~alcontact.contact.LoadCase` ramped from 0 at ``t = 0`` to full at ``t = 1``
    (proportional loading; zero supports stay fixed)."""
    import numpy as np

    from ..contact import LoadCase

    ramp = _ramp([(0.0, 0.0), (1.0, 1.0)])
    still = [s for s in fixed if not np.any(np.asarray(s.value, dtype=float) != 0.0)]
    moving = [s for s in fixed if np.any(np.asarray(s.value, dtype=float) != 0.0)]
    cases = [LoadCase(item, ramp, name=f"{type(item).__name__.lower()} {i + 1}")
             for i, item in enumerate(moving + list(loads))]
    return still, cases


def build_problem(data: dict, model, s: Sections, issues: list[Issue]) -> tuple[Any, Any]:
    """``(ContactProblem, LoadHistory or None)`` of the built sections; finite kinematics without a ramp
    loads proportionally (:func:`_proportional`)."""
    from ..contact import ContactProblem, LoadHistory

    rd, cd = data["reference"], data["contact"]
    center = tuple(rd["center"]) if rd["center"] is not None else (0.0,) * s.dim
    # the origin is only a default centre unless a reference or [reference] center names it (viz.contact_center)
    meta = {"symmetry_axis": int(rd["axis"]), "center": center,
            "center_declared": rd["center"] is not None or rd["kind"] != "none"}
    if s.pairs:  # [contact] + [obstacle] is the first pair, each [[pair]] one more
        from ..contact import Boundary, ContactPair

        pairs = [ContactPair(Boundary(model, b), ob, friction=float(s.mu if mu is None else mu))
                 for b, ob, mu in [(cd["boundary"], s.obstacle, None)] + list(s.pairs)]
        problem = _num(issues, "pair", ContactProblem, bodies=[model], pairs=pairs, supports=tuple(s.fixed),
                       loads=tuple(s.loads), name=data["problem"]["name"], reference=s.reference, meta=meta,
                       kinematics=s.kinematics)
    else:
        problem = _num(issues, "", ContactProblem, model=model, obstacle=s.obstacle, contact_boundary=cd["boundary"],
                       supports=tuple(s.fixed), loads=tuple(s.loads), friction=float(s.mu),
                       name=data["problem"]["name"], reference=s.reference, meta=meta, kinematics=s.kinematics)
    cases = s.cases
    if s.kinematics == "finite" and not cases and problem is not None:
        fixed, cases = _proportional(s.fixed, s.loads)
        problem = dataclasses.replace(problem, supports=tuple(fixed), loads=())
    history = None
    if cases or s.friction_ramp is not None or s.mu_max > 0:
        history = _num(issues, "loading", LoadHistory, tuple(cases), s.times, s.friction_ramp)
    return problem, history


# --------------------------------------------------------------------------- [[body]]: several bodies
def _prefixed(found: list[Issue], prefix: str) -> list[Issue]:
    """The issues of one body's ``[mesh]`` / ``[material]`` builders keyed under ``body[i].``."""
    return [Issue(prefix + i.path if i.path else prefix.rstrip("."), i.message) for i in found]


def _one_body(i: int, bd: dict, base: Path, issues: list[Issue], kinematics: str = "small"):
    """``[[body]]`` number ``i + 1``: ``(body, dim)``, or ``(None, dim)`` with its issues.

    The builders of ``[mesh]`` and ``[material]`` run on the body's ``mesh`` and ``material``
    tables; their issues are keyed ``body[i].mesh.*`` / ``body[i].material.*``. At ``kinematics =
    "finite"`` the body is hyperelastic (``material.model``, default ``"neo-hookean"``; P1, the
    displacement formulation), else linear elastic.
    """
    from ..fem import LinearElasticity, check_geometry
    from ..fem.hyperelastic import Hyperelastic

    found: list[Issue] = []
    md, mt = bd.get("mesh"), bd.get("material")
    mesh, dim = build_mesh(md, base, found)
    kin_found: list[Issue] = []
    _, law = build_kinematics(mt, {"kinematics": kinematics}, dim, {}, kin_found)
    # the law that does not go with [contact] kinematics is this body's material.model
    found += [Issue("material.model", f"= {mt.get('model')!r}: " + i.message.split(": ", 1)[-1])
              if i.path == "contact.kinematics" else i for i in kin_found]
    mat, law_obj = build_material(None if mt is None else {**mt, "region": None}, law, mesh, found)
    model = None
    if mesh is not None and mat is not None and not found:
        if dim == 3 and md["order"] != 1:
            found.append(Issue("mesh.order", f"= {md['order']}: contact between 3D bodies ([[body]]) is available "
                                             "for linear tetrahedra; set order = 1 (refine the mesh instead)."))
        elif md["geometry"] != "cartesian":
            found.append(Issue("mesh.geometry", f"= {md['geometry']!r}: several bodies ([[body]]) are "
                                                "Cartesian so far; remove geometry."))
        elif kinematics == "finite" and md["order"] != 1:
            found.append(Issue("mesh.order", f"= {md['order']}: contact between bodies at kinematics = 'finite' "
                                             "is available for P1 bodies (segments that stay straight); set "
                                             "order = 1."))
        elif kinematics == "finite" and isinstance(mt, dict) and mt.get("formulation") == "mixed":
            found.append(Issue("material.formulation", "= 'mixed': several bodies ([[body]]) use the displacement "
                                                       "formulation; remove formulation."))
        elif _num(found, "mesh.geometry", check_geometry, md["geometry"], dim, mesh.p, plane=mat.plane) is None:
            pass
        elif law == LINEAR_MODEL:
            model = _num(found, "mesh.order", LinearElasticity, mesh, mat, order=md["order"],
                         volumetric=md["volumetric"], geometry=md["geometry"])
        elif law_obj is not None:
            model = _num(found, "mesh.order", Hyperelastic, mesh, mat, order=md["order"], model=law_obj)
    issues.extend(_prefixed(found, f"body[{i + 1}]."))
    return model, dim


def _qualified(item, k: int):
    """A support or load of body ``k`` (or its :class:`~alcontact.contact.LoadCase`) on ``"body<k>/<boundary>"``."""
    if hasattr(item, "item"):  # a ramped one
        return dataclasses.replace(item, item=_qualified(item.item, k))
    return dataclasses.replace(item, boundary=f"body{k}/{item.boundary}")


def _body_actions(i: int, bd: dict, model, dim: int, issues: list[Issue]) -> tuple[list, list, list]:
    """``[[body.support]]`` and ``[[body.load]]`` of body ``i``: ``(supports, loads, ramped cases)`` on its
    boundaries (built by :func:`build_supports` and :func:`build_loads`, issues keyed ``body[i].*``)."""
    found: list[Issue] = []
    fixed, support_cases = build_supports(bd.get("support"), model.mesh, dim, found)
    for j, ld in enumerate(bd.get("load") or []):
        if _ok(ld) and ld["type"] == "body-force":
            found.append(Issue(f"load[{j + 1}].type", "= 'body-force': a body force in [[body.load]] would act "
                                                      "on every body; give it in the top-level [[load]] (or use "
                                                      "a traction)."))
    loads, load_cases = build_loads([ld for ld in bd.get("load") or [] if not (_ok(ld) and ld["type"] ==
                                                                                "body-force")],
                                    model.mesh, dim, found)
    issues.extend(_prefixed(found, f"body[{i + 1}]."))
    return ([_qualified(x, i) for x in fixed], [_qualified(x, i) for x in loads],
            [_qualified(x, i) for x in support_cases + load_cases])


def _boundary_names(models: list) -> dict[str, tuple[int, str]]:
    """Every name a boundary of the bodies may be given by: ``"body<k>/<name>"``, and the bare name where
    only one body has it (as :class:`alcontact.fem.MultiBody` resolves them)."""
    names: dict[str, tuple[int, str]] = {}
    bare: dict[str, list[int]] = {}
    for k, m in enumerate(models):
        for b in sorted((m.mesh.boundaries or {}).keys()):
            names[f"body{k}/{b}"] = (k, b)
            bare.setdefault(b, []).append(k)
    names.update({b: (ks[0], b) for b, ks in bare.items() if len(ks) == 1})
    return names


def _surface(name: str, key: str, names: dict, n: int, issues: list[Issue]) -> tuple[int, str] | None:
    """``(body index, boundary)`` named by ``[contact] boundary`` / ``master``, or ``None`` with an issue."""
    if not name:
        issues.append(Issue(key, "missing: with [[body]] the contact pair needs boundary = 'body1/bottom' (the "
                                 "slave) and master = 'body0/top' (a boundary of another body)."))
        return None
    if name in names:
        return names[name]
    m = re.match(r"^(body\d+)/", name)
    owners = [k.split("/", 1)[0] for k in names if "/" in k and k.split("/", 1)[1] == name]
    if len(owners) > 1:
        issues.append(Issue(key, f"= {name!r}: ambiguous, {' and '.join(owners)} both have a boundary {name!r}; "
                                 f"name the body, e.g. {owners[0] + '/' + name!r}."))
    elif m and not any(k.startswith(m.group(1) + "/") for k in names):
        issues.append(Issue(key, f"= {name!r}: there is no body {m.group(1)!r}; the file has {n} [[body]] "
                                 f"table(s), named {_known([f'body{k}' for k in range(n)])} in order."))
    else:
        known = sorted(names)
        issues.append(Issue(key, f"= {name!r}: no body has the boundary {name!r}.{_did_you_mean(name, known)} "
                                 f"Boundaries: {_known(known)} (a bare name only where one body has it)."))
    return None


#: the kinematics of contact between bodies ([[body]] tables)
KINEMATICS_OF_BODIES = ("small", "finite")


def _bodies_table_issues(data: dict, issues: list[Issue]) -> None:
    """Tables and options that do not go with ``[[body]]`` (what runs: small deformation, one pair)."""
    for key, what in (("mesh", "each body has its own [body.mesh]"),
                      ("material", "each body has its own [body.material]"),
                      ("obstacle", "the master of the pair is [contact] master, a body's boundary")):
        if data.get(key) is not None:
            issues.append(Issue(key, f"given together with [[body]]: {what}; remove [{key}]."))
    cd = data.get("contact")
    if not isinstance(cd, dict) or cd.get("kinematics") != "finite":
        return
    for i, pd in enumerate(data.get("pair") or []):  # what the finite two-body path does not take yet
        if _ok(pd) and pd["type"]:
            issues.append(Issue(f"pair[{i + 1}].type", f"= {pd['type']!r}: a rigid obstacle beside two-body pairs at "
                                                       "kinematics = 'finite' is not supported yet; give master = a "
                                                       "boundary of another body, or kinematics = 'small'."))
        if _ok(pd) and isinstance(pd.get("friction"), float) and pd["friction"] > 0:
            issues.append(Issue(f"pair[{i + 1}].friction", f"= {pd['friction']:g}: contact between bodies at "
                                                           "kinematics = 'finite' is frictionless so far; set "
                                                           "friction = 0.0, or kinematics = 'small'."))
    if isinstance(cd.get("friction"), float) and cd["friction"] > 0:
        issues.append(Issue("contact.friction", f"= {cd['friction']:g}: contact between bodies at kinematics = "
                                                "'finite' is frictionless so far; set friction = 0.0, or "
                                                "kinematics = 'small' (linear elastic bodies)."))


def _two_body_reference(rd: dict | None, models: list, mu: float, issues: list[Issue]):
    """``[reference] kind = "hertz"`` between two bodies: Hertz with the effective modulus
    :math:`1/E^* = (1-\\nu_1^2)/E_1 + (1-\\nu_2^2)/E_2` (plane strain; in 3D always) and ``radius`` the
    effective :math:`R` (Johnson, Contact Mechanics, eq. 4.45-4.47 for two cylinders, 4.22-4.23 for two
    spheres or a sphere on a flat); ``"cattaneo-mindlin"`` (2D): the partial slip of that contact under a
    tangential load, :math:`c/a = \\sqrt{1 - Q/(\\mu P)}` (Johnson, section 7.1; exact for two bodies of the
    same material, which decouple the normal and tangential problems). ``(hertz, mindlin)``."""
    if not _ok(rd) or rd["kind"] == "none":
        return None, None
    dim = int(models[0].dim)
    kinds = ("hertz", "cattaneo-mindlin") if dim == 2 else ("hertz",)
    if rd["kind"] not in kinds or len(models) != 2:
        issues.append(Issue("reference.kind", f"= {rd['kind']!r}: with [[body]] the reference is "
                                              f"{' or '.join(repr(k) for k in kinds)} between two bodies "
                                              f"{'in 2D ' if dim == 2 else 'in 3D '}(or 'none')."))
        return None, None
    if not _reference_ok(rd, dim, mu, issues):
        return None, None
    from ..problems.friction import MindlinReference
    from ..problems.hertz import HertzReference

    comp = sum(1.0 / m.material.E if dim == 2 and m.material.plane == "stress" else
               1.0 / m.material.plane_strain_modulus for m in models)
    ref = HertzReference("cylinder" if dim == 2 else "sphere", rd["radius"], 1.0 / comp, rd["symmetry"])
    return ref, (MindlinReference(ref, float(mu)) if rd["kind"] == "cattaneo-mindlin" else None)


def _bodies_meta(rd, dim: int) -> dict:
    """The problem's ``meta`` of a file with ``[[body]]`` tables: the reference's symmetry axis and centre."""
    rd = rd if _ok(rd) else {"center": None, "axis": 0, "kind": "none"}
    center = tuple(rd["center"]) if rd["center"] is not None else (0.0,) * dim
    return {"symmetry_axis": int(rd["axis"]), "center": center,
            "center_declared": rd["center"] is not None or rd["kind"] != "none"}


def _bodies_kinematics(cd) -> str:
    """``[contact] kinematics`` of a file with ``[[body]]`` tables (``"small"`` where the table is invalid)."""
    return cd["kinematics"] if _ok(cd) and cd.get("kinematics") in KINEMATICS_OF_BODIES else "small"


def _finite_loading(kinematics: str, s: Sections) -> None:
    """Finite kinematics without a ramp: proportional loading (:func:`_proportional`), in place."""
    if kinematics == "finite" and not s.cases:
        s.fixed, s.cases = _proportional(s.fixed, s.loads)
        s.loads = []


def _bodies_3d_issues(cd, kinematics: str, issues: list[Issue]) -> None:
    """What contact between 3D bodies does not take yet: finite deformation, friction."""
    if kinematics == "finite":
        issues.append(Issue("contact.kinematics", "= 'finite': contact between 3D bodies is small deformation so far "
                                                  "(the finite two-body gap is 2D); set kinematics = 'small'."))
    if _ok(cd) and isinstance(cd.get("friction"), float) and cd["friction"] > 0:
        issues.append(Issue("contact.friction", f"= {cd['friction']:g}: contact between 3D bodies is frictionless "
                                                "so far (two-body Coulomb friction is 2D); set friction = 0.0."))


def build_bodies(data: dict, base: Path, issues: list[Issue]):
    """``[[body]]`` tables, their supports and loads, and the two-body pairs of ``[contact]`` and ``[[pair]]``:
    ``(ContactProblem, LoadHistory or None, Sections)``, or ``None`` (every problem in ``issues``).

    The pairs are mortar (:class:`~alcontact.contact.BodySurface`): ``boundary`` is the slave,
    ``master`` a boundary of another body (or of the same body). Checked here: each body's
    mesh and material, that the bodies have one dimension, that both boundaries of every pair exist,
    and that slave and master are not the same boundary.
    """
    from types import SimpleNamespace

    from ..contact import ContactProblem, LoadHistory

    _bodies_table_issues(data, issues)
    cd = data["contact"]
    kinematics = _bodies_kinematics(cd)
    built = [_one_body(i, bd, base, issues, kinematics) for i, bd in enumerate(data["body"]) if _ok(bd)]
    if len(built) != len(data["body"]):
        return None
    dims = [d for _, d in built]
    if len({d for d in dims if d is not None}) > 1:
        each = ", ".join(f"body{k}: {d}D" for k, d in enumerate(dims))
        issues.append(Issue("body", f"the bodies have different dimensions ({each}); "
                                    "every body of a problem has the same dimension, 2D or 3D."))
        return None
    models = [m for m, _ in built]
    if any(m is None for m in models):
        return None
    s = Sections(dim=dims[0], material=models[0].material)
    s.kinematics = kinematics
    names = _boundary_names(models)
    where = SimpleNamespace(boundaries=dict.fromkeys(names))  # boundary_ok checks the qualified names
    pair = _contact_pair(cd, models, names, issues)
    others = _body_pairs(data.get("pair") or [], models, names, s.dim, base, cd, issues)
    if s.dim == 3:
        _bodies_3d_issues(cd, kinematics, issues)
    s.fixed, support_cases = build_supports(data.get("support"), where, s.dim, issues)
    s.loads, load_cases = build_loads(data.get("load"), where, s.dim, issues)
    s.cases = support_cases + load_cases
    for k, (bd, m) in enumerate(zip(data["body"], models)):
        more = _body_actions(k, bd, m, s.dim, issues)
        s.fixed, s.loads, s.cases = s.fixed + more[0], s.loads + more[1], s.cases + more[2]
    s.times, s.friction_ramp = build_loading(data.get("loading"), issues)
    s.mu = cd["friction"] if _ok(cd) and isinstance(cd.get("friction"), float) else 0.0
    s.mu_max = max([s.mu] + [p.friction for p in others or ()])
    s.solver = build_solver(data.get("solver"), s.mu_max, kinematics, issues)
    s.units = build_units(data.get("units"), issues)
    rd = data.get("reference")
    s.reference, s.mindlin = _two_body_reference(rd, models, s.mu, issues)
    if issues or pair is None or s.times is None or others is None:
        return None
    meta = _bodies_meta(rd, s.dim)
    _finite_loading(kinematics, s)
    problem = _num(issues, "body", ContactProblem, bodies=models, pairs=[pair] + others, supports=tuple(s.fixed),
                   loads=tuple(s.loads), name=data["problem"]["name"], reference=s.reference, meta=meta,
                   kinematics=kinematics)
    if problem is None:
        return None
    history = None
    if s.cases or s.friction_ramp is not None or s.mu_max > 0:
        history = _num(issues, "loading", LoadHistory, tuple(s.cases), s.times, s.friction_ramp)
    return problem, history, s


def _contact_pair(cd: Any, models: list, names: dict, issues: list[Issue]):
    """The two-body pair of ``[contact]`` (``boundary`` the slave, ``master`` a boundary of another body, its
    ``friction``), or ``None`` with the issues."""
    from ..contact import BodySurface, Boundary, ContactPair

    if not _ok(cd):
        return None
    slave = _surface(cd["boundary"], "contact.boundary", names, len(models), issues)
    master = _surface(cd["master"], "contact.master", names, len(models), issues)
    if slave is None or master is None:
        return None
    if slave == master:
        issues.append(Issue("contact.master", f"= {cd['master']!r}: the same boundary as the slave "
                                              f"(contact.boundary = {cd['boundary']!r}); a pair needs two "
                                              "surfaces: name a boundary of the other body."))
        return None
    mu = cd["friction"] if isinstance(cd.get("friction"), float) else 0.0
    return ContactPair(Boundary(models[slave[0]], slave[1]), BodySurface(models[master[0]], master[1]), friction=mu)


def _body_pairs(pds: list, models: list, names: dict, dim, base: Path, cd: Any, issues: list[Issue]) -> list | None:
    """The ``[[pair]]`` tables of a file with ``[[body]]``: each a pair between two bodies (``master``) or
    against a rigid obstacle (``type``) on the body of its ``boundary``; ``None`` when one failed."""
    from ..contact import BodySurface, Boundary, ContactPair

    out: list | None = []
    mu0 = cd["friction"] if _ok(cd) and isinstance(cd.get("friction"), float) else 0.0
    for i, pd in enumerate(pds):
        key = f"pair[{i + 1}]"
        if not _ok(pd) or not _pair_kind_ok(pd, key, issues, bodies=True):
            out = None
            continue
        slave = _surface(pd["boundary"], f"{key}.boundary", names, len(models), issues)
        if pd["master"]:
            other = _surface(pd["master"], f"{key}.master", names, len(models), issues)
            if other is not None and other == slave:
                issues.append(Issue(f"{key}.master", f"= {pd['master']!r}: the same boundary as the slave "
                                                     f"({key}.boundary = {pd['boundary']!r}); a pair needs two "
                                                     "surfaces: name a boundary of the other body."))
                other = None
            master = None if other is None else BodySurface(models[other[0]], other[1])
        else:
            master = build_obstacle(pd, dim, issues, key=key, base=base)
        if slave is None or master is None:
            out = None
        elif out is not None:
            mu = mu0 if pd["friction"] is None else pd["friction"]
            out.append(ContactPair(Boundary(models[slave[0]], slave[1]), master, friction=mu))
    return out
