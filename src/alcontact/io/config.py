"""Problem files: read a TOML file, validate it against :mod:`alcontact.io.schema`, build the problem.

:func:`load_problem` does everything before solving: it parses the TOML, checks
every key against the schema (unknown keys with a "did you mean", wrong types,
values out of range), builds or reads the mesh, checks the boundary and region
names against it, builds the material, the obstacle (parameters checked
against the registered factory), the supports, loads and the load history,
and checks that algorithm, penalty and friction fit together (one builder per
section, in a fixed order: :mod:`alcontact.io._sections`). All problems
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

import logging
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._options import BAD, Option, check_value
from ._issues import Issue, _did_you_mean, _known, _raise
from ._rigid import rigid_issues, rigid_problem
from ._sections import build_bodies, build_model, build_problem, build_sections
from .schema import Table, schema

__all__ = ["Issue", "ProblemSetup", "load_problem", "load_problem_text", "parse_toml", "validate_data"]

logger = logging.getLogger(__name__)

_BAD = BAD  # marker of a value that failed its check


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


#: the tables that ``[[body]]`` replaces (each body has its own mesh and material; the master is a body's boundary)
_PER_BODY = ("mesh", "material", "obstacle")


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
    bodies = bool(data.get("body"))  # [[body]] tables replace [mesh], [material] and [obstacle]
    for key, tab in roots.items():
        if key not in out:
            if bodies and key in _PER_BODY:
                out[key] = None
            elif tab.required:
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
    petsc_options : dict
        ``[solver.petsc_options]``: PETSc options of the PETSc linear solver
        (:func:`alcontact.linalg.backend_options`); empty when not given.
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
    petsc_options: dict = field(default_factory=dict)

    @property
    def finite(self) -> bool:
        """Finite-deformation run (:func:`alcontact.contact.solve` of a ``kinematics="finite"`` problem)."""
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
        where = (f"obstacle {self.data['obstacle']['type']}, contact on {self.problem.contact_boundary!r}"
                 if self.data.get("obstacle") else "")
        if len(self.problem.pairs) > 1 or not where:
            where = f"{len(self.problem.pairs)} contact pairs (" + ", ".join(
                f"{p.slave.name!r} on {p.master.name}" for p in self.problem.pairs) + ")"
        if hasattr(m, "bodies"):  # [[body]]: several bodies
            parts = [b.mesh.nelements for b in m.bodies if b.mesh is not None]  # a rigid body has no mesh
            rigid = len(m.bodies) - len(parts)
            count = f"{len(parts)} bodies" if not rigid else \
                f"{len(parts)} bod{'y' if len(parts) == 1 else 'ies'} and {rigid} rigid bod{'y' if rigid == 1 else 'ies'}"
            return (f"{self.name}: {count}, {m.dim}D, {m.ndofs} DOFs, {sum(parts)} elements, "
                    f"{where}, {law}, {alg}, {n} load step{'s' if n != 1 else ''}")
        return (f"{self.name}: {m.dim}D P{m.order}{kin}, {m.ndofs} DOFs, {m.mesh.nelements} elements, "
                f"{where}, {law}, {alg}, {n} load step{'s' if n != 1 else ''}")


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


def _build(data: dict, base: Path, issues: list[Issue], source) -> ProblemSetup | None:
    """The :class:`ProblemSetup` of the normalized file ``data``, or ``None`` (every problem in ``issues``).

    Each section is built by its own builder (:mod:`alcontact.io._sections`); the model and
    the problem are built only when every section was.
    """
    if data.get("body"):
        return _build_bodies(data, base, issues, source)
    parts = build_sections(data, base, issues)
    rigid_issues(data, parts.dim, parts.kinematics, parts.mu, issues)
    if issues or not parts.complete():
        if not issues:  # pragma: no cover - every failure above records an issue
            issues.append(Issue("", "the problem could not be built."))
        return None
    model = build_model(data["mesh"], parts, issues)
    if model is None:
        return None
    problem, history = build_problem(data, model, parts, issues)
    problem, history = rigid_problem(data, problem, history, parts.times, issues)  # [obstacle] reference
    if problem is None or issues:
        return None
    if parts.mu == 0 and parts.friction_ramp is not None:
        logger.warning("loading.friction_ramp is ignored: contact.friction = 0")
    od, sv = data["obstacle"], parts.solver
    return ProblemSetup(
        source=Path(source) if source is not None else None, data=data, problem=problem, history=history,
        times=parts.times, algorithm=sv.algorithm, penalty=sv.penalty, options=sv.options,
        friction_options=sv.friction_options, reference=parts.reference, mindlin=parts.mindlin,
        output=dict(data["output"]), kinematics=parts.kinematics,
        obstacle_path=tuple(od["path"]) if od.get("path") is not None else None,
        max_cutbacks=int(data["loading"]["max_cutbacks"]), units=parts.units, petsc_options=sv.petsc_options,
    )


def _build_bodies(data: dict, base: Path, issues: list[Issue], source) -> ProblemSetup | None:
    """:func:`_build` of a file with ``[[body]]`` tables: several bodies and one two-body contact pair
    (:func:`alcontact.io._sections.build_bodies`)."""
    built = build_bodies(data, base, issues)
    if built is None or issues:
        if not issues:  # pragma: no cover - every failure records an issue
            issues.append(Issue("body", "the bodies could not be built."))
        return None
    problem, history, parts = built
    sv = parts.solver
    return ProblemSetup(
        source=Path(source) if source is not None else None, data=data, problem=problem, history=history,
        times=parts.times, algorithm=sv.algorithm, penalty=sv.penalty, options=sv.options,
        friction_options=sv.friction_options, reference=parts.reference, output=dict(data["output"]),
        max_cutbacks=int(data["loading"]["max_cutbacks"]), units=parts.units, petsc_options=sv.petsc_options,
    )
