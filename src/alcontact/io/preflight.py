r"""Pre-flight checks of a problem file: everything ``alcontact run`` would reject, found before solving.

:func:`check_problem` is what ``alcontact check`` runs, and what ``alcontact run``
runs before it solves. On top of :func:`~alcontact.io.config.load_problem`
(schema, names, builders) it checks:

- **size**, *before the mesh is built*: node, element and DOF counts from
  ``[mesh]`` (the 1D axis coordinates of the generators, or the header of a
  Gmsh file), the fill of the direct factorization or the AMG hierarchy, and
  the memory this needs against the machine's memory (``/proc/meminfo``);
  problems that would not fit, or would run for hours, are refused with the
  way out (a coarser mesh, ``linear_solver = "amg"``). The same check runs
  again with the exact counts once the mesh is built.
- **rigidity**: the contact points touching the obstacle may stop the motions
  the supports leave free, on the direct and on the AMG path: without friction
  through their normal motion (as :meth:`~alcontact.contact.systems._condensed.DiscreteContact._stabilize`
  and :meth:`~alcontact.contact.systems._krylov.IterativeContact._stabilize` do), with
  friction through all their components (normal contact plus friction, as
  :meth:`~alcontact.contact.systems._condensed.FrictionalContact._stabilize`;
  a load beyond the friction limit is then reported by ``run`` as sliding away).
  The message names the free motions and a ``[[support]]`` that stops them.
- **mesh quality** (inverted or degenerate elements, :mod:`alcontact.fem.quality`,
  raised when the body is built) and a Gmsh file without a physical group for
  the body (the file then holds only its boundary lines).
- **conflicting supports**: two supports giving one DOF different values, also
  when ramped supports meet fixed ones at some step time.
- **number ranges** of the material and the loads that double precision can
  carry through the solver (squares of stiffness entries must stay finite).

All problems are reported in one :class:`~alcontact.errors.ConfigError` whose
issues name the key path, the value and the way out.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from .._options import VALUE_RANGE
from ..errors import ConfigError, InputError
from ._bodies_check import bodies_issues
from ._sections import low_dim_issue
from .config import Issue, _raise, _text_of, load_problem, parse_toml, validate_data

__all__ = ["SizeEstimate", "Preflight", "check_problem", "estimate_size", "exact_size", "size_issues", "setup_issues",
           "machine_memory", "run_features", "run_seconds", "time_calibration", "machine_kind", "this_machine", "MAX_DOFS", "MAX_SECONDS", "MEMORY_FRACTION", "VALUE_RANGE"]

logger = logging.getLogger(__name__)

#: Refused above this many DOFs: hours of solving on a workstation-class machine even with AMG
#: (measured: 3D Hertz, P1, 5.06M DOFs on the AMG path, 18.3 GB peak and 21 CPU minutes for the
#: contact solve, ``docs/benchmarks/hertz_3d_large.md``; the memory test below decides first).
MAX_DOFS = 6_000_000
#: Refused when the estimated solve time exceeds this (seconds).
MAX_SECONDS = 4 * 3600.0
#: Refused when the estimated peak memory exceeds this fraction of the machine's memory.
MEMORY_FRACTION = 0.8

# Calibration (SuperLU/CHOLMOD on structured meshes, 20k-80k DOFs): nonzeros of the
# stiffness per DOF, of the factor per DOF (x log2 n in 2D, x n^(1/3) in 3D), and
# seconds of a whole contact solve (factorization and condensation ~ 3 factorizations).
_NNZ_K = {(2, 1): 12, (2, 2): 22, (3, 1): 36, (3, 2): 80}
_FILL_2D = 14.0  # nnz(L+U) = c n log2 n  (measured 9.5-12.7)
_FILL_3D = 40.0  # nnz(L+U) = c n^(4/3)   (measured 25-31)
_T_DIRECT_2D = 3e-7  # s * n^1.5
_T_DIRECT_3D = 6e-9  # s * n^2
_T_AMG = 2e-4  # s per DOF
_LOCAL = {(2, 1): 6, (2, 2): 12, (3, 1): 12, (3, 2): 30}  # DOFs per element
_QUAD = {(2, 1): 3, (2, 2): 6, (3, 1): 4, (3, 2): 11}  # quadrature points per element of the stiffness


# --------------------------------------------------------------------------- size
@dataclasses.dataclass(frozen=True)
class SizeEstimate:
    """Estimated size of a problem and of its solve.

    Attributes
    ----------
    dim, order : int
    nodes, elements, ndofs : int
        Scalar DOF locations (vertices, plus edge midpoints for P2), elements, DOFs.
    linear_solver : str
        ``"direct"`` or ``"amg"`` (the path the solver takes).
    memory_bytes : float
        Estimated peak memory of assembly, factorization/AMG and solution.
    seconds : float
        Rough solve time on a current workstation core.
    exact : bool
        ``False`` when counted before the mesh exists (from ``[mesh]`` or a file header).
    """

    dim: int
    order: int
    nodes: int
    elements: int
    ndofs: int
    linear_solver: str
    memory_bytes: float
    seconds: float
    exact: bool = False
    key: str = "mesh"
    value: Any = None
    note: str = ""

    def describe(self) -> str:
        about = "" if self.exact else "about "
        note = f" ({self.note})" if self.note else ""
        return (f"{about}{self.ndofs:,} DOFs, {self.elements:,} elements, {self.linear_solver} linear solver: "
                f"estimated peak memory {_gib(self.memory_bytes)}, solve time {_duration(self.seconds)}{note}")


#: Newton iterations of one finite-deformation load step (measured 8-12 on the half-cylinder, all subproblems).
NEWTON_PER_STEP = 10
#: Seconds per element and quadrature point of one tangent + internal-force assembly (vectorized einsum/bincount).
_T_TANGENT = 1e-6


def _finite_cost(est: SizeEstimate, data: dict) -> SizeEstimate:
    """``est`` of a finite-deformation run: steps x Newton iterations x (tangent assembly + factorization).

    A small-deformation solve factorizes the stiffness once (``est.seconds`` counts about
    3 factorizations); a finite one assembles and factorizes the tangent at every Newton
    iteration of every load step (:data:`NEWTON_PER_STEP`). Memory is that of one
    tangent and its factor, as before.
    """
    cd, lo = data.get("contact"), data.get("loading")
    if not (isinstance(cd, dict) and cd.get("kinematics") == "finite"):
        return est
    steps = 1
    if isinstance(lo, dict):
        times, n = lo.get("times"), lo.get("steps")
        steps = len(times) if isinstance(times, list) else n if isinstance(n, int) else 1
    per_newton = est.seconds / 3.0 + _T_TANGENT * est.elements * _QUAD[(est.dim, est.order)]
    newton = steps * NEWTON_PER_STEP
    return dataclasses.replace(est, seconds=newton * per_newton,
                               note=f"finite deformation: {steps} load steps x ~{NEWTON_PER_STEP} Newton "
                                    f"iterations, each a tangent assembly and solve")


def _gib(b: float) -> str:
    return f"{b / 2**30:.3g} GiB" if b >= 2**27 else f"{b / 2**20:.3g} MiB"


def _duration(s: float) -> str:
    if s < 60:
        return f"~{max(s, 0.1):.2g} s"
    if s < 3600:
        return f"~{s / 60:.2g} min"
    return f"~{s / 3600:.3g} h"


def machine_memory() -> tuple[float, float]:
    """``(total, available)`` memory of this machine in bytes (``/proc/meminfo``, else ``os.sysconf``)."""
    try:
        info = {}
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                key, _, rest = line.partition(":")
                info[key] = float(rest.split()[0]) * 1024.0
        total = info["MemTotal"]
        return total, info.get("MemAvailable", total)
    except (OSError, KeyError, ValueError, IndexError):
        try:
            total = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
        except (ValueError, OSError, AttributeError):  # pragma: no cover - exotic platforms
            total = float("inf")
        return total, total


def _direct_cost(dim: int, n: float, nnz_k: float) -> tuple[float, float]:
    """Factor memory (bytes, 16 per nonzero of L+U) and solve time of the sparse direct path."""
    if dim == 2:  # nested-dissection-like fill n log n, work n^1.5
        return _FILL_2D * n * math.log2(max(n, 2.0)) * 16, _T_DIRECT_2D * n**1.5
    return _FILL_3D * n ** (4.0 / 3.0) * 16, _T_DIRECT_3D * n**2  # 3D: fill n^(4/3), work n^2


#: Process peak of a contact solve on the AMG path: interpreter and libraries, plus bytes per
#: stiffness nonzero for everything that scales with the mesh (mesh, model and contact boundary
#: data, ``K`` on the free DOFs, the AMG hierarchy of :func:`alcontact.linalg._amg.smoothed_aggregation`
#: and its setup transient, the Newton matrix and its coarse operators, CG vectors). Measured on
#: 3D P1 Hertz (benchmarks/hertz_3d_large.py, peak resident set of the first contact solve:
#: 0.577 GB at 128,625 DOFs / 4.56M nonzeros, 3.71 GB at 1,041,984 DOFs / 37.8M nonzeros; the
#: fixed part is the interpreter, libraries and the fixed-size chunk temporaries of the
#: assembly and the AMG setup): see docs/benchmarks/hertz_3d_large.md
_AMG_PROCESS = 1.5e8
_AMG_BYTES_PER_NNZ = 94.0


def _amg_cost(dim: int, n: float, nnz_k: float) -> tuple[float, float]:
    """Whole-process peak memory (measured model above) and solve time (linear in n) of the AMG path."""
    return _AMG_PROCESS + _AMG_BYTES_PER_NNZ * nnz_k, _T_AMG * n


#: Memory and time model of each linear solver path (``ContactOptions.linear_solver`` after "auto").
_SOLVER_COST = {"direct": _direct_cost, "amg": _amg_cost}


def _cost(dim: int, order: int, nodes: int, elements: int, solver: str, exact: bool) -> SizeEstimate:
    n = dim * nodes
    key = (dim, order)
    nnz_k = _NNZ_K[key] * n
    local = _LOCAL[key]
    solver_mem, secs = _SOLVER_COST[solver](dim, float(n), float(nnz_k))
    if solver == "amg":  # measured as a whole (_amg_cost)
        mem = solver_mem
    else:
        mem = (nodes * dim * 8 + elements * (dim + 1) * 8 * 6  # mesh, facets, connectivity
               + elements * local * 2 * dim * _QUAD[key] * 8  # basis values and gradients (measured 2.4 kB/tet)
               + 1.5 * elements * local**2 * 24  # assembly (COO values, rows, columns) and conversion
               + 2 * nnz_k * 12  # stiffness and its condensed copy
               + n * 8 * 40  # solution vectors, fields, output
               + solver_mem)
    return SizeEstimate(dim, order, int(nodes), int(elements), int(n), solver, float(mem), float(secs), exact)


def _size_key(data: dict) -> tuple[str, Any]:
    """The ``[mesh]`` key that sets the size, and its value (for messages)."""
    md = data.get("mesh") if isinstance(data, dict) else None
    if not isinstance(md, dict):
        return "mesh", None
    if md.get("generator") == "file":
        return "mesh.file", md.get("file")
    r = md.get("refine")
    if isinstance(r, dict) and r.get("h_min") is not None:
        return "mesh.refine.h_min", r["h_min"]
    return "mesh.cells", md.get("cells")


def _resolve_solver(data: dict, dim: int, ndofs: int) -> str:
    sv = data.get("solver") or {}
    return _solver_path(sv.get("linear_solver", "auto") if isinstance(sv, dict) else "auto", dim, ndofs)


def _solver_path(name, dim: int, ndofs: int) -> str:
    """Cost model of the solver :func:`alcontact.linalg.select_solver` makes of ``name``: ``"direct"`` (it
    factorizes) or ``"amg"`` (an approximate solver preconditioning Krylov solves); ``"direct"`` for a name
    the problem-file check refuses anyway (or a solver that is not installed)."""
    from ..errors import InputError
    from ..linalg import select_solver

    try:
        return "direct" if select_solver(name, dim=dim, ndofs=ndofs).exact else "amg"
    except InputError:
        return "direct"


_HUGE_AXIS = 50_000_000


def _axis_count(a: float, b: float, n: int, r: dict | None, top: bool, ax: int) -> int:
    """Number of coordinates along one axis, as :func:`alcontact.fem.meshes.rectangle` would make them."""
    from ..fem.meshes import graded_axis

    if r is None:
        return int(n) + 1
    h_min = float(r["h_min"])
    growth = float(r.get("growth") or 1.2)
    h_max = float(r.get("h_max") or (b - a) / n)
    c = float(r["center"][ax])
    lo, hi = (c - r["depth"], b) if top else (c - r["width"], c + r["width"])
    lo_c, hi_c = max(lo, a), min(hi, b)
    fine = math.ceil((hi_c - lo_c) / h_min) if hi_c > lo_c else 0
    cap = max(h_max, h_min)
    graded = (b - a) / h_min if growth <= 1.0 else (math.log(cap / h_min) / math.log(growth) + 2 + (b - a) / cap)
    bound = fine + 2 * graded + 3
    if bound > _HUGE_AXIS:  # do not allocate the axis: it alone is too large
        return int(min(bound, 1e18))
    return int(graded_axis(a, b, lo, hi, h_min, growth, h_max).size)


def _generated_counts(md: dict, dim: int) -> tuple[int, int]:
    b, cells, r = md["bounds"], md["cells"], md["refine"]
    counts = [_axis_count(b[2 * k], b[2 * k + 1], cells[k], r, k == dim - 1, k) for k in range(dim)]
    nodes = math.prod(counts)
    boxes = math.prod(c - 1 for c in counts)
    elements = (2 if dim == 2 else 6) * boxes
    return nodes, elements


def _gmsh_header_counts(path: Path) -> tuple[int, int] | None:
    """Node and element counts from the section headers of an ASCII Gmsh file (None if not found)."""
    nodes = elements = None
    version = None
    try:
        with open(path, "rb") as fh:
            prev = b""
            for raw in fh:
                line = raw.strip()
                if prev == b"$MeshFormat":
                    parts = line.split()
                    version = parts[0].decode("ascii", "replace") if parts else None
                    if len(parts) > 1 and parts[1] != b"0":
                        return None  # binary file: the counts are not text
                elif prev in (b"$Nodes", b"$Elements"):
                    nums = [int(x) for x in line.split()]
                    count = nums[0] if (version or "").startswith("2") or len(nums) == 1 else nums[1]
                    if prev == b"$Nodes":
                        nodes = count
                    else:
                        elements = count
                    if nodes is not None and elements is not None:
                        return nodes, elements
                prev = line
    except (OSError, ValueError, IndexError):
        return None
    return None


def estimate_size(data: dict, base_dir: str | os.PathLike = ".") -> SizeEstimate | None:
    """Estimate the size of a validated problem file (:func:`~alcontact.io.config.validate_data`) before meshing.

    Generated meshes are counted from the 1D axis coordinates
    (:func:`~alcontact.fem.meshes.graded_axis`, never the 2D/3D mesh); Gmsh
    files from their ``$Nodes``/``$Elements`` headers (ASCII files). ``None``
    when the size cannot be known before meshing (binary or ``.geo`` files, an
    incomplete ``[mesh]``).
    """
    md = data.get("mesh")
    if not isinstance(md, dict):
        return None
    gen, order = md.get("generator"), md.get("order")
    if order not in (1, 2):
        return None
    try:
        if gen in ("rectangle", "box"):
            dim = 2 if gen == "rectangle" else 3
            b, cells, r = md.get("bounds"), md.get("cells"), md.get("refine")
            if not (isinstance(b, list) and isinstance(cells, list) and len(b) == 2 * dim and len(cells) == dim):
                return None
            if any(not b[2 * k] < b[2 * k + 1] for k in range(dim)):
                return None
            if r is not None and not (isinstance(r, dict) and isinstance(r.get("center"), list)
                                      and len(r["center"]) == dim
                                      and all(isinstance(r.get(k), float) for k in ("h_min", "width", "depth"))):
                return None
            vertices, elements = _generated_counts(md, dim)
        elif gen == "file" and isinstance(md.get("file"), str) and md["file"]:
            p = Path(md["file"])
            p = p if p.is_absolute() else Path(base_dir) / p
            counts = _gmsh_header_counts(p) if p.suffix.lower() == ".msh" and p.is_file() else None
            if counts is None:
                return None
            vertices, elements = counts
            dim = 3 if elements > 3.5 * vertices else 2  # tetrahedra: ~5-6 per vertex, triangles ~2
        else:
            return None
    except (TypeError, ValueError, KeyError, OverflowError):
        return None
    nodes = vertices
    if order == 2:  # edge midpoints (Euler): V + F - 1 edges in 2D, about V + T in 3D
        nodes = vertices + vertices + elements - (1 if dim == 2 else 0)
    n = dim * nodes
    key, value = _size_key(data)
    est = _cost(dim, order, nodes, elements, _resolve_solver(data, dim, n), exact=False)
    return _finite_cost(dataclasses.replace(est, key=key, value=value), data)


def exact_size(setup) -> SizeEstimate:
    """:class:`SizeEstimate` of a built problem (exact counts; memory and time still estimated)."""
    model = setup.problem.model
    solver = _resolve_solver(setup.data, model.dim, model.ndofs)
    if setup.options.get("linear_solver"):
        solver = _solver_path(setup.options["linear_solver"], model.dim, model.ndofs)
    key, value = _size_key(setup.data)
    # a mixed u-p body's unknowns are its displacement DOFs and one pressure per vertex: the cost model counts
    # the nodes of the displacement field, the size reported is every unknown
    nodes = getattr(model, "ndofs_u", model.ndofs) // model.dim
    parts = [b for b in getattr(model, "bodies", [model]) if b.mesh is not None]  # several bodies (a rigid one: none)
    est = _cost(model.dim, max(b.order for b in parts), nodes, sum(b.mesh.nelements for b in parts), solver,
                exact=True)
    return _finite_cost(dataclasses.replace(est, key=key, value=value, ndofs=int(model.ndofs)), setup.data)


def size_issues(est: SizeEstimate | None, memory: float | None = None) -> list[Issue]:
    """Issues when ``est`` would not fit in ``memory`` bytes (default: this machine's) or run too long."""
    if est is None:
        return []
    total = machine_memory()[0] if memory is None else float(memory)
    head = f"= {est.value!r}: " if est.value is not None else ""
    coarser = "a coarser mesh (fewer [mesh] cells, a larger mesh.refine.h_min or growth, or order = 1)"
    reasons, ways = [], [coarser]
    if est.ndofs > MAX_DOFS:
        reasons.append(f"more than {MAX_DOFS:,} DOFs would run for hours on this kind of machine")
        ways.append("grading (mesh.refine) instead of uniform cells for fine elements only where contact is")
    elif est.seconds > MAX_SECONDS:
        reasons.append(f"the solve would take longer than {_duration(MAX_SECONDS)}")
    if est.memory_bytes > MEMORY_FRACTION * total:
        reasons.append(f"it needs more than {MEMORY_FRACTION:.0%} of this machine's {_gib(total)} of memory")
    if not reasons:
        return []
    if est.linear_solver == "direct" and est.dim == 3:
        amg = _cost(est.dim, est.order, est.nodes, est.elements, "amg", est.exact)
        ways.append(f"solver.linear_solver = 'amg' (no factorization: about {_gib(amg.memory_bytes)}, "
                    f"{_duration(amg.seconds)})")
    return [Issue(est.key, f"{head}{est.describe()}: {'; '.join(reasons)}. Use {' or '.join(ways)}.")]


def _touching_points(setup, fixed: np.ndarray):
    """The contact points that touch the obstacle at the start, as ``_stabilize`` finds them.

    Returns ``(dofs, coef, is_fixed, near, gmax, h)``: the points' DOFs ``(m, d)``, the
    coefficients of their normal motion (zero on fixed components), the fixed-DOF mask, the
    points that can move and lie within ``h/2`` of the largest gap ``gmax`` (``-inf`` when no
    point can move), and the contact-zone element size ``h``.
    """
    from ..contact import contact_element_size

    prob = setup.problem
    model = prob.model
    pts, dofs = prob.slave_nodes()
    gap0, nu = prob.obstacle.evaluate(pts)
    is_fixed = np.zeros(model.ndofs, dtype=bool)
    is_fixed[fixed] = True
    coef = np.where(is_fixed[dofs], 0.0, -nu)
    movable = np.linalg.norm(coef, axis=1) > 1e-12
    h = min(contact_element_size(model, p.slave.name, p.master) for p in prob.pairs)
    g0 = np.where(movable, gap0, -np.inf)
    gmax = float(np.max(g0, initial=-np.inf))
    near = np.flatnonzero(movable & (g0 >= gmax - 0.5 * h)) if movable.any() else np.zeros(0, dtype=np.int64)
    return dofs, coef, is_fixed, near, gmax, h


# --------------------------------------------------------------------------- rigidity
def _contact_points_restrain(setup, fixed: np.ndarray, null: np.ndarray, R, row_of, *,
                             all_components: bool = False) -> tuple[bool, str]:
    """Whether the contact points touching the obstacle stop the free motions (as ``_stabilize`` does).

    Frictionless (``_discrete.DiscreteContact._stabilize``) only their normal motion
    counts; with friction (``all_components``, ``_friction_discrete.FrictionalContact._stabilize``)
    the pressed points also hold their tangential motion, so every free component counts.
    """
    from ..fem import numerical_rank

    dofs, coef, is_fixed, near, gmax, h = _touching_points(setup, fixed)
    if gmax == -np.inf:
        return False, "no contact point can move toward the obstacle"
    if gmax < -0.5 * h:
        return False, f"the body does not touch the obstacle either (closest gap {-gmax:.3g})"
    if all_components:  # every free component of the touching points: mode_k(X_i, c)
        N = R[row_of[dofs[near]]][~is_fixed[dofs[near]]]
    else:  # normal constraint rows: sum_c coef_ic * mode_k(X_i, c)
        N = np.einsum("ic,ick->ik", coef[near], R[row_of[dofs[near]]])
    if numerical_rank(N @ null.T) == null.shape[0]:
        return True, ""
    return False, f"the {near.size} contact point(s) touching the obstacle do not stop it either"


def _rigidity_issues(setup) -> list[Issue]:
    from ..fem.elasticity import describe_motions

    prob = setup.problem
    model = prob.model
    fixed = _fixed_dofs(setup)
    null, names, R, row_of = model.free_rigid_motions(fixed)
    if null.shape[0] == 0:
        return []
    free = describe_motions(null, names)
    # normal contact (and with friction, the tangential springs of the pressed points) may hold the body (both
    # solver paths)
    ok, why = _contact_points_restrain(setup, fixed, null, R, row_of, all_components=setup.friction > 0)
    if ok:
        return []
    fix = model._support_hint(null, R, row_of, prob.contact_boundary)  # the way out of the solver's own message
    return [Issue("support", f"rigid-body motion(s) not stopped by the supports: {free}, and {why}: nothing "
                             f"holds the body. {fix}, or move the obstacle into contact.")]


# --------------------------------------------------------------------------- supports, ranges
def _ramped_support_issues(setup) -> list[Issue]:
    """Fixed and ramped supports that give one DOF different values at some step time."""
    from ..contact import Support, merge_supports

    if setup.history is None:
        return []
    cases = [c for c in setup.history.cases if isinstance(c.item, Support)]
    if not cases:
        return []
    fixed_labels = [f"support[{i + 1}]" for i, s in enumerate(setup.data.get("support") or [])
                    if isinstance(s, dict) and s.get("ramp") is None]
    fixed = list(setup.problem.supports)
    if len(fixed_labels) != len(fixed):
        fixed_labels = [f"support on {s.boundary!r}" for s in fixed]
    items = fixed + [c.item for c in cases]
    labels = fixed_labels + [c.name or f"ramped support on {c.item.boundary!r}" for c in cases]
    for t in setup.times:
        scales = [1.0] * len(fixed) + [float(c.amplitude(t)) for c in cases]
        try:
            merge_supports(setup.problem.model, items, labels, scales=scales)
        except InputError as exc:
            return [Issue("support", f"at step time t = {t:g}: {exc}")]
    return []


def _range_issues(setup) -> list[Issue]:
    lo, hi = VALUE_RANGE
    issues = []
    mat = setup.problem.model.material
    lam, mu = mat.lame(setup.problem.model.dim)
    if not (lo <= mat.E <= hi) or not math.isfinite(lam + 2 * mu):
        issues.append(Issue("material.E", f"= {mat.E:g}: outside {lo:g} .. {hi:g}, where the solver's double "
                                          "precision stays finite (stiffness entries scale with E and the "
                                          "solver squares them: E = 1e308 overflows to infinity). Express E in "
                                          "other units, e.g. MPa or GPa instead of Pa (and the loads alike)."))
    for i, ld in enumerate(setup.data.get("load") or []):
        if not isinstance(ld, dict):
            continue
        vals = [ld.get("value")] if ld.get("value") is not None else list(ld.get("vector") or [])
        big = [v for v in vals if isinstance(v, float) and v != 0 and not (lo <= abs(v) <= hi)]
        if big:
            key = "value" if ld.get("value") is not None else "vector"
            issues.append(Issue(f"load[{i + 1}].{key}", f"= {ld[key]!r}: magnitudes outside {lo:g} .. {hi:g} "
                                                         "overflow or underflow in the solver; rescale the units."))
    return issues + _support_range_issues(setup)


#: largest prescribed displacement over the body's size: beyond it the gaps at the displaced positions are
#: round-off at the default penetration tolerance (1e-8 h) for any element size above 1e-8 of the body
SUPPORT_RANGE = 1e6


def _support_range_issues(setup) -> list[Issue]:
    """Support values far beyond the body's size (a support moved by 1e14): double precision cannot resolve the
    gaps, the contact forces or the equilibrium at such positions (issue 18: reported converged before)."""
    mesh = getattr(setup.problem.model, "mesh", None)
    if mesh is None:
        return []
    size = float(np.max(np.ptp(np.asarray(mesh.p, dtype=float), axis=1)))
    issues = []
    for i, sd in enumerate(setup.data.get("support") or []):
        if not isinstance(sd, dict) or sd.get("value") is None:
            continue
        vals = np.atleast_1d(np.asarray(sd["value"], dtype=float)) if _numbers(sd["value"]) else np.zeros(0)
        big = float(np.max(np.abs(vals), initial=0.0))
        if big > SUPPORT_RANGE * size:
            issues.append(Issue(f"support[{i + 1}].value", f"= {sd['value']!r}: a displacement of {big:g} is "
                                f"{big / size:.1e} times the body's size ({size:g}); at such positions double "
                                "precision cannot resolve the gaps, contact forces or equilibrium. Prescribe a "
                                f"displacement of at most {SUPPORT_RANGE:g} times the body's size (check the units)."))
    return issues


def _numbers(v) -> bool:
    """Whether ``v`` is a number or a list of numbers (anything else is the schema's to report)."""
    items = v if isinstance(v, (list, tuple)) else [v]
    return all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in items)


def _pinned_issues(setup) -> list[Issue]:
    """Contact points whose normal motion is fully prescribed but that start inside the obstacle.

    The gap (6.15) of such a point is known without solving; the direct and AMG
    paths reject it (``ContactPoints._setup_candidates``).
    """
    prob = setup.problem
    if setup.friction > 0 or setup.history is not None or not prob.supports:
        return []
    model = prob.model
    fixed, values = prob.dirichlet()
    pts, dofs = prob.slave_nodes()
    gap0, nu = prob.obstacle.evaluate(pts)
    u = np.zeros(model.ndofs)
    u[fixed] = values
    is_fixed = np.zeros(model.ndofs, dtype=bool)
    is_fixed[fixed] = True
    pinned = np.all(is_fixed[dofs] | (np.abs(nu) <= 1e-12), axis=1)
    g = gap0 - np.einsum("ij,ij->i", nu, u[dofs])
    bad = np.flatnonzero(pinned & (g > 0))
    if bad.size == 0:
        return []
    i = int(bad[np.argmax(g[bad])])
    return [Issue("support", f"{bad.size} contact point(s) of {prob.contact_boundary!r} are held by supports in "
                             f"the normal direction but start inside the obstacle (deepest: "
                             f"{np.round(pts[i], 6).tolist()} by {g[i]:.3g}): move the obstacle out of the "
                             "body, or release the normal component of the support on the contact boundary.")]


def _fixed_dofs(setup) -> np.ndarray:
    """DOFs fixed by the supports, ramped ones included (as :func:`_rigidity_issues`)."""
    from ..contact import Support

    prob = setup.problem
    model = prob.model
    fixed = prob.dirichlet()[0]
    if setup.history is not None:
        extra = [model.dirichlet(c.item.boundary, None if c.item.components is None else list(c.item.components),
                                 c.item.value)[0] for c in setup.history.cases if isinstance(c.item, Support)]
        fixed = np.unique(np.concatenate([fixed, *extra])) if extra else fixed
    return np.asarray(fixed, dtype=np.int64)


def _piece_issues(setup) -> list[Issue]:
    """A mesh of several disconnected pieces, one of which nothing holds (no support, no contact).

    :func:`_rigidity_issues` is exact for a connected body; a second piece of the mesh
    has rigid motions of its own, and a piece without supports and away from the
    obstacle makes the stiffness matrix singular. Each piece is checked as the whole
    body is: the supports on it and the contact points touching the obstacle (with
    friction, all their components) must stop its rigid motions.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from ..fem import rigid_body_modes

    prob = setup.problem
    model = prob.model
    sdofs = getattr(model, "scalar_dofs", None)
    if sdofs is None:
        return []
    ed = np.asarray(sdofs.element_dofs)  # (nloc, nel) scalar DOFs of each element
    n = int(model.dof_map.shape[0])
    rows = np.repeat(ed[:1], ed.shape[0] - 1, axis=0).ravel()
    graph = coo_matrix((np.ones(rows.size), (rows, ed[1:].ravel())), shape=(n, n))
    count, piece = connected_components(graph, directed=False)
    if count <= 1:
        return []
    fixed = _fixed_dofs(setup)
    pts, _ = model.all_node_dofs()
    modes, _ = rigid_body_modes(pts)
    nm = modes.shape[-1]
    scalar_of = np.empty(model.ndofs, dtype=np.int64)
    scalar_of[model.dof_map.ravel()] = np.repeat(np.arange(n), model.dof_map.shape[1])
    comp_of = np.empty(model.ndofs, dtype=np.int64)
    comp_of[model.dof_map.ravel()] = np.tile(np.arange(model.dof_map.shape[1]), n)
    from ..fem import numerical_rank

    # contact rows: the points touching the obstacle (as _contact_points_restrain finds them)
    cdofs, coef, is_fixed, near, _, _ = _touching_points(setup, fixed)
    near_scalar = scalar_of[cdofs[near, 0]] if near.size else np.zeros(0, dtype=np.int64)
    for c in range(count):
        sel = fixed[piece[scalar_of[fixed]] == c]
        blocks = [modes[scalar_of[sel], comp_of[sel]]]
        mine = near[piece[near_scalar] == c] if near.size else near
        for i in mine:
            vals = modes[scalar_of[cdofs[i, 0]]]  # (dim, nm): each mode's displacement at the point
            if setup.friction > 0:
                blocks += [vals[k][None, :] for k in range(vals.shape[0]) if not is_fixed[cdofs[i, k]]]
            else:
                blocks.append((coef[i] @ vals)[None, :])
        held = np.vstack(blocks) if blocks else np.zeros((0, nm))
        if numerical_rank(held) < nm:
            members = np.flatnonzero(piece == c)
            lo, hi = pts[members].min(axis=0), pts[members].max(axis=0)
            box = " x ".join(f"[{a:.4g}, {b:.4g}]" for a, b in zip(lo, hi))
            return [Issue("mesh", f"the mesh has {count} disconnected pieces, and nothing holds piece {c + 1} "
                                  f"({members.size} nodes in {box}): no support stops its rigid motions and it does "
                                  "not touch the obstacle, so the stiffness matrix is singular. Remove the piece "
                                  "from the mesh (a stray surface/volume in the Gmsh file), connect it to the body "
                                  "(shared nodes; Gmsh: Coherence), or add a [[support]] on a boundary of it.")]
    return []


def _tangential_first_step_issues(setup) -> list[Issue]:
    """A tangential load already non-zero at the first step time: the frictional solver refuses it.

    At the start of the first step no point carries a contact pressure, so no point is
    in contact there (``_friction._closed`` needs ``t_N > 0``) and
    :func:`alcontact.contact.solve` with friction raises for any tangential case with a non-zero
    value at the first step: known without solving.
    """
    if setup.friction <= 0 or setup.history is None or getattr(setup.problem, "kinematics", "small") != "small":
        return []
    t1 = float(setup.times[0])
    active = [c for c in setup.history.cases if c.tangential and c.value(t1) != 0.0]
    if not active:
        return []
    names = ", ".join(c.label for c in active)
    return [Issue("loading", f"the tangential load {names} is already non-zero at the first step time t = {t1:g}, "
                             "before any point is in contact (the frictional solver needs contact at the start of "
                             "a step that shears): ramp the normal load first and start the tangential ramp at 0 "
                             "until then (e.g. ramp = [[0.5, 0.0], [1.0, 1.0]]) with [loading] steps (or times) "
                             "that put a step before it.")]


def _mixed_solver_issues(setup) -> list[Issue]:
    """An approximate ``linear_solver`` (``"amg"``) for a mixed u-p body: its Newton matrices are saddle-point
    systems (symmetric indefinite) that AMG-preconditioned CG cannot solve, and the solve refuses it
    (``alcontact.contact.solve`` raises the same): known without solving."""
    from ..fem import MixedHyperelastic

    model = setup.problem.model
    sv = setup.data.get("solver") or {}
    name = setup.options.get("linear_solver") or (sv.get("linear_solver", "auto") if isinstance(sv, dict) else "auto")
    if not isinstance(model, MixedHyperelastic) or name in ("auto", "direct"):
        return []
    if _solver_path(name, model.dim, model.ndofs) == "direct":
        return []
    return [Issue("solver.linear_solver", f"= {name!r}: an approximate solver cannot solve the Newton systems of a "
                                          "mixed u-p body (material.formulation = 'mixed'): they are saddle-point "
                                          "matrices (symmetric indefinite), on which AMG-preconditioned CG fails; use "
                                          "linear_solver = 'auto', 'direct' or a direct solver (mkl-pardiso, superlu).")]


def setup_issues(setup) -> list[Issue]:
    """Issues of a built problem: rigidity on the solver's path, ramped support conflicts, number ranges."""
    if hasattr(setup.problem.model, "bodies"):  # several bodies: their own checks (io._bodies_check)
        return _ramped_support_issues(setup) + bodies_issues(setup, _fixed_dofs(setup))
    issues = _range_issues(setup)
    if issues:  # the rigidity test would report the overflow as a free motion
        return issues
    return (_ramped_support_issues(setup) + _pinned_issues(setup) + _tangential_first_step_issues(setup)
            + _piece_issues(setup) + _mixed_solver_issues(setup) + _rigidity_issues(setup))


# --------------------------------------------------------------------------- run time
#: Calibration of :func:`run_seconds` (written by ``benchmarks/time_estimates.py``).
CALIBRATION_FILE = Path(__file__).with_name("time_calibration.json")


def time_calibration() -> dict:
    """The committed calibration of the run-time estimates (empty when the file is missing)."""
    import json

    try:
        return json.loads(CALIBRATION_FILE.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


def run_features(setup, size: SizeEstimate) -> dict[str, Any]:
    """What :func:`run_seconds` depends on: DOFs, load steps, friction, finite deformation, solver model time."""
    return {"ndofs": int(size.ndofs), "steps": len(setup.times), "friction": int(setup.friction > 0),
            "finite": int(setup.finite), "solver_s": float(size.seconds)}


def run_seconds(setup, size: SizeEstimate, calibration: dict | None = None) -> float:
    r"""Estimated wall time of ``alcontact run FILE`` on the calibration machine, in seconds.

    .. math::

        t = a + S\,(b + b_f\,[\text{friction}] + b_F\,[\text{finite}]) + c\,n\,S + t_{solver}

    :math:`t_{solver}` is ``size.seconds`` (the linear-algebra cost model above);
    :math:`a, b, b_f, b_F, c` are fitted on the example files by
    ``benchmarks/time_estimates.py`` (``time_calibration.json``, report in
    ``docs/benchmarks/time_estimates.md``: within a factor 2 of the measured time on
    every example).
    """
    cal = (time_calibration() if calibration is None else calibration).get("run") or {}
    f = run_features(setup, size)
    S = f["steps"]
    return (cal.get("fixed_s", 0.0) + S * (cal.get("per_step_s", 0.0) + f["friction"] * cal.get("per_friction_step_s",
                                                                                                 0.0)
                                           + f["finite"] * cal.get("per_finite_step_s", 0.0))
            + cal.get("per_dof_step_s", 0.0) * f["ndofs"] * S + f["solver_s"])


def machine_kind(cal: dict | None = None) -> str:
    """``"<cpu>, <n> cores"`` of the calibration machine, and whether this machine is of that kind."""
    cal = time_calibration() if cal is None else cal
    m = cal.get("machine") or {}
    if not m:
        return "uncalibrated"
    here = this_machine()
    same = (here.get("cpu"), here.get("cores")) == (m.get("cpu"), m.get("cores"))
    kind = f"{m.get('cpu')}, {m.get('cores')} cores"
    return f"this machine kind ({kind})" if same else f"{kind}; this machine differs, scale accordingly"


def this_machine() -> dict:
    """CPU model and core count of this machine: the "machine kind" a time calibration holds for.

    ``benchmarks/time_estimates.py`` records it with the calibration and :func:`machine_kind`
    compares it with the running machine, so both read it here.
    """
    import platform

    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu or platform.processor() or platform.machine(), "cores": os.cpu_count() or 1}


# --------------------------------------------------------------------------- entry point
@dataclasses.dataclass(frozen=True)
class Preflight:
    """Outcome of :func:`check_problem`.

    Attributes
    ----------
    setup : ProblemSetup
        The built problem, ready for :func:`alcontact.runner.run_setup`.
    size : SizeEstimate
        Exact counts of the built mesh and the estimated memory/time.
    memory : float
        The machine memory (bytes) the size was checked against.
    """

    setup: Any
    size: SizeEstimate
    memory: float

    @property
    def run_seconds(self) -> float:
        """Estimated wall time of ``alcontact run`` of this file (:func:`run_seconds`)."""
        return run_seconds(self.setup, self.size)

    def summary_lines(self) -> list[str]:
        return [self.setup.summary_line(),
                f"size: {self.size.describe()} (machine memory {_gib(self.memory)})",
                f"run time: {_duration(self.run_seconds)} for `alcontact run` (solve and result files), "
                f"calibrated on {machine_kind()}"]


def check_problem(path: str | os.PathLike, *, memory: float | None = None) -> Preflight:
    """Everything ``alcontact run`` would reject, found before solving.

    Parameters
    ----------
    path : path-like
        The TOML problem file.
    memory : float, optional
        Memory in bytes to check the size against (default: this machine's
        total memory, :func:`machine_memory`).

    Returns
    -------
    Preflight

    Raises
    ------
    ConfigError
        With every problem found (``exc.issues``: key path and message).
    """
    p = Path(path)
    label = str(p)
    text = _text_of(p)
    total = machine_memory()[0] if memory is None else float(memory)
    data, issues = validate_data(parse_toml(text, label))
    if issues:  # load_problem reports them all, with its wording
        load_problem(p)
        raise AssertionError("load_problem accepted a file with schema issues")  # pragma: no cover
    est = estimate_size(data, p.parent)
    if est is not None:
        logger.info("size estimate before meshing: %s", est.describe())
        _check(size_issues(est, total), label)
    try:
        setup = load_problem(p)
    except ConfigError as exc:
        issues = [_mesh_issue(data.get("mesh") or {}, p.parent, i) for i in getattr(exc, "issues", [])]
        if issues:
            _raise(issues, label)
        raise
    size = exact_size(setup)
    issues = size_issues(size, total) + setup_issues(setup) + _output_issues(setup)
    _check(issues, label)
    return Preflight(setup=setup, size=size, memory=total)


def _output_issues(setup) -> list[Issue]:
    """``[output] folder`` names no folder this system can make (too long a name, a NUL): ``run`` would fail."""
    from .results import output_path_issue

    folder = str(setup.output.get("folder") or "")
    why = output_path_issue(folder) if folder else None
    if why is None:
        return []
    shown = folder if len(folder) <= 60 else folder[:30] + "..." + folder[-15:]
    return [Issue("output.folder", f"= {shown!r}: {why}.")]


def _mesh_issue(md: dict, base: Path, issue: Issue) -> Issue:
    """Rewrite the mesh issues of :func:`load_problem` for the user: the key that fixes them."""
    if md.get("generator") == "file" and issue.path == "mesh" and issue.message.startswith("the mesh is"):
        return low_dim_issue(md, base, issue)
    if issue.path == "mesh.order" and any(w in issue.message for w in (
            "inverted element", "degenerate element", "second-order element")):  # the quality check of the body
        if md.get("generator") == "file":
            return Issue("mesh.file", f"= {md.get('file')!r}: {issue.message}")
        return Issue("mesh", issue.message)
    return issue


def _check(issues: list[Issue], label: str) -> None:
    if issues:
        _raise(issues, label)
