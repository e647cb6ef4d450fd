"""PETSc KSP + GAMG on 1 and 2 MPI ranks against the serial PyAMG solver: 3D linear elasticity.

The problem: a bar ``[0, 4] x [0, 1] x [0, 1]`` of P1 tetrahedra (``alcontact.fem.meshes.box``),
clamped at ``x = 0``, under a body force; E = 200, nu = 0.3. Each size is solved

* serially: ``alcontact.linalg.make_solver("amg")`` (PyAMG smoothed aggregation with the
  rigid-body modes + CG) on the condensed stiffness, the path ``"auto"`` takes above 250k DOFs;
* distributed: :class:`alcontact.distributed.DistributedElasticity` (METIS partition, per-rank
  scikit-fem assembly, ``MPIAIJ`` with COO preallocation, CG + GAMG with the rigid-body
  near-null space) under ``mpirun -n 1`` and ``mpirun -n 2``.

All to the relative residual 1e-8 (the true residual for both). Each run is its own process,
so its peak resident memory (``ru_maxrss``, per rank) is its own. The displacement of every
run is compared with the serial one (max-norm, relative to max|u|).

Usage::

    make mpi
    .venv-mpi/bin/python benchmarks/distributed.py --out benchmarks/out --sizes 6,12,20

writes ``distributed.csv``, ``distributed.json`` and ``distributed.md`` (copy the report to
``docs/benchmarks/distributed.md``).

With ``--contact`` (sizes: elements per contact half-width ``a`` of :func:`alcontact.problems.hertz.hertz_3d`,
e.g. ``--sizes 2,3``) it measures the distributed contact solve instead: 3D Hertz, Algorithm 6.1
(``simo-laursen``), serially with the factorization-free Krylov path (``linear_solver = "amg"``,
PyAMG + CG) and with :func:`alcontact.contact.solve_distributed` (CG + GAMG, ``"petsc"``) under
``mpirun -n 1`` and ``-n 2``: outer and Newton iterations, linear solves and Krylov iterations,
solve time, peak memory per rank, and the contact force against the serial one; written to
``distributed_contact.csv``, ``.json`` and ``.md``. ``--dofs 1M 4M 8M`` picks the meshes by size
(the graded block of ``benchmarks/hertz_3d_large.py``, growth 1.04); sizes above ``--max-serial`` /
``--max-one-rank`` (default 4M) run on 2 ranks only. The quiet-machine command of
``docs/benchmarks/distributed.md``::

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 .venv-mpi/bin/python benchmarks/distributed.py --contact \
        --dofs 1M 4M 8M --ranks 1,2 --out benchmarks/out --timeout 14400

``--model benchmarks/out/distributed_contact.json`` then writes the weak-scaling projection
(``distributed_model.md`` / ``.json``) from the measured per-rank constants.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

RTOL = 1e-8
E, NU = 200.0, 0.3
FORCE = [0.0, 0.3, -1.0]


def _mesh(k: int):
    from alcontact.fem import meshes

    return meshes.box(0, 4, 0, 1, 0, 1, 4 * k, k, k)


def _clamped(x):
    return x[0] < 1e-12


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def worker_serial(k: int, out: Path) -> None:
    from alcontact import linalg
    from alcontact.fem import LinearElasticity, Material

    t0 = time.perf_counter()
    model = LinearElasticity(_mesh(k), Material(E=E, nu=NU))
    K = model.stiffness()
    f = model.body_load(FORCE)
    pts, dmap = model.all_node_dofs()
    fixed = dmap[_clamped(pts.T)].ravel()
    free = np.setdiff1d(np.arange(model.ndofs), fixed)
    Kf = K[free][:, free].tocsr()
    t1 = time.perf_counter()
    fac = linalg.make_solver("amg", rtol=RTOL).factorize(Kf, linalg.MatrixHints(
        dim=3, near_null=lambda: model._free_rigid_modes(free)))
    t2 = time.perf_counter()
    u = np.zeros(model.ndofs)
    u[free] = fac.solve(f[free])
    t3 = time.perf_counter()
    np.save(out.with_suffix(".npy"), u[dmap])
    out.write_text(json.dumps({"path": "serial pyamg", "ranks": 1, "ndofs": int(model.ndofs),
                               "assemble_s": t1 - t0, "setup_s": t2 - t1, "solve_s": t3 - t2,
                               "iterations": int(fac.iterations), "peak_mb_per_rank": _peak_mb()}))


def worker_petsc(k: int, out: Path) -> None:
    from alcontact.distributed import DistributedElasticity, run_ranks, world
    from alcontact.fem import Material

    def main():
        comm = world()
        t0 = time.perf_counter()
        mesh = _mesh(k) if comm.rank == 0 else None
        model = DistributedElasticity(mesh, Material(E=E, nu=NU), comm=comm)
        sol = model.solve(FORCE, _clamped, rtol=RTOL)
        wall = time.perf_counter() - t0
        u, _ = model.gather(sol)
        peaks = comm.gather(_peak_mb(), root=0)
        secs = comm.gather(sol.seconds, root=0)
        if comm.rank == 0:
            np.save(out.with_suffix(".npy"), u[model.numbering])
            s = {key: max(d.get(key, 0.0) for d in secs) for key in ("distribute", "assemble", "setup", "solve")}
            out.write_text(json.dumps({"path": "petsc gamg", "ranks": comm.size, "ndofs": int(u.size),
                                       "distribute_s": s["distribute"], "assemble_s": s["assemble"],
                                       "setup_s": s["setup"], "solve_s": s["solve"], "wall_s": wall,
                                       "iterations": sol.iterations, "peak_mb_per_rank": max(peaks),
                                       "peak_mb_ranks": peaks}))

    run_ranks(main)


GROWTH = 1.04  # the graded quarter block of benchmarks/hertz_3d_large.py (nearly uniform near the contact zone)


def _hertz(n: float, growth: float):
    from alcontact.problems import hertz

    return hertz.hertz_3d(n_per_a=n, growth=growth)


def _cpu_s() -> float:
    return time.process_time()


def worker_contact_serial(n: float, growth: float, out: Path) -> None:
    from alcontact.contact import solve

    t0 = time.perf_counter()
    problem = _hertz(n, growth)
    t1, c1 = time.perf_counter(), _cpu_s()
    sol = solve(problem, "simo-laursen", options={"linear_solver": "amg"})
    t2, c2 = time.perf_counter(), _cpu_s()
    r = sol.result
    out.write_text(json.dumps({"path": "serial amg (pyamg + cg)", "ranks": 1, "ndofs": int(problem.model.ndofs),
                               "status": r.status.label, "outer": r.outer_iterations, "newton": r.newton_iterations,
                               "linear_solves": r.linear_solves, "krylov_iterations": sol.extra.get("cg_iterations"),
                               "setups": sol.extra.get("amg_setups"), "updates": sol.extra.get("amg_updates"),
                               "build_s": t1 - t0, "solve_s": t2 - t1, "solve_cpu_s": c2 - c1,
                               "linear_solve_s": sol.timings.get("linear_solve_s"),
                               "force": float(sol.total_contact_force[-1]), "peak_mb_per_rank": _peak_mb(),
                               "peak_mb_ranks": [_peak_mb()]}))


def worker_contact_petsc(n: float, growth: float, out: Path, petsc_options: dict | None = None) -> None:
    from alcontact.contact import solve_distributed
    from alcontact.distributed import run_ranks, world

    def main():
        comm = world()
        t0 = time.perf_counter()
        comm.Barrier()
        t1, c1 = time.perf_counter(), _cpu_s()
        # the problem is built on rank 0 inside the solve and released there once distributed
        built = {"s": 0.0, "cpu": 0.0}

        def build():
            b0, bc = time.perf_counter(), _cpu_s()
            problem = _hertz(n, growth)
            built["s"], built["cpu"] = time.perf_counter() - b0, _cpu_s() - bc
            return problem

        sol = solve_distributed(build if comm.rank == 0 else None, "simo-laursen",
                                options={"linear_solver": "petsc"}, comm=comm, petsc_options=petsc_options)
        t2, c2 = time.perf_counter(), _cpu_s() - built["cpu"]
        t1 += comm.bcast(built["s"], root=0)  # the solve without building the problem (as the serial row)
        piece = sol.piece
        n_own = piece.node_range[1] - piece.node_range[0]
        mine = {"peak_mb": _peak_mb(), "cpu_s": c2 - c1, "owned_dofs": 3 * n_own,
                "ghost_dofs": 3 * (int(piece.global_nodes.size) - n_own), "elements": int(piece.elements.shape[1]),
                "timings": sol.timings}
        ranks = comm.gather(mine, root=0)
        if comm.rank == 0:
            r = sol.result
            phases = {k: max(x["timings"].get(k, 0.0) for x in ranks) for k in sol.timings}
            out.write_text(json.dumps({
                "path": "distributed (petsc cg + gamg)", "ranks": comm.size, "ndofs": int(sol.extra["dofs"]),
                "status": r.status.label, "outer": r.outer_iterations, "newton": r.newton_iterations,
                "linear_solves": r.linear_solves, "krylov_iterations": sol.extra["ksp_iterations"],
                "setups": sol.extra["gamg_setups"], "updates": sol.extra["gamg_updates"],
                "lagged": sol.extra["pc_lagged"], "lag_failures": sol.extra["lag_failures"],
                "build_s": t1 - t0, "solve_s": t2 - t1,
                "solve_cpu_s": max(x["cpu_s"] for x in ranks),
                "linear_solve_s": phases.get("linear_solve_s"), "phases_s": phases,
                "force": float(sol.total_contact_force[-1]),
                "peak_mb_per_rank": max(x["peak_mb"] for x in ranks), "peak_mb_ranks": [x["peak_mb"] for x in ranks],
                "owned_dofs_ranks": [x["owned_dofs"] for x in ranks],
                "ghost_dofs_ranks": [x["ghost_dofs"] for x in ranks],
                "elements_ranks": [x["elements"] for x in ranks]}))

    run_ranks(main)


def _size(text: str) -> int:
    """``"250k"`` -> 250000, ``"1M"`` -> 1000000."""
    t = text.strip().lower()
    mult = {"k": 10**3, "m": 10**6}.get(t[-1:], 1)
    return int(float(t[:-1] if mult > 1 else t) * mult)


def _n_per_a(dofs: int, growth: float) -> float:
    """Elements per contact radius of the 3D Hertz mesh with at least ``dofs`` DOFs (benchmarks/hertz_3d_large.py)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("hertz_3d_large", Path(__file__).with_name("hertz_3d_large.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.n_per_a_for(dofs, growth)


def contact_main(a, me) -> int:
    """The contact benchmark: every size and path in its own process, one row each; CSV, JSON and Markdown."""
    rows = []
    ranks = [int(r) for r in a.ranks.split(",")]
    sizes = [_size(s) for s in a.dofs] if a.dofs else None
    targets = sizes or [float(s) for s in a.sizes.split(",")]
    env_load = os.getloadavg()
    for target in targets:
        n = _n_per_a(target, a.growth) if sizes else target
        big = sizes is not None and target > _size(a.max_one_rank)
        runs = ([] if a.skip_serial or (sizes is not None and target > _size(a.max_serial)) else
                [("serial", me + ["--worker", "contact-serial"])]) + \
            [(f"petsc{r}", ["mpirun", "-n", str(r), "--oversubscribe"] + me + ["--worker", "contact-petsc"])
             for r in ranks if not (big and r == 1)]
        res = {}
        for tag, cmd in runs:
            f = a.out / f"distributed_contact_{n:g}_{tag}.json"
            t0 = time.perf_counter()
            extra = ["--petsc-options", a.petsc_options] if tag != "serial" else []
            _run(cmd + ["--k", f"{n:g}", "--growth", f"{a.growth:g}", "--file", str(f)] + extra, a.timeout)
            res[tag] = json.loads(f.read_text())
            res[tag]["process_wall_s"] = time.perf_counter() - t0
            res[tag]["load"] = os.getloadavg()[0]
            r = res[tag]
            print(f"n={n:g} {tag}: {r['ndofs']} DOFs, {r['outer']} outer, {r['newton']} Newton, "
                  f"{r['krylov_iterations']} Krylov its, solve {r['solve_s']:.1f} s (cpu {r['solve_cpu_s']:.1f} s), "
                  f"{r['peak_mb_per_rank']:.0f} MB/rank {r['peak_mb_ranks']}", flush=True)
        ref_tag = "serial" if "serial" in res else next(iter(res))
        ref = res[ref_tag]["force"]
        one = res.get("petsc1")
        for tag, r in res.items():
            r["n_per_a"] = n
            r["growth"] = a.growth
            r["rel_diff_force"] = abs(r["force"] - ref) / abs(ref)
            r["peak_ratio_to_1rank"] = r["peak_mb_per_rank"] / one["peak_mb_per_rank"] if one else None
            r["peak_gb_total"] = sum(r["peak_mb_ranks"]) / 1024
            r["speedup_to_1rank"] = one["solve_s"] / r["solve_s"] if one else None
            rows.append(r)
    meta = {"machine": platform.platform(), "cpus": os.cpu_count(), "load_at_start": env_load,
            "petsc_options": json.loads(a.petsc_options), "rows": rows}
    return _write_contact(a.out, meta)


def _lagged(row: dict) -> str:
    """`` / lagged (failed)`` of a distributed row that counted them (rows measured before the lag: nothing)."""
    if row.get("lagged") is None:
        return ""
    return f" / {row['lagged']} ({row['lag_failures']})"


def _write_contact(out: Path, meta: dict) -> int:
    """``distributed_contact.csv``, ``.json`` and ``.md`` of the rows of ``meta``."""
    rows = meta["rows"]
    for r in rows:
        r.setdefault("peak_gb_total", sum(r["peak_mb_ranks"]) / 1024)
    keys = ["n_per_a", "ndofs", "path", "ranks", "status", "outer", "newton", "linear_solves", "krylov_iterations",
            "setups", "updates", "lagged", "lag_failures", "build_s", "solve_s", "solve_cpu_s", "linear_solve_s",
            "process_wall_s",
            "peak_mb_per_rank", "peak_gb_total", "peak_ratio_to_1rank", "speedup_to_1rank", "force", "rel_diff_force",
            "load"]
    with open(out / "distributed_contact.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    (out / "distributed_contact.json").write_text(json.dumps(meta, indent=1))
    lines = ["| DOFs | path | ranks | outer | Newton | linear solves | Krylov its | hierarchies built / updated "
             "(/ lagged solves, of which failed) | "
             "solve s | solve CPU s | ratio to serial (wall / CPU) | speed-up to 1 rank | peak MB/rank | "
             "peak / 1-rank peak | peak GB, all ranks | force rel. diff. |", "|" + "---|" * 16]
    for r in rows:
        base = next((x for x in rows if x["n_per_a"] == r["n_per_a"] and "serial" in x["path"]), None)
        ratio = f"{r['solve_s'] / base['solve_s']:.2f} / {r['solve_cpu_s'] / base['solve_cpu_s']:.2f}" if base else "-"
        sp = f"{r['speedup_to_1rank']:.2f}" if r["speedup_to_1rank"] and "serial" not in r["path"] else "-"
        pk = f"{r['peak_ratio_to_1rank']:.2f}" if r["peak_ratio_to_1rank"] and "serial" not in r["path"] else "-"
        lines.append(f"| {r['ndofs']:,} | {r['path']} | {r['ranks']} | {r['outer']} | {r['newton']} | "
                     f"{r['linear_solves']} | {r['krylov_iterations']} | {r['setups']} / {r['updates']}"
                     f"{_lagged(r)} | "
                     f"{r['solve_s']:.2f} | {r['solve_cpu_s']:.2f} | {ratio} | {sp} | "
                     f"{', '.join(f'{p:.0f}' for p in r['peak_mb_ranks'])} | {pk} | {r['peak_gb_total']:.2f} | "
                     f"{r['rel_diff_force']:.1e} |")
    (out / "distributed_contact.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


#: machine constants of the model (a commodity InfiniBand cluster; override with --model-net): latency of one
#: small allreduce per log2(P) stage, of one neighbour message, and the bandwidth of one rank's link
NET = {"allreduce_stage_s": 5e-6, "message_s": 2e-6, "bandwidth_Bps": 5e9}
#: halo exchanges per CG + GAMG iteration: CG's matvec, Chebyshev(2) pre- and post-smoothing (4 matvecs) and the
#: residual on the finest level, times 1.4 for the coarser levels (their halos shrink with the grid)
HALOS_PER_ITERATION = 6 * 1.4
#: global reductions per iteration (CG's two dot products) and neighbours of a rank in a 3D partition
ALLREDUCES_PER_ITERATION, NEIGHBOURS = 2, 14
BASELINE_MB = 150.0  # a rank's interpreter, NumPy, scikit-fem, petsc4py and MPI before any problem data


def merge_main(a) -> int:
    """One table from several ``--contact`` runs: their ``distributed_contact.json`` or single-run files
    (``distributed_contact_<n>_<tag>.json``), in the order given; the comparisons (force against the serial row,
    speed-up and peak against the 1-rank row of the same mesh) are recomputed over the merged rows."""
    rows, runs = [], []
    for f in a.merge:
        m = json.loads(Path(f).read_text())
        got = m["rows"] if "rows" in m else [dict(m, n_per_a=float(Path(f).stem.split("_")[2]), growth=a.growth)]
        rows += got
        runs.append({"file": Path(f).name, "load_at_start": m.get("load_at_start"),
                     "petsc_options": m.get("petsc_options"), "dofs": sorted({r["ndofs"] for r in got})})
    rows.sort(key=lambda r: (r["ndofs"], "serial" not in r["path"], r["ranks"]))
    for r in rows:
        same = [x for x in rows if x["ndofs"] == r["ndofs"]]
        ser = next((x for x in same if "serial" in x["path"]), None)
        one = next((x for x in same if "distributed" in x["path"] and x["ranks"] == 1), None)
        ref = (ser or one or r)["force"]
        r["rel_diff_force"] = abs(r["force"] - ref) / abs(ref)
        r["peak_ratio_to_1rank"] = r["peak_mb_per_rank"] / one["peak_mb_per_rank"] if one else None
        r["speedup_to_1rank"] = one["solve_s"] / r["solve_s"] if one else None
    a.out.mkdir(parents=True, exist_ok=True)
    return _write_contact(a.out, {"machine": platform.platform(), "cpus": os.cpu_count(), "runs": runs,
                                  "rows": rows})


def model_main(a) -> int:
    """The weak-scaling model of docs/benchmarks/distributed.md from the rows of a ``--contact`` run."""
    meta = json.loads(Path(a.model).read_text())
    rows = [r for r in meta["rows"] if "distributed" in r["path"]]
    one = [r for r in rows if r["ranks"] == 1]
    two = [r for r in rows if r["ranks"] == 2]
    if not one or not two:
        raise SystemExit("--model needs 1- and 2-rank rows of a --contact run (--ranks 1,2)")
    ref = max(one, key=lambda r: r["ndofs"])
    N1 = ref["ndofs"]
    cpu = ref["solve_cpu_s"]
    wall = ref["solve_s"]
    f = cpu / wall  # the run's wall phases scaled to CPU time (the machine was shared)
    ph = {k: v * f for k, v in ref["phases_s"].items()}
    its = ref["krylov_iterations"]
    newton = ref["newton"]
    c_asm = ph["assembly_s"] / N1  # per DOF: local assembly into the MPIAIJ matrix
    c_gamg = ph["factor_s"] / N1  # per DOF: the one GAMG hierarchy
    # rank 0's serial part of the set-up: partitioning and sending the mesh (measured since ``distribute_s``; before,
    # the set-up less the assembly, the GAMG set-up and the reference solve)
    c_rank0 = (ph["distribute_s"] if "distribute_s" in ph else
               max(ph["setup_s"] - ph["assembly_s"] - ph["factor_s"] - ph["linear_solve_s"], 0.0)) / N1
    c_build = ref["build_s"] * f / N1  # rank 0 builds the whole problem (mesh, model, loads)
    c_it = max(cpu - ph["setup_s"], 1e-12) / (its * N1)  # per Krylov iteration and DOF, updates and Newton included
    # iteration growth from the 1-rank sizes: its = i0 (1 + g log2(N / N0))
    pts = sorted((r["ndofs"], r["krylov_iterations"] / max(r["newton"], 1)) for r in one)
    g = 0.0
    if len(pts) > 1 and pts[-1][0] > pts[0][0]:
        g = max((pts[-1][1] / pts[0][1] - 1.0) / np.log2(pts[-1][0] / pts[0][0]), 0.0)
    # ghost DOFs per rank: kappa n^(2/3) from the 2-rank runs
    r2 = max(two, key=lambda r: r["ndofs"])
    n2 = r2["ndofs"] / 2
    kappa = float(np.mean(r2["ghost_dofs_ranks"])) / n2 ** (2 / 3)
    # memory: the 2-rank rank without the problem (rank 1) gives bytes per owned DOF of the solve; rank 0's extra over
    # rank 1 is the whole problem it built (bytes per DOF of the mesh)
    peaks = r2["peak_mb_ranks"]
    mb_solve = (peaks[-1] - BASELINE_MB) / n2
    mb_build = max(peaks[0] - peaks[-1], 0.0) / r2["ndofs"]
    per_it = its / max(newton, 1)
    net = dict(NET, **json.loads(a.model_net))
    out = []
    for N in (10e6, 100e6, 1e9):
        for P in (8, 64, 512, 1024):
            n = N / P
            if n < 2e4 or n > 2e7:
                continue
            its_N = per_it * (1.0 + g * np.log2(N / N1)) * newton
            halo = HALOS_PER_ITERATION * (NEIGHBOURS * net["message_s"] + 8.0 * kappa * n ** (2 / 3)
                                          / net["bandwidth_Bps"])
            red = ALLREDUCES_PER_ITERATION * net["allreduce_stage_s"] * max(np.log2(P), 1.0)
            t_par = n * (c_asm + c_gamg) + its_N * (c_it * n + halo + red)
            t0 = N * (c_build + c_rank0)
            out.append({"dofs": N, "ranks": P, "dofs_per_rank": n, "krylov_iterations": its_N,
                        "parallel_s": t_par, "comm_share": its_N * (halo + red) / t_par, "rank0_serial_s": t0,
                        "total_s": t_par + t0, "mb_per_rank": BASELINE_MB + mb_solve * n,
                        "rank0_extra_gb": mb_build * N / 1024})
    consts = {"from_dofs": N1, "cpu_over_wall": f, "assembly_s_per_dof": c_asm, "gamg_setup_s_per_dof": c_gamg,
              "rank0_partition_s_per_dof": c_rank0, "rank0_build_s_per_dof": c_build,
              "krylov_iteration_s_per_dof": c_it, "iterations_per_newton": per_it, "iteration_growth": g,
              "newton": newton, "ghost_kappa": kappa, "mb_per_owned_dof": mb_solve, "rank0_mb_per_dof": mb_build,
              "net": net}
    lines = ["| DOFs | ranks | DOFs/rank | Krylov its | parallel part s | of it communication | rank-0 serial "
             "set-up s | total s | MB/rank | rank 0 extra GB |", "|" + "---|" * 10]
    for r in out:
        lines.append(f"| {r['dofs']:.0e} | {r['ranks']} | {r['dofs_per_rank']:,.0f} | {r['krylov_iterations']:.0f} | "
                     f"{r['parallel_s']:.0f} | {100 * r['comm_share']:.0f} % | {r['rank0_serial_s']:.0f} | "
                     f"{r['total_s']:.0f} | {r['mb_per_rank']:.0f} | {r['rank0_extra_gb']:.0f} |")
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "distributed_model.json").write_text(json.dumps({"constants": consts, "rows": out}, indent=1))
    (Path(a.out) / "distributed_model.md").write_text("\n".join(lines) + "\n")
    print(json.dumps(consts, indent=1))
    print("\n".join(lines))
    return 0


def _run(cmd, timeout):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1")
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{proc.stdout}\n{proc.stderr}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("benchmarks/out"))
    ap.add_argument("--sizes", default="6,12,18", help="k: the mesh is 4k x k x k cubes of 6 tetrahedra")
    ap.add_argument("--timeout", type=float, default=900)
    ap.add_argument("--contact", action="store_true", help="the distributed contact solve (3D Hertz; sizes: elements "
                    "per contact half-width, or --dofs)")
    ap.add_argument("--dofs", nargs="*", help="contact: target sizes, e.g. 250k 1M 4M (the mesh with at least that many "
                    "DOFs)")
    ap.add_argument("--ranks", default="1,2", help="contact: MPI rank counts, e.g. 1,2")
    ap.add_argument("--growth", type=float, default=GROWTH, help="contact: mesh grading of hertz_3d")
    ap.add_argument("--skip-serial", action="store_true", help="contact: leave out the serial PyAMG run")
    ap.add_argument("--max-serial", default="4M", help="contact: no serial run above this size (e.g. 4M)")
    ap.add_argument("--max-one-rank", default="4M", help="contact: no 1-rank run above this size (e.g. 4M)")
    ap.add_argument("--petsc-options", default="{}", help="contact: PETSc options of the distributed runs as JSON, "
                    "e.g. '{\"pc_gamg_threshold\": 0.01}'")
    ap.add_argument("--merge", nargs="*", help="contact: write one table (CSV, JSON, Markdown) from these runs' "
                    "distributed_contact.json")
    ap.add_argument("--model", help="the weak-scaling model from a --contact run's distributed_contact.json")
    ap.add_argument("--model-net", default="{}", help="machine constants of the model as JSON (allreduce_stage_s, "
                    "message_s, bandwidth_Bps)")
    ap.add_argument("--worker", choices=["serial", "petsc", "contact-serial", "contact-petsc"], help=argparse.SUPPRESS)
    ap.add_argument("--k", type=float, help=argparse.SUPPRESS)
    ap.add_argument("--file", type=Path, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.model:
        return model_main(a)
    if a.merge:
        return merge_main(a)
    if a.worker == "serial":
        worker_serial(int(a.k), a.file)
        return 0
    if a.worker == "petsc":
        worker_petsc(int(a.k), a.file)
        return 0
    if a.worker == "contact-serial":
        worker_contact_serial(a.k, a.growth, a.file)
        return 0
    if a.worker == "contact-petsc":
        worker_contact_petsc(a.k, a.growth, a.file, json.loads(a.petsc_options))
        return 0
    a.out.mkdir(parents=True, exist_ok=True)
    rows = []
    me = [sys.executable, str(Path(__file__).resolve())]
    if a.contact:
        return contact_main(a, me)
    for k in [int(s) for s in a.sizes.split(",")]:
        runs = [("serial", me + ["--worker", "serial"])] + \
            [(f"petsc{n}", ["mpirun", "-n", str(n), "--oversubscribe"] + me + ["--worker", "petsc"]) for n in (1, 2)]
        res = {}
        for tag, cmd in runs:
            f = a.out / f"distributed_{k}_{tag}.json"
            t0 = time.perf_counter()
            _run(cmd + ["--k", str(k), "--file", str(f)], a.timeout)
            r = json.loads(f.read_text())
            r["process_wall_s"] = time.perf_counter() - t0
            res[tag] = (r, np.load(f.with_suffix(".npy")))
        ref = res["serial"][1]
        for tag, (r, u) in res.items():
            r["k"] = k
            r["rel_diff_vs_serial"] = float(np.max(np.abs(u - ref)) / np.max(np.abs(ref)))
            r["setup_plus_solve_s"] = r["setup_s"] + r["solve_s"]
            r.pop("peak_mb_ranks", None)
            rows.append(r)
            print(f"k={k} {tag}: {r['ndofs']} DOFs, setup+solve {r['setup_plus_solve_s']:.2f} s, "
                  f"{r['iterations']} its, {r['peak_mb_per_rank']:.0f} MB/rank", flush=True)
        for f in a.out.glob(f"distributed_{k}_*.npy"):
            f.unlink()
    keys = ["k", "ndofs", "path", "ranks", "iterations", "assemble_s", "setup_s", "solve_s", "setup_plus_solve_s",
            "process_wall_s", "peak_mb_per_rank", "rel_diff_vs_serial"]
    with open(a.out / "distributed.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    meta = {"machine": platform.platform(), "cpus": os.cpu_count(), "rtol": RTOL, "rows": rows}
    (a.out / "distributed.json").write_text(json.dumps(meta, indent=1))
    lines = ["| DOFs | path | ranks | iterations | assemble s | setup s | solve s | setup+solve s | "
             "ratio to serial | peak MB/rank | rel. diff. to serial |", "|" + "---|" * 11]
    for r in rows:
        base = next(x for x in rows if x["k"] == r["k"] and x["path"] == "serial pyamg")
        lines.append(f"| {r['ndofs']:,} | {r['path']} | {r['ranks']} | {r['iterations']} | {r['assemble_s']:.2f} | "
                     f"{r['setup_s']:.2f} | {r['solve_s']:.2f} | {r['setup_plus_solve_s']:.2f} | "
                     f"{r['setup_plus_solve_s'] / base['setup_plus_solve_s']:.2f} | {r['peak_mb_per_rank']:.0f} | "
                     f"{r['rel_diff_vs_serial']:.1e} |")
    (a.out / "distributed.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
