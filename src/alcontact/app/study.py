"""``alcontact study``: the matrix problems x methods x penalty scales x update rules, measured.

The dissertation proposes augmented Lagrangian methods with family-P penalties (Algorithms
6.3 / 6.4, MET 1 (5.23) and MET 2 (5.25)) against the pure penalty (6.10), Simo & Laursen's
Algorithm 6.1 / 6.2 (Macaulay update (6.13)) and Rockafellar's (5.18); it leaves open how the
penalty parameter should be set and updated. :func:`run_study` answers that by measurement:
every cell of the matrix is one :func:`alcontact.contact.solve` in its own process, one CSV row
per cell (:data:`COLUMNS`), and :func:`alcontact.app.study_report.write_report` renders
``report.md`` and the heat maps from that CSV only.

Cells
-----
- problems (:data:`PROBLEMS`): built-in problems of :mod:`alcontact.problems`, among them the
  two-body Hertz cylinders (mortar), two meshes in ``--quick``, four in the full run;
- methods (:func:`methods`): ``penalty``, ``simo-laursen``, ``rockafellar`` and every MET 1 /
  MET 2 penalty of :func:`alcontact.contact.contact_penalties` under Algorithm 6.3 / 6.4
  (``family-p``), the semi-smooth Newton reference ``ssn`` and the barrier anchor ``log-barrier``
  (modified log barrier with fixed multipliers, no update rule; with friction per load step, the
  tangential part of Algorithm 6.2); a method the solver does not register for the problem's
  friction and kinematics (the pure penalty with friction) is not a cell. Under the study's
  ``eta_scaling = "adaptive"`` MET 1 and MET 2 are the same traction law (see
  :mod:`alcontact.contact.laws`), so their rows agree up to rounding;
- the scale of the automatic :math:`\\varepsilon_N` (``penalty_scale``, :math:`\\varepsilon_N` =
  scale :math:`\\times E'/h`): :data:`FULL_SCALES` (six decades) or :data:`QUICK_SCALES`; ``ssn`` has no
  penalty parameter (one cell);
- the frictionless penalty update rule (:func:`alcontact.optim.available_strategies`: ``fixed``,
  ``infeasibility``, Algorithm 5.4 as printed ``alg54-printed`` and as corrected ``alg54-corrected``, ...)
  of the multiplier methods, every rule at every scale (``--quick``: :data:`QUICK_RULES`); friction
  solvers and the barrier have no rule (``-``).

A cell is keyed by all its parameters and :data:`STUDY_VERSION`; a re-run skips the keys already
in ``results.csv``, and each finished row is appended and flushed, so an interrupted study keeps
every finished cell (Ctrl-C stops the parent, which kills the running cells; a half-written last
row is dropped on resume).

Counts and cost: outer, Newton and linear solves are summed over the accepted load steps (the
work of a step that was cut back is in the CPU time, ``cutbacks`` counts them); the CPU time of
the solve is divided by the CPU time of one sparse factorization + solve of the mesh's stiffness
(measured once per mesh in the same run, ``units/``).

Error against the reference: the relative error of the fitted peak pressure against Hertz's
:math:`p_0` for the load the model carries (``reference = "hertz"``), otherwise
:math:`\\|u - u_{ssn}\\|_\\infty / \\|u_{ssn}\\|_\\infty` against the converged ``ssn`` solution of the
same mesh (solved first, kept in ``ssn/``).

Where the committed reports come from
-------------------------------------
``docs/study-quick.md`` and ``docs/study.md`` are generated, never edited: ``alcontact study --quick
--jobs 2 --out DIR --publish docs/study-quick.md`` and ``alcontact study --jobs 2 --out DIR --publish
docs/study.md`` write ``report.md`` of the run into ``DIR`` and publish it with its ``results.csv``,
``study.json`` and heat maps in ``docs/study-quick/`` (``docs/study/``)
(:func:`alcontact.app.study_report.publish_report`); a resumed run publishes the completed CSV. Every
number of the report is computed from that CSV by :mod:`alcontact.app.study_report`.
"""

from __future__ import annotations

import csv
import json
import logging
import math
import multiprocessing as mp
import os
import signal
import time
from collections.abc import Callable, Iterable
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..errors import InputError, UnknownNameError
from .study_report import CSV_NAME, read_rows, write_report

__all__ = [
    "STUDY_VERSION",
    "COLUMNS",
    "PROBLEMS",
    "FULL_SCALES",
    "QUICK_SCALES",
    "REFERENCES",
    "StudyProblem",
    "StudyRun",
    "Method",
    "Cell",
    "methods",
    "plan",
    "run_study",
    "read_rows",
    "CSV_NAME",
]

log = logging.getLogger(__name__)

#: Version of the matrix and of the CSV layout; a results folder of another version is refused. Version 2:
#: every update rule at every eps scale, the two-body problem, the barrier anchor with friction, the counts
#: summed over the load steps, the columns ``steps`` and ``cutbacks``.
STUDY_VERSION = 2

#: Columns of ``results.csv`` (one row per cell).
COLUMNS = (
    "key", "study_version", "problem", "mesh", "dofs", "method", "algorithm", "penalty", "met", "family_p",
    "eps_scale", "rule", "status", "outer", "newton", "linear_solves", "steps", "cutbacks", "wall_s", "cpu_s",
    "linear_solve_s", "time_per_linear_solve", "eps_final", "error", "error_reference", "penetration",
    "complementarity", "message",
)

#: :math:`\\varepsilon_N` scales of the full run: six decades around the automatic value.
FULL_SCALES = (1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3)
#: Scales of ``--quick``.
QUICK_SCALES = (1e-2, 1.0, 1e2)
#: The rule of the per-problem sweep tables and heat maps (every rule runs at every scale).
BASE_RULE = "fixed"
#: Rules of ``--quick`` (the full run takes every registered rule): the base rule, the infeasibility rule and
#: Algorithm 5.4's rule as printed and as corrected.
QUICK_RULES = ("fixed", "infeasibility", "alg54-printed", "alg54-corrected")
#: Coulomb coefficient of the frictional ironing problem.
IRONING_MU = 0.3


#: What a problem's error is measured against (:attr:`StudyProblem.reference`): Hertz's peak pressure of the
#: load the model carries (``problem.reference``, a :class:`~alcontact.problems.hertz.HertzReference`), or the
#: displacement of the converged ``ssn`` solve of the same mesh.
REFERENCES = ("hertz", "ssn")


@dataclass(frozen=True)
class StudyProblem:
    """A problem of the study: a builder per mesh size and what its error is measured against.

    ``build(mesh)`` returns ``(problem, solve_kwargs)`` for :func:`alcontact.contact.solve`; the mesh
    values are what the CSV's ``mesh`` column shows (elements per contact half-width, cells across, ...,
    said in ``doc``). ``reference`` is one of :data:`REFERENCES`; ``frictional`` and ``kinematics`` select
    the methods the solver registers for the problem (:func:`plan`). A new problem (a two-body case, a
    3D mortar case, ...) is one entry of :data:`PROBLEMS` with its builder.
    """

    name: str
    doc: str
    build: Callable[[Any], tuple[Any, dict]]
    quick_meshes: tuple
    full_meshes: tuple
    reference: str = "ssn"
    frictional: bool = False
    kinematics: str = "small"

    def __post_init__(self):
        if self.reference not in REFERENCES:
            raise ValueError(f"StudyProblem {self.name!r}: reference {self.reference!r} is not one of {REFERENCES}")

    @property
    def analytical(self) -> bool:
        """Whether the error is measured against a closed form (else against the ``ssn`` solution)."""
        return self.reference != "ssn"


def _hertz_2d(n):
    from ..problems.hertz import hertz_2d

    return hertz_2d(n_per_a=int(n)), {}


def _hertz_3d(n):
    from ..problems.hertz import hertz_3d

    return hertz_3d(n_per_a=float(n)), {}


def _signorini(n):
    from ..problems.blocks import signorini_block

    return signorini_block(n=int(n)), {}


def _half_cylinder(n):
    from ..problems.half_cylinder import half_cylinder

    return half_cylinder(n=int(n), delta=0.4), {"steps": 8}


def _hemisphere(n):
    from ..problems.hemisphere import hemisphere

    return hemisphere(n=int(n)), {"steps": 5}


def _mindlin(n):
    from ..problems.friction import cattaneo_mindlin_2d

    problem, history = cattaneo_mindlin_2d(n_per_a=int(n), normal_steps=2, tangential_steps=2)
    return problem, {"history": history}


def _ironing(n):
    from ..problems.ironing import ironing, ironing_schedule

    problem = ironing(n=int(n), slide=0.5, slide_step=0.125, press_steps=2)
    times, path = ironing_schedule(problem)
    return problem, {"steps": times, "obstacle_path": path, "friction": IRONING_MU}


def _two_cylinders(n):
    from ..problems.hertz import LEVELS_2D
    from ..problems.two_body import hertz_cylinders

    return hertz_cylinders(level=LEVELS_2D.index(int(n))), {}


#: The problems of the study, by name (mesh sizes: ``quick_meshes`` in ``--quick``, ``full_meshes`` otherwise).
PROBLEMS: dict[str, StudyProblem] = {p.name: p for p in (
    StudyProblem("hertz-2d", "rigid cylinder on a block, plane strain, small deformation (elements per a)",
                 _hertz_2d, (2, 4), (4, 8, 16, 32), reference="hertz"),
    StudyProblem("hertz-3d", "rigid sphere on a block, small deformation (elements per a)",
                 _hertz_3d, (1, 2), (2, 3, 4, 6), reference="hertz"),
    StudyProblem("signorini", "cantilever block pressed onto a plane: contact with lift-off (cells across)",
                 _signorini, (2, 4), (4, 8, 16, 32)),
    StudyProblem("half-cylinder", "neo-Hookean half-cylinder pressed to delta/R = 0.4, 8 load steps (n)",
                 _half_cylinder, (4, 6), (6, 12, 18, 24), kinematics="finite"),
    StudyProblem("hemisphere", "neo-Hookean quarter hemisphere to delta/R = 0.2, 5 load steps (n)",
                 _hemisphere, (2, 3), (3, 4, 6, 8), kinematics="finite"),
    StudyProblem("cattaneo-mindlin", "Cattaneo-Mindlin: Hertz load then shear, Coulomb mu = 0.3 (elements per a)",
                 _mindlin, (2, 4), (4, 8, 16, 32), frictional=True),
    StudyProblem("ironing", "finite-deformation frictional ironing, mu = 0.3, press then slide 0.5 (elements "
                 "per unit length)", _ironing, (4, 6), (6, 8, 12, 16), frictional=True, kinematics="finite"),
    StudyProblem("hertz-2body", "two elastic cylinders (steel on aluminium), mortar, plane strain, small "
                 "deformation; Hertz with the effective radius and modulus (elements per a on the slave)",
                 _two_cylinders, (8, 16), (8, 16, 32, 64), reference="hertz"),
)}


@dataclass(frozen=True)
class Method:
    """A method of the study: ``label`` (CSV and ``--only``), the solver's algorithm and penalty."""

    label: str
    algorithm: str
    penalty: str | None
    met: str
    family_p: bool

    @property
    def has_penalty_parameter(self) -> bool:
        return self.algorithm != "ssn"

    @property
    def has_update_rule(self) -> bool:
        return self.algorithm in ("simo-laursen", "family-p")


def methods() -> list[Method]:
    """Every method of the study, from the registries (:func:`alcontact.contact.contact_penalties`,
    :func:`alcontact.penalties.facts`)."""
    from .. import penalties
    from ..contact import available_algorithms, contact_penalties

    out = [Method("penalty", "penalty", None, "-", False),
           Method("simo-laursen", "simo-laursen", None, "-", False)]
    for name in contact_penalties():
        f = penalties.facts(penalties.make(name))
        met = "1" if name.endswith("-met1") else "2" if name.endswith("-met2") else "-"
        out.append(Method(name, "family-p", name, met, bool(f.family_p)))
    out.append(Method("ssn", "ssn", None, "-", False))
    # the barrier anchor (modified log barrier, fixed multipliers): no multiplier update, no update rule
    out.append(Method("log-barrier", "log-barrier", None, "-", False))
    known = set(available_algorithms())
    return [m for m in out if m.algorithm in known]


@dataclass(frozen=True)
class Cell:
    """One solve of the matrix."""

    problem: str
    mesh: Any
    method: Method
    eps_scale: float | None
    rule: str

    @property
    def key(self) -> str:
        scale = "-" if self.eps_scale is None else f"{self.eps_scale:g}"
        return f"v{STUDY_VERSION}|{self.problem}|{self.mesh}|{self.method.label}|{scale}|{self.rule}"


def _applicable(problem: StudyProblem, method: Method) -> bool:
    """Whether the solver registers ``method`` for the problem's friction and kinematics (else: no cell)."""
    from ..contact.algorithms import algorithms as registered

    return any(e.name == method.algorithm for e in registered(friction=problem.frictional,
                                                                kinematics=problem.kinematics))


def _select(only: Iterable[str] | None) -> tuple[list[StudyProblem], list[Method]]:
    """Problems and methods named by ``--only`` (a problem name, a method label or an algorithm name)."""
    all_methods = methods()
    names = list(only or ())
    probs = [n for n in names if n in PROBLEMS]
    meths = []
    labels = {m.label for m in all_methods} | {m.algorithm for m in all_methods}
    for n in names:
        if n in PROBLEMS:
            continue
        if n not in labels:
            raise UnknownNameError("--only name", n, sorted(set(PROBLEMS) | labels))
        meths.append(n)
    problems = [PROBLEMS[n] for n in PROBLEMS if not probs or n in probs]
    chosen = [m for m in all_methods if not meths or m.label in meths or m.algorithm in meths]
    return problems, chosen


def plan(*, quick: bool = False, only: Iterable[str] | None = None, meshes: int | None = None) -> list[Cell]:
    """The cells of a study, reference (``ssn``) cells first.

    ``meshes`` keeps the ``meshes`` smallest mesh sizes of each problem (default: all of them).

    Raises
    ------
    UnknownNameError
        A name in ``only`` that is neither a problem nor a method (the closest match is named).
    InputError
        ``meshes`` below 1.
    """
    from ..optim import available_strategies

    if meshes is not None and not (isinstance(meshes, int) and meshes >= 1):
        raise InputError(f"--meshes must be a whole number of at least 1 (the smallest mesh sizes of each problem "
                         f"to keep); got {meshes!r}.")
    problems, chosen = _select(only)
    scales = QUICK_SCALES if quick else FULL_SCALES
    registered = available_strategies()
    rules = [r for r in (QUICK_RULES if quick else registered) if r in registered]
    rules = [r for r in rules if r == BASE_RULE] + [r for r in rules if r != BASE_RULE]  # the base rule first
    first, rest = [], []
    for p in problems:
        # the ssn reference of the error always runs for a problem without an analytical solution
        need_ref = not p.analytical and not any(m.algorithm == "ssn" for m in chosen)
        pm = list(chosen) + ([m for m in methods() if m.algorithm == "ssn"] if need_ref else [])
        for mesh in (p.quick_meshes if quick else p.full_meshes)[:meshes]:
            for m in pm:
                if not _applicable(p, m):
                    continue
                if not m.has_penalty_parameter:
                    first.append(Cell(p.name, mesh, m, None, "-"))
                    continue
                # every rule at every scale: which rule makes the method robust to the starting eps_N
                own_rules = rules if (m.has_update_rule and not p.frictional) else ["-"]
                rest += [Cell(p.name, mesh, m, s, r) for r in own_rules for s in scales]
    return first + rest


# ----------------------------------------------------------------------------------- one cell


def _linear_solve_seconds(model) -> float:
    """CPU seconds of one sparse LU factorization plus one solve of the stiffness at ``u = 0`` (best of 3).

    The unit of cost: the tangent of the undeformed body (the linear stiffness at small deformation),
    shifted by ``1e-8`` of its mean diagonal so that the unsupported matrix factorizes (same pattern,
    same cost).
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    K = sp.csc_matrix(model.tangent(np.zeros(model.ndofs)))
    K = (K + sp.identity(K.shape[0], format="csc") * (1e-8 * float(abs(K.diagonal()).mean()))).tocsc()
    rhs = np.ones(K.shape[0])
    best = math.inf
    for _ in range(3):
        t0 = time.process_time()
        splu(K).solve(rhs)
        best = min(best, time.process_time() - t0)
    return max(best, 1e-6)


def _unit_seconds(out: Path, cell: Cell, model) -> float:
    """:func:`_linear_solve_seconds` of the cell's mesh, measured once per mesh in the run (``units/``)."""
    path = out / "units" / f"{cell.problem}-{cell.mesh}.txt"
    try:
        return float(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        pass
    seconds = _linear_solve_seconds(model)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    tmp.write_text(f"{seconds!r}\n", encoding="utf-8")
    os.replace(tmp, path)  # atomic: a cell running at the same time reads the whole number or measures itself
    return seconds


def _ref_path(out: Path, cell: Cell) -> Path:
    return out / "ssn" / f"{cell.problem}-{cell.mesh}.npy"


def _error(cell: Cell, spec: StudyProblem, problem, sol, out: Path) -> tuple[float | None, str]:
    if spec.analytical:
        ref = problem.reference
        load = float(ref.load(float(sol.normal_force)))
        if load <= 0:
            return None, "hertz p0"
        p0 = float(ref.peak_pressure(load))
        return abs(float(sol.peak_pressure) - p0) / p0, "hertz p0"
    if cell.method.algorithm == "ssn":
        return None, "ssn (self)"
    path = _ref_path(out, cell)
    if not path.is_file():
        return None, "ssn (failed)"
    u_ref = np.load(path)
    scale = float(np.max(np.abs(u_ref)))
    return float(np.max(np.abs(np.asarray(sol.u) - u_ref)) / scale) if scale > 0 else None, "ssn u"


def solve_cell(cell: Cell, out: Path) -> dict:
    """Solve one cell and return its CSV row (runs in the cell's own process)."""
    from ..contact import solve

    spec = PROBLEMS[cell.problem]
    problem, kwargs = spec.build(cell.mesh)
    options: dict[str, Any] = {}
    if cell.eps_scale is not None:
        options["penalty_scale"] = float(cell.eps_scale)
    if cell.rule not in ("-",):
        options["strategy"] = cell.rule
    t_lin = _unit_seconds(out, cell, problem.model)
    w0, c0 = time.perf_counter(), time.process_time()
    sol = solve(problem, cell.method.algorithm, cell.method.penalty, options or None, **kwargs)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    res = sol.result
    # the whole solve: the sums over the accepted load steps (the last frame's result of a frictional run
    # holds that step's counts only); the work of attempts that were cut back is in the CPU time
    frames = sol.frames or ()
    outer = sum(int(f.outer_iterations) for f in frames) if frames else int(res.outer_iterations)
    newton = sum(int(f.newton_iterations) for f in frames) if frames else int(res.newton_iterations)
    solves = sum(int(f.linear_solves) for f in frames) if frames else int(res.linear_solves)
    row = _row_base(cell)
    row.update(dofs=int(problem.model.ndofs), penalty=res.penalty or row["penalty"], status=res.status.label,
               outer=outer, newton=newton, linear_solves=solves, steps=len(frames) or 1,
               cutbacks=sum(int(f.cutbacks) for f in frames), wall_s=f"{wall:.4g}", cpu_s=f"{cpu:.4g}",
               linear_solve_s=f"{t_lin:.4g}", time_per_linear_solve=f"{cpu / t_lin:.4g}",
               eps_final=f"{float(res.eps_n):.4g}", penetration=f"{float(res.penetration):.3e}",
               complementarity=f"{float(res.complementarity):.3e}",
               message=" ".join(str(res.message).split())[:200])
    if sol.success and cell.method.algorithm == "ssn" and not spec.analytical:
        path = _ref_path(out, cell)
        path.parent.mkdir(parents=True, exist_ok=True)
        np.save(path, np.asarray(sol.u, dtype=float))
    err, kind = _error(cell, spec, problem, sol, out) if sol.success else (None, "-")
    row.update(error="" if err is None else f"{err:.4e}", error_reference=kind)
    return row


def _row_base(cell: Cell) -> dict:
    m = cell.method
    row = {c: "" for c in COLUMNS}
    row.update(key=cell.key, study_version=STUDY_VERSION, problem=cell.problem, mesh=cell.mesh, method=m.label,
               algorithm=m.algorithm, penalty=m.penalty or ("rockafellar" if m.algorithm == "simo-laursen" else "-"),
               met=m.met, family_p=int(m.family_p), eps_scale="-" if cell.eps_scale is None else f"{cell.eps_scale:g}",
               rule=cell.rule)
    return row


#: Signals that stop a study (Ctrl-C, kill): handled by the parent only.
_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def _stop_signals_deferred():
    """Defer Ctrl-C / SIGTERM while a cell's process is forked: their handler runs after the fork, not inside it.

    A signal arriving while the parent forks runs its Python handler inside the interpreter's at-fork
    callbacks (the logging module's), where the exception it raises is printed and dropped ("Exception
    ignored"): the study went on. Here the handler only notes the signal; the original one runs after.
    """
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    old = {sig: signal.signal(sig, lambda signum, frame: caught.append(signum)) for sig in _STOP_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        if caught:
            handler = old[caught[0]]
            if callable(handler):
                handler(caught[0], None)
            elif handler == signal.SIG_DFL and caught[0] == signal.SIGINT:
                raise KeyboardInterrupt
            elif handler == signal.SIG_DFL:
                signal.raise_signal(caught[0])


def _child(cell: Cell, out: str, conn) -> None:
    # Ctrl-C reaches the whole process group: only the parent handles it (it kills the running cells and keeps
    # every finished row); a cell interrupted here would otherwise be recorded as crashed, or print a traceback
    for sig in _STOP_SIGNALS:
        signal.signal(sig, signal.SIG_IGN)
    logging.getLogger("alcontact").setLevel(logging.ERROR)  # the row carries the status; no warnings per cell
    try:
        row = solve_cell(cell, Path(out))
    except Exception as exc:  # a cell that raises is a measured outcome, recorded as status "error"
        row = _row_base(cell)
        row.update(status="error", message=f"{type(exc).__name__}: {' '.join(str(exc).split())[:200]}")
    conn.send(row)
    conn.close()


# ----------------------------------------------------------------------------------- the folder

_MARKER = "study.json"


def _csv_header(path: Path) -> list[str] | None:
    """The first row of ``path`` (``None`` without a file or an empty one)."""
    if not path.is_file():
        return None
    with path.open(newline="", encoding="utf-8") as fh:
        return next(csv.reader(fh), None)


def _open_folder(out: Path) -> None:
    """Create ``out`` or accept a study folder of this version; refuse anything else."""
    marker = out / _MARKER
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {str(out)!r} is a file; pass a folder.")
    if marker.is_file():
        try:
            meta = json.loads(marker.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            meta = {}
        if meta.get("study_version") != STUDY_VERSION:
            raise InputError(f"results folder {str(out)!r} holds a study of version {meta.get('study_version')!r}, "
                             f"this is version {STUDY_VERSION}: its cells cannot be resumed. Pass a new --out "
                             "folder (or delete that one to start over).")
        header = _csv_header(out / CSV_NAME)
        if header is not None and header != list(COLUMNS):
            raise InputError(f"{str(out / CSV_NAME)!r} does not have the columns of a version {STUDY_VERSION} study "
                             f"(first line {','.join(header)[:120]!r}): it was written by another version or edited. "
                             "Pass a new --out folder (or delete that one to start over).")
        return
    if out.is_dir() and any(out.iterdir()):
        raise InputError(f"--out {str(out)!r} is not empty and holds no study ({_MARKER} missing); pass a new or "
                         "empty folder.")
    out.mkdir(parents=True, exist_ok=True)
    marker.write_text(json.dumps({"study_version": STUDY_VERSION, "alcontact": __version__}, indent=1) + "\n",
                      encoding="utf-8")


def _complete_rows_only(csv_path: Path) -> None:
    """Drop a last line without its end of line (a run killed while writing it): every row left is whole."""
    if not csv_path.is_file():
        return
    data = csv_path.read_bytes()
    if data and not data.endswith(b"\n"):
        keep = data.rfind(b"\n") + 1
        log.warning("%s: dropping an unfinished last row (%d bytes) of an interrupted run", csv_path, len(data) - keep)
        with csv_path.open("r+b") as fh:
            fh.truncate(keep)


@dataclass
class StudyRun:
    """What :func:`run_study` did: the folder, cells planned, skipped (already in the CSV) and solved."""

    out: Path
    planned: int
    skipped: int
    solved: int
    report: Path | None = None
    rows: list = field(default_factory=list)


def run_study(out: str | os.PathLike, *, quick: bool = False, only: Iterable[str] | None = None, jobs: int = 1,
              timeout: float | None = None, progress: Callable[[int, int, dict], None] | None = None,
              report: bool = True, meshes: int | None = None) -> StudyRun:
    """Run (or resume) the study into ``out`` and write ``report.md`` and the heat maps.

    Parameters
    ----------
    out : path
        Results folder: ``results.csv``, ``study.json``, ``ssn/`` (references), ``report.md``, ``*.png``.
    quick : bool
        Two meshes per problem, :data:`QUICK_SCALES`, :data:`QUICK_RULES`.
    only : iterable of str
        Problem names, method labels or algorithm names; each given kind restricts the matrix.
    meshes : int, optional
        Keep the ``meshes`` smallest mesh sizes of each problem.
    jobs : int
        Cells solved at once, each in its own process.
    timeout : float, optional
        Seconds per cell (default 60 with ``quick``, 600 otherwise); a cell past it is killed and
        recorded with status ``timeout``.
    progress : callable ``(done, total, row)``
        Called after each finished cell (``row`` is ``{}`` for the initial call).

    Raises
    ------
    InputError
        ``jobs < 1``, ``meshes < 1``, an unknown name in ``only`` (:class:`UnknownNameError`), ``out`` from
        another study version, not a study folder, or a ``results.csv`` whose columns are not :data:`COLUMNS`.
    """
    if int(jobs) < 1:
        raise InputError(f"--jobs must be at least 1; got {jobs}.")
    cells = plan(quick=quick, only=only, meshes=meshes)
    out = Path(out)
    _open_folder(out)
    csv_path = out / CSV_NAME
    _complete_rows_only(csv_path)
    done_keys = {r.get("key") for r in read_rows(csv_path)}
    todo = [c for c in cells if c.key not in done_keys]
    run = StudyRun(out, len(cells), len(cells) - len(todo), 0)
    limit = float(timeout) if timeout is not None else (60.0 if quick else 600.0)
    log.info("study v%d: %d cells, %d already in %s, %d to solve", STUDY_VERSION, len(cells), run.skipped,
             csv_path, len(todo))
    if progress is not None:
        progress(run.skipped, len(cells), {})
    new = not csv_path.is_file() or csv_path.stat().st_size == 0
    with csv_path.open("a", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=COLUMNS)
        if new:
            writer.writeheader()
            fh.flush()

        def record(row: dict) -> None:
            writer.writerow(row)
            fh.flush()
            run.solved += 1
            run.rows.append(row)
            if progress is not None:
                progress(run.skipped + run.solved, len(cells), row)

        if todo:
            _warm_up({c.problem for c in todo})
        refs = [c for c in todo if c.method.algorithm == "ssn"]
        _run_cells(refs, out, int(jobs), limit, record)  # the references of the error first
        _run_cells([c for c in todo if c.method.algorithm != "ssn"], out, int(jobs), limit, record)
    if report:
        run.report = write_report(out, title=f"alcontact study (version {STUDY_VERSION}{', quick' if quick else ''})")
    return run


def _warm_up(problems: set[str]) -> None:
    """Solve each problem's smallest mesh once in this process, before the cells are forked from it.

    The first solve of a process imports the linear-solver backends and the solver modules it reaches
    (measured: 0.15 s of CPU inside the solve of a 4664-DOF 2D Hertz cell whose later solves take 0.05 s);
    forked from a warmed-up parent, every cell's CPU time is that of its solve.
    """
    from ..contact import solve

    level = logging.getLogger("alcontact").level
    logging.getLogger("alcontact").setLevel(logging.ERROR)
    try:
        for name in sorted(problems):
            spec = PROBLEMS[name]
            try:
                problem, kwargs = spec.build(spec.quick_meshes[0])
                solve(problem, "simo-laursen", None, None, **kwargs)
            except Exception:  # a warm-up only: the cells record their own failures
                log.debug("warm-up of %s failed", name, exc_info=True)
    finally:
        logging.getLogger("alcontact").setLevel(level)


def _past_limit(row: dict, limit: float) -> dict:
    """``row`` of a cell that finished, as a ``timeout`` when its solve took longer than ``limit`` seconds (it
    finished between two polls of the parent, which would otherwise have killed it)."""
    try:
        wall = float(row.get("wall_s") or 0.0)
    except ValueError:
        return row
    if wall > limit and row.get("status") != "timeout":
        row = dict(row, status="timeout", message=f"finished after {wall:.3g} s, past the {limit:g} s limit")
    return row


def _run_cells(cells: list[Cell], out: Path, jobs: int, limit: float, record: Callable[[dict], None]) -> None:
    """Solve ``cells``, at most ``jobs`` processes at once, each killed after ``limit`` seconds."""
    ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else mp.get_context()
    queue = list(cells)
    running: list[tuple[Cell, Any, Any, float]] = []
    try:
        while queue or running:
            while queue and len(running) < jobs:
                cell = queue.pop(0)
                recv, send = ctx.Pipe(duplex=False)
                proc = ctx.Process(target=_child, args=(cell, str(out), send), daemon=True)
                with _stop_signals_deferred():
                    proc.start()
                send.close()
                running.append((cell, proc, recv, time.perf_counter()))
            still = []
            for cell, proc, recv, t0 in running:
                row = None
                if recv.poll():
                    try:
                        row = _past_limit(recv.recv(), limit)
                    except EOFError:
                        row = _row_base(cell)
                        row.update(status="crashed", message=f"process exited with code {proc.exitcode}")
                elif not proc.is_alive():
                    proc.join()
                    row = _row_base(cell)
                    row.update(status="crashed", message=f"process exited with code {proc.exitcode}")
                elif time.perf_counter() - t0 > limit:
                    proc.kill()
                    row = _row_base(cell)
                    row.update(status="timeout", message=f"killed after {limit:g} s", wall_s=f"{limit:g}")
                if row is None:
                    still.append((cell, proc, recv, t0))
                    continue
                proc.join(timeout=5)
                recv.close()
                record(row)
            running = still
            if running:
                time.sleep(0.02)
    finally:
        for _, proc, recv, _ in running:  # interrupted: no orphaned cell processes
            proc.kill()
            proc.join(timeout=5)
