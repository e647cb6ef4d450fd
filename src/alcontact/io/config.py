"""Problem files: read a TOML file, validate it against :mod:`alcontact.io.schema`, build the problem.

:func:`load_problem` does everything before solving: it parses the TOML, checks
every key against the schema (unknown keys with a "did you mean", wrong types,
values out of range), builds or reads the mesh, checks the boundary and region
names against it, builds the material, the obstacle (parameters checked
against the registered factory), the supports, loads and the load history,
and checks that algorithm, penalty and friction fit together. All problems
found are reported together in one :class:`~alcontact.errors.ConfigError`
whose ``issues`` list holds ``(key path, message)`` pairs, e.g.::

    problem.toml: 2 errors
      solver.penalty_scale = -1.0: out of range, must be > 0.
      contact.boundary = 'topp': the mesh has no boundary 'topp'. Did you mean 'top'? ...

Examples
--------
>>> setup = load_problem("examples/hertz_2d.toml")          # doctest: +SKIP
>>> setup.summary_line()                                     # doctest: +SKIP
'hertz-2d: 2D P1, 8964 DOFs, ...'
"""

from __future__ import annotations

import dataclasses
import difflib
import inspect
import logging
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._options import BAD, ENERGY_MODEL, LINEAR_MODEL, Option, check_value, declarations, units_issues
from ..errors import ConfigError, InputError, MeshError, UnknownNameError
from .schema import Table, schema

__all__ = ["Issue", "ProblemSetup", "load_problem", "load_problem_text", "parse_toml", "validate_data"]

logger = logging.getLogger(__name__)

_BAD = BAD  # marker of a value that failed its check


@dataclass(frozen=True)
class Issue:
    """One problem of a problem file: the key path and what is wrong (with the fix)."""

    path: str
    message: str

    def __str__(self) -> str:
        if not self.path:
            return self.message
        sep = " " if self.message.startswith("= ") else ": "  # "key = value: ..." or "key: ..."
        return f"{self.path}{sep}{self.message}"


def _raise(issues: list[Issue], source: str) -> None:
    n = len(issues)
    head = f"{source}: {n} error{'s' if n != 1 else ''} (nothing was solved)"
    exc = ConfigError(head + "\n" + "\n".join(f"  {i}" for i in issues))
    exc.issues = list(issues)  # type: ignore[attr-defined]
    raise exc


def _did_you_mean(name: str, known) -> str:
    close = difflib.get_close_matches(str(name), [str(k) for k in known], n=1, cutoff=0.6)
    return f" Did you mean {close[0]!r}?" if close else ""


def _known(names) -> str:
    names = sorted(str(n) for n in names)
    return ", ".join(names) if names else "(none)"


# --------------------------------------------------------------------------- schema pass
def _check_value(opt: Option, value: Any, path: str, issues: list[Issue]) -> Any:
    """The value converted to its Python type, or ``_BAD`` (an issue is recorded)."""
    out, found = check_value(opt, value)
    issues.extend(Issue(path + suffix, msg) for suffix, msg in found)
    return out


def _subtables(path: str) -> dict[str, Table]:
    prefix = f"{path}." if path else ""
    return {t.path[len(prefix):]: t for t in schema()
            if t.path.startswith(prefix) and "." not in t.path[len(prefix):]}


def _check_table(tab: Table, data: Any, path: str, issues: list[Issue]) -> dict | None:
    if not isinstance(data, dict):
        kind = f"[[{tab.path}]]" if tab.array else f"[{tab.path}]"
        issues.append(Issue(path, f"must be a table ({kind}); got {type(data).__name__}."))
        return None
    subs = _subtables(tab.path)
    out: dict[str, Any] = {}
    extra: dict[str, Any] = {}
    for key, value in data.items():
        kp = f"{path}.{key}"
        if key in subs:
            out[key] = _check_node(subs[key], value, kp, issues)
        elif (opt := tab.get(key)) is not None:
            v = _check_value(opt, value, kp, issues)
            out[key] = _BAD if v is _BAD else v
        elif tab.open:
            extra[key] = value
        else:
            known = tab.names + list(subs)
            issues.append(Issue(kp, f"unknown key in [{tab.path}].{_did_you_mean(key, known)} "
                                    f"Known keys: {_known(known)}."))
    for opt in tab.options:
        if opt.name not in out:
            if opt.required:
                issues.append(Issue(f"{path}.{opt.name}", f"missing (required): {opt.doc}"))
                out[opt.name] = _BAD
            else:
                out[opt.name] = opt.default
    for key, sub in subs.items():
        if key not in out:  # absent sub-table: its defaults, or None when it has required keys
            if sub.array:
                out[key] = []
            else:
                out[key] = None if any(o.required for o in sub.options) else _check_table(sub, {}, key, issues)
    if tab.open:
        out["params"] = extra
    return out


def _check_node(tab: Table, value: Any, path: str, issues: list[Issue]):
    if tab.array:
        if isinstance(value, dict):
            issues.append(Issue(path, f"write each entry as [[{tab.path}]] (an array of tables), "
                                      f"not [{tab.path}]."))
            return []
        if not isinstance(value, list):
            issues.append(Issue(path, f"must be an array of tables [[{tab.path}]]; got {type(value).__name__}."))
            return []
        return [_check_table(tab, v, f"{path}[{i + 1}]", issues) for i, v in enumerate(value)]
    return _check_table(tab, value, path, issues)


def validate_data(data: dict) -> tuple[dict, list[Issue]]:
    """Schema pass over a parsed file: ``(normalized data with defaults, issues)``.

    Entries of arrays of tables are numbered from 1 in the key paths
    (``support[2].boundary`` is the second ``[[support]]``).
    """
    issues: list[Issue] = []
    roots = _subtables("")
    out: dict[str, Any] = {}
    for key, value in data.items():
        if key in roots:
            out[key] = _check_node(roots[key], value, key, issues)
        else:
            issues.append(Issue(key, f"unknown table [{key}].{_did_you_mean(key, roots)} "
                                     f"Known tables: {_known(roots)}."))
    for key, tab in roots.items():
        if key not in out:
            if tab.required:
                issues.append(Issue(key, f"missing table [{key}] (required): {tab.doc}"))
                out[key] = None
            elif tab.array:
                out[key] = []
            else:
                out[key] = _check_table(tab, {}, key, issues)
    return out, issues


# --------------------------------------------------------------------------- the built problem
@dataclass(frozen=True)
class ProblemSetup:
    """A validated problem file with everything built, ready to solve.

    Attributes
    ----------
    source : Path or None
        The file.
    data : dict
        Normalized contents (every option present, defaults filled in).
    problem : ContactProblem
        Body, obstacle, contact boundary, the un-ramped supports and loads, friction.
    history : LoadHistory or None
        Ramped supports/loads and step times (``None``: one step, nothing ramped).
    times : tuple of float
        Step times (``(1.0,)`` for a single step).
    algorithm, penalty : str, str or None
    options : dict
        :class:`~alcontact.contact.ContactOptions` fields of frictionless runs (the friction-only ones left out).
    friction_options : dict
        :class:`~alcontact.contact.ContactOptions` fields of frictional runs (``[solver]`` and ``[solver.friction]``).
    reference : HertzReference or None
    mindlin : MindlinReference or None
    output : dict
        The ``[output]`` table.
    kinematics : str
        ``"small"`` or ``"finite"`` (``[contact] kinematics``).
    obstacle_path : tuple of float or None
        Finite kinematics: translation of the obstacle per unit pseudo-time (``[obstacle] path``).
    max_cutbacks : int
        Finite kinematics: halvings of a failed step (``[loading] max_cutbacks``).
    units : tuple of (str or None)
        ``(length, stress, force)`` of ``[units]`` (``None``: unnamed; force checked to be
        stress x length^2), see :meth:`plot_units`.
    """

    source: Path | None
    data: dict
    problem: Any
    history: Any
    times: tuple[float, ...]
    algorithm: str
    penalty: str | None
    options: dict
    friction_options: dict
    reference: Any = None
    mindlin: Any = None
    output: dict = field(default_factory=dict)
    kinematics: str = "small"
    obstacle_path: tuple[float, ...] | None = None
    max_cutbacks: int = 6
    units: tuple[str | None, str | None, str | None] = (None, None, None)

    @property
    def finite(self) -> bool:
        """Finite-deformation run (:func:`alcontact.contact.solve_finite`)."""
        return self.kinematics == "finite"

    def obstacle_offset(self, t: float):
        """Translation of the obstacle at pseudo-time ``t`` (``t * path``), or ``None`` if it does not move."""
        if self.obstacle_path is None:
            return None
        import numpy as np

        return float(t) * np.asarray(self.obstacle_path, dtype=float)

    @property
    def name(self) -> str:
        return self.data["problem"]["name"]

    def plot_units(self):
        """The :class:`alcontact.viz.Units` of the labels (``[units]``; ``L`` / ``[E]`` without it)."""
        from ..viz.plots import Units

        return Units(*self.units)

    @property
    def friction(self) -> float:
        return float(self.problem.friction)

    @property
    def stepped(self) -> bool:
        return len(self.times) > 1 or self.history is not None

    def summary_line(self) -> str:
        m = self.problem.model
        law = f"Coulomb mu={self.friction:g}" if self.friction > 0 else "frictionless"
        alg = self.algorithm + (f"/{self.penalty}" if self.penalty else "")
        n = len(self.times)
        kin = f", finite deformation ({m.law.name})" if self.finite else ""
        return (f"{self.name}: {m.dim}D P{m.order}{kin}, {m.ndofs} DOFs, {m.mesh.nelements} elements, "
                f"obstacle {self.data['obstacle']['type']}, contact on {self.problem.contact_boundary!r}, "
                f"{law}, {alg}, {n} load step{'s' if n != 1 else ''}")


def _num(issues, path, fn, *args, **kwargs):
    """Call a builder, turning its InputError into an issue at ``path``."""
    try:
        return fn(*args, **kwargs)
    except InputError as exc:
        issues.append(Issue(path, str(exc)))
        return None


def _build_mesh(d: dict, base: Path, issues: list[Issue]):
    from ..fem import meshes

    gen = d["generator"]
    if gen == "file":
        if d["file"] is _BAD:  # the schema pass recorded the issue
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
        import contextlib
        import io

        try:
            # meshio prints and calls sys.exit(1) on some unreadable files: keep both from the user
            with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
                return meshes.read(p)
        except MeshError as exc:
            issues.append(Issue("mesh.file", f"= {d['file']!r}: {exc}"))
        except SystemExit:
            issues.append(Issue("mesh.file", f"= {d['file']!r}: cannot read mesh file {str(p)!r} (meshio gave up). "
                                             "Export it from Gmsh as .msh (format 2.2 or 4.1)."))
        return None
    dim = 2 if gen == "rectangle" else 3
    ok = True
    if d["file"]:
        issues.append(Issue("mesh.file", f"not used with generator = {gen!r}; remove it or set "
                                         "generator = 'file'."))
        ok = False
    for key, n, example in (("bounds", 2 * dim, "[0.0, 1.0, 0.0, 1.0]" if dim == 2 else "[0, 1, 0, 1, 0, 1]"),
                            ("cells", dim, "[8, 8]" if dim == 2 else "[4, 4, 4]")):
        v = d[key]
        if v is _BAD:
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
    refine = d["refine"]
    if refine is not None:
        if refine is _BAD or any(v is _BAD for v in refine.values()):
            ok = False
        elif len(refine["center"]) != dim:
            issues.append(Issue("mesh.refine.center", f"= {refine['center']!r}: needs {dim} coordinates for a "
                                                      f"{dim}D mesh."))
            ok = False
    if not ok:
        return None
    r = None
    if refine is not None:
        r = {k: v for k, v in refine.items() if v is not None}
    fn = meshes.rectangle if dim == 2 else meshes.box
    return _num(issues, "mesh", fn, *d["bounds"], *d["cells"], refine=r)


def _boundary(mesh, name: str, path: str, issues: list[Issue]) -> bool:
    known = sorted((mesh.boundaries or {}).keys())
    if name in known:
        return True
    issues.append(Issue(path, f"= {name!r}: the mesh has no boundary {name!r}.{_did_you_mean(name, known)} "
                              f"Mesh boundaries: {_known(known)}."))
    return False


def _ramp(knots):
    from ..contact import Ramp

    return Ramp(tuple(k[0] for k in knots), tuple(k[1] for k in knots), hold_before=True, hold_after=True)


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


def _obstacle(d: dict, dim: int | None, issues: list[Issue]):
    from ..contact import obstacles

    name = d["type"]
    if name is _BAD:
        return None
    if name == "user":
        issues.append(Issue("obstacle.type", "= 'user': a user obstacle needs Python functions; problem files "
                                             "hold data only. Use a registered shape, or build the problem in "
                                             "Python with alcontact.contact.obstacles.UserObstacle."))
        return None
    if name not in obstacles.available():
        known = [n for n in obstacles.available() if n != "user"]
        issues.append(Issue("obstacle.type", f"= {name!r}: unknown obstacle.{_did_you_mean(name, known)} "
                                             f"Known obstacles: {_known(known)}."))
        return None
    params = d["params"]
    from ..contact.obstacles import _REGISTRY  # signature of the factory: the accepted parameters

    sig = inspect.signature(_REGISTRY[name].factory)
    accepted = [p for p in sig.parameters]
    ok = True
    for key in params:
        if key not in accepted:
            issues.append(Issue(f"obstacle.{key}", f"unknown parameter of obstacle {name!r}."
                                                   f"{_did_you_mean(key, accepted)} Accepted: {_known(accepted)}."))
            ok = False
    for p in sig.parameters.values():
        if p.default is inspect.Parameter.empty and p.name not in params:
            issues.append(Issue(f"obstacle.{p.name}", f"missing: obstacle {name!r} needs {p.name} "
                                                      f"(parameters: {_known(accepted)})."))
            ok = False
    if not ok:
        return None
    try:
        ob = obstacles.make(name, **params)
    except (InputError, TypeError, ValueError, ArithmeticError) as exc:
        issues.append(Issue("obstacle", f"{name}: {exc or type(exc).__name__}. Check the parameters "
                                        f"({_known(accepted)}): finite numbers of a sensible size."))
        return None
    if dim is not None:
        try:
            ob.check_dim(dim)
        except InputError as exc:
            issues.append(Issue("obstacle.type", f"= {name!r}: {exc} (the mesh is {dim}D)."))
            return None
    return ob


def _text_of(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        _raise([Issue("", f"problem file {str(path)!r} does not exist; check the path "
                          f"(relative to {os.getcwd()!r}), or see examples/.")], str(path))
    except (OSError, UnicodeDecodeError) as exc:
        _raise([Issue("", f"cannot read problem file {str(path)!r}: {exc}.")], str(path))
    raise AssertionError  # pragma: no cover


def parse_toml(text: str, label: str = "problem file") -> dict:
    """The TOML document ``text`` as a dict; every way the text can fail to parse is a :class:`ConfigError`.

    The one parser of problem files (:func:`load_problem_text` and
    :func:`alcontact.io.preflight.check_problem`), so that no reading path lets a
    ``RecursionError`` (arrays nested hundreds of levels deep) or a ``ValueError``
    (an integer of more than 4300 digits) escape as a traceback.

    Raises
    ------
    ConfigError
        Naming ``label`` and the way out.
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        _raise([Issue("", f"not valid TOML: {exc}. Check quotes, brackets and '=' on that line.")], label)
    except ValueError as exc:  # e.g. an integer of more than 4300 digits (sys.get_int_max_str_digits)
        _raise([Issue("", f"cannot read the TOML: {exc}. Numbers must fit a 64-bit float (about 1.8e308).")],
               label)
    except RecursionError:
        _raise([Issue("", "arrays or tables nested too deeply to read; a problem file needs at most 3 levels "
                          "(e.g. ramp = [[0.0, 0.0], [1.0, 1.0]]). Check the brackets.")], label)
    raise AssertionError  # pragma: no cover


def load_problem(path: str | os.PathLike) -> ProblemSetup:
    """Read, validate and build the problem file ``path``.

    Raises
    ------
    ConfigError
        With every problem found (``exc.issues``); nothing has been solved.
    """
    if not isinstance(path, (str, os.PathLike)):
        _raise([Issue("", f"problem file = {path!r:.60}: expected a path (str or pathlib.Path), got "
                          f"{type(path).__name__}.")], "load_problem")
    p = Path(path)
    return load_problem_text(_text_of(p), base_dir=p.parent, source=p)


def load_problem_text(text: str, *, base_dir: str | os.PathLike = ".", source: str | os.PathLike | None = None
                      ) -> ProblemSetup:
    """:func:`load_problem` from the TOML text (mesh files relative to ``base_dir``)."""
    label = str(source) if source is not None else "problem file"
    data, issues = validate_data(parse_toml(text, label))
    setup = _build(data, Path(base_dir), issues, source)
    if issues:
        _raise(issues, label)
    assert setup is not None
    logger.info("loaded %s", setup.summary_line())
    return setup


def _ok(d) -> bool:
    return d is not None and d is not _BAD and all(v is not _BAD for v in d.values())


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


def _kinematics(mt, cd, dim, data: dict, issues: list[Issue]) -> tuple[str, str]:
    """``(kinematics, material model)`` of the file, with an issue for each combination that cannot run.

    Finite kinematics needs a hyperelastic law (plane strain in 2D) and, with friction
    (Coulomb at finite deformation, :func:`~alcontact.contact.solve_finite_friction`), no
    ``friction_ramp``; a
    hyperelastic law needs finite kinematics; ``[obstacle] path`` needs finite kinematics
    and one entry per space dimension.
    """
    kin = cd.get("kinematics") if isinstance(cd, dict) else "small"
    kin = "small" if kin is _BAD or kin is None else kin
    model = mt.get("model") if isinstance(mt, dict) else None
    if model is _BAD:
        model = None
    energy = mt.get("energy") if isinstance(mt, dict) else None
    if energy is not None and energy is not _BAD:
        if model is not None:
            issues.append(Issue("material.energy", f"given together with model = {model!r}: a user energy is "
                                                   "its own law; remove one of model and energy."))
        model = ENERGY_MODEL
        if kin != "finite":
            issues.append(Issue("contact.kinematics", "= 'small': a user material.energy is a hyperelastic law "
                                                      "and needs kinematics = 'finite'."))
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
        mu = cd.get("friction") if isinstance(cd, dict) else 0.0
        lo = data.get("loading")
        ramp = lo.get("friction_ramp") if isinstance(lo, dict) else None
        if isinstance(mu, float) and mu > 0 and ramp is not None and ramp is not _BAD:
            issues.append(Issue("loading.friction_ramp", "a friction amplitude is not available with "
                                                         "contact.kinematics = 'finite' (the coefficient is "
                                                         "constant); remove friction_ramp, or use kinematics = "
                                                         "'small'."))
        if dim == 2 and isinstance(mt, dict) and mt.get("plane") == "stress":
            issues.append(Issue("material.plane", "= 'stress': hyperelastic bodies in 2D are plane strain only; "
                                                  "set plane = 'strain' or use a 3D mesh."))
    od = data.get("obstacle")
    path = od.get("path") if isinstance(od, dict) else None
    if path is not None and path is not _BAD:
        if not finite:
            issues.append(Issue("obstacle.path", "a moving obstacle needs contact.kinematics = 'finite'; remove "
                                                 "path (small kinematics: move the body with a ramped support)."))
        elif dim is not None and len(path) != dim:
            issues.append(Issue("obstacle.path", f"= {path!r}: needs {dim} numbers (a translation per unit "
                                                 f"pseudo-time) for a {dim}D mesh."))
    return kin, model


def _split_message(msg: str, default: str) -> Issue:
    """An :class:`Issue` from an InputError message that starts with its key path (``key = ...`` / ``key: ...``)."""
    import re

    m = re.match(r"^([A-Za-z_][\w.\[\]]*)( = |: )(.*)$", msg, flags=re.S)
    if m is None or not m.group(1).startswith("material."):
        return Issue(default, msg)
    return Issue(m.group(1), ("= " if m.group(2) == " = " else "") + m.group(3))


def _material_law(mt: dict, law: str, issues: list[Issue]):
    """``(law instance or None, E, nu)`` of ``[material]``: the law built from ``model`` and
    ``[material.parameters]`` (or ``energy``), and the constants, completed from the moduli
    the law fixes (:meth:`~alcontact.fem.HyperelasticLaw.fixed_moduli`) and checked against them.

    ``E`` or ``nu`` is ``None`` (with an issue) when it is missing or cannot be derived.
    """
    from ..fem import EnergyExpression, check_material_parameters, make_material

    sub = mt.get("parameters")
    params = dict(sub.get("params") or {}) if isinstance(sub, dict) else {}
    E, nu = mt["E"], mt["nu"]

    def require(key: str, why: str):
        issues.append(Issue(f"material.{key}", f"missing (required {why})."))

    if law == LINEAR_MODEL or law is None:
        if params:
            issues.append(Issue("material.parameters", f"= {sorted(params)}: not used by the linear elastic model "
                                                       "(its constants are E and nu); remove [material.parameters] "
                                                       "or choose a hyperelastic model."))
        for key, v in (("E", E), ("nu", nu)):
            if v is None:
                require(key, "for the linear elastic model")
        return None, E, nu
    if law == ENERGY_MODEL:
        try:
            obj = EnergyExpression(mt["energy"], params, key="material.energy", params_key="material.parameters")
        except InputError as exc:
            issues.append(_split_message(str(exc), "material.energy"))
            return None, E, nu
    else:
        values, found = check_material_parameters(law, params)
        issues.extend(_split_message(f"material.parameters.{k} {m}" if m.startswith("= ")
                                     else f"material.parameters.{k}: {m}", "material.parameters")
                      for k, m in found)
        if found:
            return None, E, nu
        obj = make_material(law, **values)
    mu0, K0 = obj.fixed_moduli()
    if mu0 is None:  # the law takes its moduli from E and nu
        for key, v in (("E", E), ("nu", nu)):
            if v is None:
                require(key, f"for model {law!r}, which takes its shear and bulk moduli from E and nu")
        return obj, E, nu
    if K0 is None:  # mu0 fixed, the bulk modulus from nu
        if nu is None:
            require("nu", f"for model {law!r}: it sets the bulk modulus of the volumetric term")
            return obj, E, None
        E0 = 2.0 * mu0 * (1.0 + nu)
        what = f"model {law!r} with these parameters has initial shear modulus mu0 = {mu0:.6g}"
    else:  # the user energy fixes both
        E0 = 9.0 * K0 * mu0 / (3.0 * K0 + mu0)
        nu0 = (3.0 * K0 - 2.0 * mu0) / (2.0 * (3.0 * K0 + mu0))
        what = f"the energy has initial moduli mu0 = {mu0:.6g}, K0 = {K0:.6g}"
        if nu is not None and abs(nu - nu0) > 1e-6:
            issues.append(Issue("material.nu", f"= {nu!r}: {what}, so nu = {nu0:.9g}; remove nu (it is derived) "
                                               "or make it agree."))
            return obj, E, None
        nu = nu0
    if E is not None and abs(E - E0) > 1e-6 * E0:
        issues.append(Issue("material.E", f"= {E!r}: {what}, so E = 2 mu0 (1 + nu) = {E0:.9g} (consistency with "
                                          "linear elasticity); remove E (it is derived) or make it agree."
                            if K0 is None else f"= {E!r}: {what}, so E = {E0:.9g}; remove E (it is derived) or "
                                               "make it agree."))
        return obj, None, nu
    return obj, E0 if E is None else E, nu


def _build(data: dict, base: Path, issues: list[Issue], source) -> ProblemSetup | None:  # noqa: C901
    from ..contact import ContactOptions, ContactProblem, Pressure, Traction, BodyForce, Support
    from ..contact import FrictionOptions, friction_algorithms
    from ..contact import LoadCase, LoadHistory
    from ..contact._algorithms import find_algorithm, friction_only_options
    from ..fem import LinearElasticity, Material
    from ..fem._material import material_issues
    from ..fem.hyperelastic import Hyperelastic

    # ---- mesh
    mesh = dim = None
    md = data.get("mesh")
    if md is not None and md is not _BAD and md["generator"] is not _BAD:
        mesh = _build_mesh(md, base, issues)
        dim = None if mesh is None else int(mesh.dim())
    if mesh is not None and dim not in (2, 3):
        issue = Issue("mesh", f"the mesh is {dim}D; contact problems need a 2D or 3D mesh.")
        if md.get("generator") == "file":  # a Gmsh file without a body group: say which groups it has
            from .preflight import _low_dim_issue

            issue = _low_dim_issue(md, base, issue)
        issues.append(issue)
        mesh = dim = None

    # ---- kinematics and constitutive law
    mt = data.get("material")
    cd = data.get("contact")
    kinematics, law = _kinematics(mt, cd, dim, data, issues)

    # ---- material
    mat = law_obj = None
    if _ok({k: v for k, v in (mt or {}).items() if k != "region"}) and mt is not None:
        law_obj, E, nu = _material_law(mt, law, issues)
        bad = [] if E is None or nu is None else material_issues(E, nu, mt["plane"])  # keyed like the file
        issues.extend(Issue(f"material.{key}", msg) for key, msg in bad)
        if not bad and E is not None and nu is not None:
            mat = _num(issues, "material", Material, E=E, nu=nu, plane=mt["plane"])
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
            if mat is not None and (reg["E"], reg["nu"], reg["plane"]) != (mat.E, mat.nu, mat.plane):
                issues.append(Issue(rp, f"region {reg['name']!r} has E={reg['E']:g}, nu={reg['nu']:g}, "
                                        f"plane={reg['plane']!r}, different from [material]: several materials "
                                        "in one body are not supported yet (the FEM layer takes one material); "
                                        "use one [material] for the whole body."))

    # ---- boundaries, supports, loads
    contact_ok = _ok(cd)
    if contact_ok and mesh is not None:
        contact_ok = _boundary(mesh, cd["boundary"], "contact.boundary", issues)
    fixed, loads, cases = [], [], []
    for i, s in enumerate(data.get("support") or []):
        sp = f"support[{i + 1}]"
        if not _ok(s) or dim is None:
            continue
        good = _boundary(mesh, s["boundary"], f"{sp}.boundary", issues)
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
            continue
        item = Support(s["boundary"], None if comps is None else tuple(comps), value)
        if s["ramp"] is None:
            fixed.append(item)
        else:
            cases.append(LoadCase(item, _ramp(s["ramp"]), tangential=s["tangential"], name=sp))
    for i, ld in enumerate(data.get("load") or []):
        lp = f"load[{i + 1}]"
        if not _ok(ld) or dim is None:
            continue
        kind = ld["type"]
        good = True
        if kind in ("traction", "pressure"):
            if not ld["boundary"]:
                issues.append(Issue(f"{lp}.boundary", f"missing: a {kind} load needs boundary = 'NAME'."))
                good = False
            else:
                good = _boundary(mesh, ld["boundary"], f"{lp}.boundary", issues)
        elif ld["boundary"]:
            issues.append(Issue(f"{lp}.boundary", "not used by a body-force load (it acts on the whole body); "
                                                  "remove it."))
            good = False
        if kind == "pressure":
            if ld["value"] is None:
                issues.append(Issue(f"{lp}.value", "missing: a pressure load needs value = NUMBER."))
                good = False
            if ld["vector"] is not None:
                issues.append(Issue(f"{lp}.vector", "not used by a pressure load; give value = NUMBER instead."))
                good = False
        else:
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
        if not good:
            continue
        if kind == "traction":
            item = Traction(ld["boundary"], tuple(ld["vector"]))
        elif kind == "pressure":
            item = Pressure(ld["boundary"], float(ld["value"]))
        else:
            item = BodyForce(tuple(ld["vector"]))
        if ld["ramp"] is None:
            loads.append(item)
        else:
            cases.append(LoadCase(item, _ramp(ld["ramp"]), tangential=ld["tangential"], name=lp))

    # ---- load steps
    lo = data.get("loading")
    times: tuple[float, ...] | None = None
    friction_ramp = None
    if _ok(lo):
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

    # ---- obstacle, solver
    ob = None
    od = data.get("obstacle")
    if od is not None and od is not _BAD:
        ob = _obstacle(od, dim, issues)
    sv = data.get("solver")
    mu = cd["friction"] if isinstance(cd, dict) and isinstance(cd.get("friction"), float) else 0.0
    algorithm, penalty = "simo-laursen", None
    options: dict = {}
    fopts: dict = {}
    if sv is not None and _ok({k: v for k, v in sv.items() if k != "friction"}):
        algorithm = sv["algorithm"]
        penalty = sv["penalty"] or None
        own_penalty = find_algorithm(algorithm).penalty
        if penalty is not None and own_penalty is not None and penalty != own_penalty:
            issues.append(Issue("solver.penalty", f"= {penalty!r}: algorithm {algorithm!r} uses its own penalty; "
                                                  "set algorithm = 'family-p' to choose one, or remove penalty."))
        if isinstance(mu, float) and mu > 0 and algorithm not in friction_algorithms():
            issues.append(Issue("solver.algorithm", f"= {algorithm!r}: not available with friction (contact.friction"
                                                    f" = {mu:g}); use one of {_known(friction_algorithms())}."))
        skip = {"algorithm", "penalty", "friction"}
        given = {k: v for k, v in sv.items() if k not in skip and v is not None}
        try:
            ContactOptions(**given).validate()
        except InputError as exc:
            issues.append(Issue("solver", str(exc)))
        else:  # the linear-solver path must be one the algorithm's registry entry has at these kinematics
            try:
                find_algorithm(algorithm, friction=isinstance(mu, float) and mu > 0,
                               kinematics=kinematics if kinematics in ("small", "finite") else "small"
                               ).check_options(ContactOptions(**given))
            except UnknownNameError:
                pass  # an algorithm without friction support is reported above
            except InputError as exc:
                issues.append(Issue("solver.linear_solver", str(exc)))
        # one options type: the frictional runs read every [solver] key; the friction-only ones may also be
        # set in [solver.friction] (a value other than the default there wins; both set: they must agree)
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
        friction_only = set(friction_only_options())
        options = {k: v for k, v in given.items() if k not in friction_only}  # the frictionless runs' options
        try:
            FrictionOptions(**fopts).validate()
        except InputError as exc:
            issues.append(Issue("solver.friction", str(exc)))

    # ---- units (labels only; the set must be consistent)
    units: tuple = (None, None, None)
    ud = data.get("units")
    if _ok(ud):
        units = (ud["length"], ud["stress"], ud["force"])
        issues.extend(Issue(f"units.{key}", msg) for key, msg in units_issues(*units))

    # ---- reference
    ref = mindlin = None
    rd = data.get("reference")
    if _ok(rd) and rd["kind"] != "none":
        if rd["radius"] is None:
            issues.append(Issue("reference.radius", f"missing: reference kind {rd['kind']!r} needs the indenter "
                                                    "radius, e.g. radius = 10.0."))
        elif dim is not None and rd["center"] is not None and len(rd["center"]) != dim:
            issues.append(Issue("reference.center", f"= {rd['center']!r}: needs {dim} coordinates."))
        elif dim is not None and rd["axis"] >= dim:
            issues.append(Issue("reference.axis", f"= {rd['axis']}: must be < {dim} for a {dim}D mesh."))
        elif rd["kind"] == "cattaneo-mindlin" and (dim == 3 or not (isinstance(mu, float) and mu > 0)):
            issues.append(Issue("reference.kind", "= 'cattaneo-mindlin': needs a 2D mesh and contact.friction > 0."))
        elif mat is not None and dim is not None:
            from ..problems.hertz import HertzReference

            e_star = mat.E if (dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus
            ref = HertzReference("cylinder" if dim == 2 else "sphere", rd["radius"], e_star, rd["symmetry"])
            if rd["kind"] == "cattaneo-mindlin":
                from ..problems.friction import MindlinReference

                mindlin = MindlinReference(ref, float(mu))

    if issues or mesh is None or mat is None or ob is None or not contact_ok or times is None:
        if not issues:  # pragma: no cover - every failure above records an issue
            issues.append(Issue("", "the problem could not be built."))
        return None

    if law == LINEAR_MODEL:
        model = _num(issues, "mesh.order", LinearElasticity, mesh, mat, order=md["order"],
                     volumetric=md["volumetric"])
    elif md["volumetric"] != "full":
        issues.append(Issue("mesh.volumetric", f"= {md['volumetric']!r} applies to linear elasticity only; the "
                            f"hyperelastic model {law!r} uses the standard element: remove mesh.volumetric."))
        return None
    else:
        # the path of LinearElasticity: its mesh-quality errors are rewritten by alcontact.io.preflight
        if law_obj is None:
            return None
        model = _num(issues, "mesh.order", Hyperelastic, mesh, mat, order=md["order"], model=law_obj)
    if model is None:
        return None
    center = tuple(rd["center"]) if rd["center"] is not None else (0.0,) * dim
    # the origin is only a default centre unless a reference or [reference] center names it (viz.contact_center)
    meta = {"symmetry_axis": int(rd["axis"]), "center": center,
            "center_declared": rd["center"] is not None or rd["kind"] != "none"}
    problem = _num(issues, "", ContactProblem, model=model, obstacle=ob, contact_boundary=cd["boundary"],
                   supports=tuple(fixed), loads=tuple(loads), friction=float(mu), name=data["problem"]["name"],
                   reference=ref, meta=meta, kinematics=kinematics)
    history = None
    if kinematics == "finite" and not cases and problem is not None:
        fixed, cases = _proportional(fixed, loads)
        loads = []
        problem = dataclasses.replace(problem, supports=tuple(fixed), loads=())
    if cases or friction_ramp is not None or mu > 0:
        history = _num(issues, "loading", LoadHistory, tuple(cases), times, friction_ramp)
    if problem is None or issues:
        return None
    if mu == 0 and friction_ramp is not None:
        logger.warning("loading.friction_ramp is ignored: contact.friction = 0")
    return ProblemSetup(
        source=Path(source) if source is not None else None, data=data, problem=problem, history=history,
        times=times, algorithm=algorithm, penalty=penalty, options=options, friction_options=fopts,
        reference=ref, mindlin=mindlin, output=dict(data["output"]), kinematics=kinematics,
        obstacle_path=tuple(od["path"]) if od.get("path") is not None else None,
        max_cutbacks=int(lo["max_cutbacks"]), units=units,
    )
