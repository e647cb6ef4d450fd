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
    ap.add_argument("--worker", choices=["serial", "petsc"], help=argparse.SUPPRESS)
    ap.add_argument("--k", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--file", type=Path, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker == "serial":
        worker_serial(a.k, a.file)
        return 0
    if a.worker == "petsc":
        worker_petsc(a.k, a.file)
        return 0
    a.out.mkdir(parents=True, exist_ok=True)
    rows = []
    me = [sys.executable, str(Path(__file__).resolve())]
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
