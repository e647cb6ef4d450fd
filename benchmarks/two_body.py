"""Two-body (mortar) contact: cost of a contact solve in linear solves, accuracy, action = reaction, search cost.

**2D.** For the two elastic cylinders of :func:`alcontact.problems.two_body.hertz_cylinders` at several
refinement levels, and each algorithm (``ssn``, ``simo-laursen`` = Algorithm 6.1, ``exp-met1``
= Algorithm 6.3), measured in one run on one machine:

- the contact solve's CPU seconds over those of one linear solve of the same two-body system
  (factorization and solve of the block-diagonal stiffness with the supports, the same direct
  solver), the best of ``reps`` runs; the same ratio for the rigid-obstacle Hertz problem of the
  same level (:func:`alcontact.problems.hertz.hertz_2d`) as the reference of one body;
- linear solves, outer and Newton iterations (machine independent);
- half-width and peak pressure against Hertz with the effective modulus and radius, and
  ``contact_force_balance`` = |F_slave + F_master| / |F_slave|;
- the mortar setup (candidate search with a cKDTree and the segment integrals) in CPU seconds,
  per slave segment, to show its O(n log n) growth.

**3D** (``--3d``). The elastic sphere on an elastic block of
:func:`alcontact.problems.two_body_3d.sphere_on_block` (P1 tetrahedra, non-matching meshes)
at the sizes asked (``n_per_a:growth`` pairs), each in its own subprocess (a clean resident-set
peak), on the factorization-free path (``linear_solver="amg"``): the contact solve's wall time
less the stiffness assembly over one linear solve of the same two-body system measured inside
the solve (AMG setup of ``K`` plus one CG solve, ``timings["linear_solve_s"]``), as
``benchmarks/hertz_3d_large.py`` does for one body; the process peak memory
(``ru_maxrss``); the contact search (:func:`~alcontact.contact.kinematics._mortar3d.face_pairs`)
and the face integrals in CPU seconds, against the time of one Newton iteration of the same
solve (its solve phase over its Newton iterations). ``--search`` times the search alone on
flat and paraboloid face grids of 3k to 0.8M triangles (its :math:`O(n \\log n)` growth).

Usage::

    OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 python benchmarks/two_body.py [out_dir] [levels] [reps] [--growth G]
    # e.g. python benchmarks/two_body.py docs/benchmarks 1,2,3,4 2
    python benchmarks/two_body.py docs/benchmarks --3d 4:1.3 8:1.3 20:1.1 --variants ssn
    python benchmarks/two_body.py docs/benchmarks --search

Writes ``two_body.csv`` / ``.json`` (2D), ``two_body_3d.json`` / ``.csv`` (3D),
``two_body_search.json`` (search) and ``two_body.md`` (every part found in ``out_dir``).
"""

from __future__ import annotations

import csv
import json
import platform
import sys
import time
from pathlib import Path

from alcontact.contact import solve
from alcontact.contact.kinematics._mortar import mortar_gap
from alcontact.problems import hertz, two_body

ALGORITHMS = (("ssn", None), ("simo-laursen", None), ("family-p", "exp-met1"))


def _linear_solve_cpu(prob, reps: int) -> float:
    """Best CPU seconds of factorizing the stiffness with the supports and solving once (no Schur block)."""
    m = prob.model
    m.stiffness()
    fixed, vals = prob.dirichlet()
    f = prob.load_vector()
    best = float("inf")
    for _ in range(reps + 1):  # the first run loads the solver library
        m.clear_factorization()
        c = time.process_time()
        m.factorize(fixed, reuse=False).solve_full(f, vals)
        best = min(best, time.process_time() - c)
    m.clear_factorization()
    return best


def _contact_cpu(prob, algorithm, penalty, reps: int):
    best, sol = float("inf"), None
    for _ in range(reps):
        prob.model.clear_factorization()
        c = time.process_time()
        sol = solve(prob, algorithm, penalty)
        best = min(best, time.process_time() - c)
    return best, sol


def _merge(path: Path, rows: list[dict], key) -> list[dict]:
    """``rows`` with the rows of an earlier run in ``path`` whose ``key`` was not measured again (kept as they were)."""
    old = json.loads(path.read_text())["rows"] if path.is_file() else []
    new = {key(r) for r in rows}
    return [r for r in old if key(r) not in new] + rows


def _write(out: Path, stem: str, rows: list[dict]) -> None:
    fields = list(dict.fromkeys(k for r in rows for k in r))
    with open(out / f"{stem}.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    (out / f"{stem}.json").write_text(json.dumps({"machine": platform.platform(), "rows": rows}, indent=1))


def run(out_dir, levels=(1, 2, 3, 4), reps: int = 2, growth: float = 1.15) -> list[dict]:
    """The 2D two-cylinder rows (module doc) at ``levels`` with the grading ``growth``; merged into ``two_body.json``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for level in levels:
        prob = two_body.hertz_cylinders(level, growth=growth)
        rigid = hertz.hertz_2d(level, growth=growth)
        lin = _linear_solve_cpu(prob, reps)
        lin_rigid = _linear_solve_cpu(rigid, reps)
        pair = prob.pairs[0]
        c = time.process_time()
        mg = mortar_gap(prob.model, pair.slave.body, pair.slave.name, pair.master)
        search = time.process_time() - c
        nseg = int(pair.slave.body.facets(pair.slave.name).size)
        for algorithm, penalty in ALGORITHMS:
            cpu, sol = _contact_cpu(prob, algorithm, penalty, reps)
            cpu_r, sol_r = _contact_cpu(rigid, algorithm, penalty, reps)
            ref = prob.reference
            P = ref.load(sol.normal_force)
            a_ex, p0_ex = ref.half_width(P), ref.peak_pressure(P)
            a = sol.contact_half_width(axis=0, center=prob.meta["center"])
            rows.append({
                "level": level, "growth": growth, "dofs": int(prob.model.ndofs), "algorithm": algorithm,
                "penalty": penalty or "", "status": sol.result.status.label, "outer": sol.result.outer_iterations,
                "newton": sol.result.newton_iterations, "linear_solves": sol.result.linear_solves,
                "linear_solve_cpu_s": round(lin, 4), "contact_cpu_s": round(cpu, 4),
                "ratio_contact_to_linear": round(cpu / lin, 3),
                "rigid_dofs": int(rigid.model.ndofs), "rigid_linear_solves": sol_r.result.linear_solves,
                "rigid_ratio_contact_to_linear": round(cpu_r / lin_rigid, 3),
                "a_err_pct": round(100 * (a / a_ex - 1), 3),
                "p0_err_pct": round(100 * (sol.peak_pressure_nodal_max / p0_ex - 1), 3),
                "contact_force_balance": sol.extra["contact_force_balance"],
                "slave_segments": nseg, "candidates": int(sol.extra["candidates"]),
                "mortar_setup_cpu_s": round(search, 4),
                "mortar_setup_us_per_segment": round(1e6 * search / nseg, 2),
                "covered_slave_nodes": int(mg.covered.sum()),
                "load": _load(),
            })
            print(rows[-1], flush=True)
    rows = _merge(out / "two_body.json", rows, lambda r: (r["level"], r.get("growth", 1.15), r["algorithm"]))
    _write(out, "two_body", rows)
    _report(out)
    return rows


def _load() -> str:
    """The machine's load averages (1, 5, 15 min), for the reader of noisy timings."""
    try:
        import os

        return " ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return ""


# ------------------------------------------------------------------------------------------------ 3D
VARIANTS_3D = {"ssn": ("ssn", None), "simo-laursen": ("simo-laursen", None), "exp-met1": ("family-p", "exp-met1")}


def _peak_gb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e9  # Linux: kilobytes


def one_size_3d(n_per_a: float, growth: float, variants: list[str]) -> dict:
    """Build and solve one 3D size in this process (module doc); prints ``RECORD {json}`` after each stage."""
    from alcontact.contact.kinematics._mortar3d import default_search, face_pairs, mortar_gap_3d
    from alcontact.contact.masters._faces import boundary_faces
    from alcontact.problems import two_body_3d

    rec: dict = {"n_per_a": n_per_a, "growth": growth, "load_start": _load(), "variants": []}
    t0 = time.perf_counter()
    prob = two_body_3d.sphere_on_block(n_per_a=n_per_a, growth=growth)
    rec["dofs"] = int(prob.model.ndofs)
    rec["mesh_s"] = round(time.perf_counter() - t0, 2)
    pair = prob.pairs[0]
    ss, ms = boundary_faces(pair.slave.body, pair.slave.name), pair.master.faces
    rec["slave_faces"], rec["master_faces"] = int(ss.nodes.shape[0]), int(ms.nodes.shape[0])

    c, w = time.process_time(), time.perf_counter()
    s_idx, _ = face_pairs(ss, ms, default_search(ss, ms))
    rec["search_cpu_s"] = round(time.process_time() - c, 4)
    rec["search_wall_s"] = round(time.perf_counter() - w, 4)  # the clock of the solve's timings
    rec["face_pairs"] = int(s_idx.size)
    c = time.process_time()
    mortar_gap_3d(prob.model, pair.slave.body, pair.slave.name, pair.master)
    rec["mortar_setup_cpu_s"] = round(time.process_time() - c, 4)  # search + integrals + gap operator
    print(f"{rec['dofs']} DOFs, {rec['slave_faces']} / {rec['master_faces']} faces, search "
          f"{rec['search_cpu_s']} s, mortar setup {rec['mortar_setup_cpu_s']} s", file=sys.stderr, flush=True)
    c = time.process_time()
    prob.model.stiffness()  # assembled once here: the solves then time no assembly (their CPU ratio)
    rec["assembly_cpu_s"] = round(time.process_time() - c, 2)
    print("RECORD " + json.dumps(rec), flush=True)
    ref = prob.reference
    for label in variants:
        alg, pen = VARIANTS_3D[label]
        c = time.process_time()
        sol = solve(prob, alg, pen, linear_solver="amg")
        cpu = time.process_time() - c
        r, t = sol.result, sol.timings
        P = ref.load(sol.normal_force)
        newton_s = t["solve_s"] / max(r.newton_iterations, 1)
        newton_cpu = cpu * t["solve_s"] / t["total_s"] / max(r.newton_iterations, 1)  # the solve phase's share
        row = {"variant": label, "status": r.status.label, "outer": r.outer_iterations, "newton": r.newton_iterations,
               "linear_solves": r.linear_solves, "cg_iterations": sol.extra.get("cg_iterations"),
               "reference_cg_iterations": sol.extra.get("reference_cg_iterations"),
               "amg_setups": sol.extra.get("amg_setups"), "amg_updates": sol.extra.get("amg_updates"),
               "wall_s": round(t["total_s"], 2), "cpu_s": round(cpu, 2), "assembly_s": round(t.get("assembly_s", 0), 2),
               "linear_solve_s": round(t["linear_solve_s"], 3),
               "ratio": round((t["total_s"] - t.get("assembly_s", 0.0)) / t["linear_solve_s"], 3),
               "linear_solve_cpu_s": round(t["linear_solve_cpu_s"], 3),
               "cpu_ratio": round(cpu / t["linear_solve_cpu_s"], 3),
               "newton_iteration_s": round(newton_s, 3),
               "search_over_newton_iteration": round(rec["search_cpu_s"] / newton_cpu, 5),
               "newton_iteration_cpu_s": round(newton_cpu, 3),
               "a_err_pct": round(100 * (sol.contact_half_width(center=(0.0, 0.0, 0.0)) / ref.half_width(P) - 1), 3),
               "p0_err_pct": round(100 * (sol.peak_pressure_nodal_max / ref.peak_pressure(P) - 1), 3),
               "contact_force_balance": sol.extra["contact_force_balance"],
               "peak_gb": round(_peak_gb(), 3), "load": _load()}
        rec["variants"].append(row)
        print(f"  {label}: {row}", file=sys.stderr, flush=True)
        del sol
        print("RECORD " + json.dumps(rec), flush=True)
    rec["peak_gb"] = round(_peak_gb(), 3)
    print("RECORD " + json.dumps(rec), flush=True)
    return rec


def run_3d(out_dir, sizes: list[tuple[float, float]], variants: list[str]) -> list[dict]:
    """Each ``(n_per_a, growth)`` in its own subprocess; rows merged into ``two_body_3d.json``."""
    import subprocess

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for n, g in sizes:
        cmd = [sys.executable, __file__, "--worker-3d", f"{n}:{g}", "--variants", *variants]
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, text=True)  # progress on stderr
        recs = [ln for ln in proc.stdout.splitlines() if ln.startswith("RECORD ")]
        if not recs:
            print(f"{n}:{g}: failed, exit status {proc.returncode}", flush=True)
            continue
        rec = json.loads(recs[-1][len("RECORD "):])
        base = {k: v for k, v in rec.items() if k != "variants"}
        if proc.returncode != 0:
            base["error"] = f"exit status {proc.returncode} after {len(rec['variants'])} variants"
        rows += [{**base, **v} for v in rec["variants"]] or [base]
    rows = _merge(out / "two_body_3d.json", rows, lambda r: (r["n_per_a"], r["growth"], r.get("variant")))
    _write(out, "two_body_3d", rows)
    _report(out)
    return rows


def _grid_faces(n: int, z, outward_up: bool):
    """:class:`~alcontact.contact.masters._faces.Faces` of an ``n`` x ``n`` grid of ``[0, 1]^2`` lifted to ``z(x, y)``."""
    import numpy as np

    from alcontact.contact.masters._faces import Faces

    x = np.linspace(0.0, 1.0, n + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    pts = np.column_stack([X.ravel(), Y.ravel(), z(X.ravel(), Y.ravel())])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    quads = np.column_stack([a, a + n + 1, a + n + 2, a + 1])
    tri = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    if not outward_up:
        tri = tri[:, [0, 2, 1]]
    e1, e2 = pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]]
    cr = np.cross(e1, e2)
    dbl = np.linalg.norm(cr, axis=1)
    return Faces(pts, np.zeros((pts.shape[0], 3), dtype=np.int64), tri, cr / dbl[:, None], 0.5 * dbl)


def run_search(out_dir, sizes=(32, 64, 128, 256, 512)) -> list[dict]:
    """The 3D candidate search alone on face grids (module doc): a paraboloid slave over a flat master of 3/4 its cells."""
    from alcontact.contact.kinematics._mortar3d import face_pairs, pair_integrals

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for n in sizes:
        slave = _grid_faces(n, lambda x, y: 0.5 * (x * x + y * y), outward_up=False)
        master = _grid_faces(max(1, int(0.75 * n)), lambda x, y: 0.0 * x, outward_up=True)
        best = float("inf")
        for _ in range(2):
            c = time.process_time()
            s_idx, m_idx = face_pairs(slave, master, 0.25)
            best = min(best, time.process_time() - c)
        c = time.process_time()
        pair_integrals(slave, master, s_idx, m_idx)
        integ = time.process_time() - c
        nf = int(slave.nodes.shape[0] + master.nodes.shape[0])
        rows.append({"slave_faces": int(slave.nodes.shape[0]), "master_faces": int(master.nodes.shape[0]),
                     "faces": nf, "pairs": int(s_idx.size), "search_cpu_s": round(best, 4),
                     "search_us_per_face": round(1e6 * best / nf, 3), "integrals_cpu_s": round(integ, 4),
                     "load": _load()})
        print(rows[-1], flush=True)
    (out / "two_body_search.json").write_text(json.dumps({"machine": platform.platform(), "rows": rows}, indent=1))
    _report(out)
    return rows


# ------------------------------------------------------------------------------------------------ report
def _rows(out: Path, stem: str) -> list[dict]:
    path = out / f"{stem}.json"
    return json.loads(path.read_text())["rows"] if path.is_file() else []


def _report(out: Path) -> None:
    """``two_body.md`` from every part found in ``out`` (2D, 3D, search)."""
    lines = ["# Two-body (mortar) contact: two elastic cylinders (2D), an elastic sphere on a block (3D)", ""]
    rows = _rows(out, "two_body")
    if rows:
        lines += _report_2d(rows)
    rows3 = _rows(out, "two_body_3d")
    if rows3:
        lines += _report_3d(rows3)
    search = _rows(out, "two_body_search")
    if search:
        lines += _report_search(search)
    (out / "two_body.md").write_text("\n".join(lines) + "\n")


def _report_2d(rows: list[dict]) -> list[str]:
    lines = [
        "## 2D: two elastic cylinders",
        "",
        "`benchmarks/two_body.py`: `problems.two_body.hertz_cylinders` (E = 200e3 / 70e3, nu = 0.3 / 0.35,",
        "R1 = R2 = 20, plane strain, half model, non-matching meshes: the master has 3/4 of the slave's",
        "elements per a; `growth` the grading away from the contact), every algorithm, measured in one run",
        "per row on one machine (`load`: its load averages then, 2 cores). Ratios are CPU seconds of the",
        "contact solve over one linear solve (factorization + solve) of the same system and solver, measured",
        "in the same run; the rigid columns are the rigid-cylinder Hertz problem of the same mesh (`hertz_2d`),",
        "one body. Linear solves and iterations are machine independent. Rows without a load were measured",
        "by an earlier run of this script (kept when a run measures other rows).",
        "",
        "| level | growth | DOFs | algorithm | status | outer / Newton | linear solves | ratio | rigid: solves / ratio "
        "| a err % | p0 err % | force balance | mortar setup (us/segment) | load |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in sorted(rows, key=lambda r: (r["dofs"], r["algorithm"])):
        alg = r["algorithm"] + (f"/{r['penalty']}" if r["penalty"] else "")
        lines.append(f"| {r['level']} | {r.get('growth', 1.15)} | {r['dofs']} | {alg} | {r['status']} | "
                     f"{r['outer']} / {r['newton']} | {r['linear_solves']} | {r['ratio_contact_to_linear']} | "
                     f"{r['rigid_linear_solves']} / {r['rigid_ratio_contact_to_linear']} | {r['a_err_pct']} | "
                     f"{r['p0_err_pct']} | {r['contact_force_balance']:.1e} | {r['mortar_setup_us_per_segment']} | "
                     f"{r.get('load', '')} |")
    big = [r for r in rows if r["dofs"] >= 10_000]
    if big:
        worst = max(big, key=lambda r: r["ratio_contact_to_linear"])
        top = max(r["dofs"] for r in rows)
        at_top = [r for r in rows if r["dofs"] == top]
        lines += ["", "Reading: at 10k DOFs and more (a Schur block of the mortar rows' slave and master DOFs) a "
                  f"two-body contact solve takes at most {max(r['linear_solves'] for r in big)} linear solves and "
                  f"{worst['ratio_contact_to_linear']} times the CPU time of one linear solve of the same system "
                  f"({worst['algorithm']} at {worst['dofs']} DOFs; target <= 2); at the largest size, {top} DOFs: "
                  + ", ".join(f"{r['algorithm']} {r['ratio_contact_to_linear']}" for r in at_top)
                  + f". The rigid-obstacle problem of the same meshes takes "
                  f"{max(r['rigid_ratio_contact_to_linear'] for r in big)} at most. Below 10k DOFs "
                  "the condensed operator is built column by column (one solve per candidate), for one body as for "
                  "two. The mortar setup (cKDTree search and segment integrals) costs "
                  f"{min(r['mortar_setup_us_per_segment'] for r in rows)}-"
                  f"{max(r['mortar_setup_us_per_segment'] for r in rows)} us per slave segment at every size, and the "
                  f"forces on the two bodies balance to {max(r['contact_force_balance'] for r in rows):.0e}.", ""]
    return lines


def _report_3d(rows: list[dict]) -> list[str]:
    lines = [
        "## 3D: an elastic sphere on an elastic block, factorization-free path",
        "",
        "`benchmarks/two_body.py --3d`: `problems.two_body_3d.sphere_on_block(n_per_a=..., growth=...)`",
        "(sphere E 70e3, nu 0.35, R 10 on a block E 200e3, nu 0.3, quarter model, P1 tetrahedra, the block",
        "with 3/4 of the sphere's elements per a), `linear_solver=\"amg\"`, each size in its own process, the",
        "stiffness assembled before the solves. One linear solve = AMG setup of the two-body `K` plus one CG",
        "solve to 1e-10, measured inside each contact solve. `ratio` = contact solve / one linear solve, in CPU",
        "seconds (robust to the load of the shared machine; the wall-time ratio beside it is not: at load 20",
        "on 2 cores the same reference solve took 76-189 s of wall time). `search` = CPU seconds of the",
        "candidate search (cKDTree, once per solve at small deformation), over the CPU time of one Newton",
        "iteration (the solve phase's share of the solve's CPU time over its Newton iterations). a: load-matched",
        "fit of the pressure field; p0: the nodal maximum; peak: the process's resident peak after the solve.",
        "",
        "| n per a / growth | DOFs | slave / master faces | variant | status | outer / Newton | CG (AMG setups) | "
        "CG of one linear solve | one linear solve CPU (s) | ratio (CPU) | ratio (wall) | search CPU (s) | "
        "search / Newton iteration | mortar setup CPU (s) | a err % | p0 err % | balance | peak GB | load |",
        "|" + "---|" * 19,
    ]
    for r in sorted(rows, key=lambda r: (r["dofs"], r.get("variant", ""))):
        head = f"| {r['n_per_a']} / {r['growth']} | {r['dofs']} | {r['slave_faces']} / {r['master_faces']} | "
        if "variant" not in r:
            lines.append(head + f"- | {r.get('error', 'not solved')} | | | | | | | {r['search_cpu_s']} | | "
                         f"{r['mortar_setup_cpu_s']} | | | | | {r.get('load_start', '')} |")
            continue
        lines.append(head + f"{r['variant']} | {r['status']} | {r['outer']} / {r['newton']} | {r['cg_iterations']} "
                     f"({r['amg_setups']}) | {r.get('reference_cg_iterations', '')} | {r.get('linear_solve_cpu_s', '')} | "
                     f"{r.get('cpu_ratio', '')} | {r['ratio']} | {r['search_cpu_s']} | "
                     f"{r['search_over_newton_iteration']:.2%} | {r['mortar_setup_cpu_s']} | {r['a_err_pct']} | "
                     f"{r['p0_err_pct']} | {r['contact_force_balance']:.1e} | {r['peak_gb']} | {r['load']} |")
    solved = [r for r in rows if "variant" in r and "cpu_ratio" in r]
    if solved:
        top = max(r["dofs"] for r in solved)
        at = [r for r in solved if r["dofs"] == top]
        lines += ["", f"Reading: the largest size solved, {top} DOFs: "
                  + "; ".join(f"{r['variant']} {r['status']} in {r['cpu_ratio']} linear-solve equivalents (CPU), peak "
                              f"{r['peak_gb']} GB, search {r['search_over_newton_iteration']:.2%} of a Newton iteration"
                              for r in at)
                  + " (targets at 1M DOFs: <= 4, within 8 GB, <= 5 %).", ""]
    return lines


def _report_search(rows: list[dict]) -> list[str]:
    import math

    lines = ["## 3D contact search alone", "",
             "`benchmarks/two_body.py --search`: `kinematics._mortar3d.face_pairs` on a paraboloid slave grid",
             "(z = (x^2 + y^2)/2) over a flat master grid with 3/4 of its cells, search distance 0.25, best CPU",
             "time of two runs; the face integrals of the pairs found for comparison.", "",
             "| faces (slave + master) | pairs | search CPU (s) | us per face | integrals CPU (s) | load |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['faces']} | {r['pairs']} | {r['search_cpu_s']} | {r['search_us_per_face']} | "
                     f"{r['integrals_cpu_s']} | {r['load']} |")
    if len(rows) >= 2:
        a, b = rows[0], rows[-1]
        slope = math.log(b["search_cpu_s"] / a["search_cpu_s"]) / math.log(b["faces"] / a["faces"])
        lines += ["", f"Reading: from {a['faces']} to {b['faces']} faces the search time grows as faces^{slope:.2f} "
                  f"(n log n over that range: ^{1 + math.log(math.log(b['faces']) / math.log(a['faces'])) / math.log(b['faces'] / a['faces']):.2f}); "
                  f"{a['search_us_per_face']} -> {b['search_us_per_face']} us per face.", ""]
    return lines


def main(argv=None) -> int:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default="docs/benchmarks")
    ap.add_argument("levels", nargs="?", default=None, help="2D levels, e.g. 1,2,3,4")
    ap.add_argument("reps", nargs="?", type=int, default=2)
    ap.add_argument("--growth", type=float, default=1.15, help="2D grading (1.06: about 200k DOFs at level 4)")
    ap.add_argument("--3d", dest="sizes", nargs="*", default=None, help="3D sizes n_per_a:growth, e.g. 20:1.1")
    ap.add_argument("--variants", nargs="*", default=["ssn", "simo-laursen", "exp-met1"], choices=list(VARIANTS_3D))
    ap.add_argument("--search", action="store_true", help="time the 3D search alone on face grids")
    ap.add_argument("--worker-3d", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker_3d is not None:
        n, g = (float(x) for x in args.worker_3d.split(":"))
        one_size_3d(n, g, args.variants)
        return 0
    if args.search:
        run_search(args.out)
    if args.sizes:
        run_3d(args.out, [tuple(float(x) for x in s.split(":")) for s in args.sizes], args.variants)
    if args.levels is not None or not (args.search or args.sizes):
        levels = tuple(int(x) for x in args.levels.split(",")) if args.levels else (1, 2, 3, 4)
        run(args.out, levels, args.reps, args.growth)
    return 0


if __name__ == "__main__":
    sys.exit(main())
