"""Finite-deformation contact on the AMG + CG path against the direct path (``linear_solver``).

Runs :func:`alcontact.contact.solve` (finite deformation) on one case with ``linear_solver="direct"``
(MKL PARDISO per Newton matrix) and ``linear_solver="amg"``
(:class:`~alcontact.contact.systems._full_space.AMGNewtonSolver`), each in its own process
(peak resident memory from ``getrusage``), and records per load step the Newton
iterations, the CG iterations (Newton steps and all solves), the AMG setups and the CPU
seconds of the step (one thread), plus the largest relative difference of the force and of
the final displacement between the two paths. Appends one row per (case, path, step) to
``<out>/finite_amg.csv``.

Usage::

    python benchmarks/finite_amg.py --problem hemisphere --n 24 --order 1 --steps 5 [--algorithm simo-laursen]
    python benchmarks/finite_amg.py --problem half-cylinder --n 56 --order 1 --steps 8
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

#: the keys the final frame adds to ``ContactSolution.extra`` (the step's own record, not the run's)
FRAME_KEYS = ("t", "cutbacks", "seconds", "requested", "step_newton_iterations", "step_outer_iterations",
              "step_linear_solves")

FIELDS = ["problem", "n", "order", "dofs", "algorithm", "penalty", "linear_solver", "step", "newton", "cg_newton",
          "cg_all", "amg_setups", "cpu_s", "wall_s", "force", "peak_rss_mb", "max_rel_force_diff", "max_rel_u_diff"]


def _problem(name: str, n: int, order: int):
    from alcontact.problems.half_cylinder import half_cylinder
    from alcontact.problems.hemisphere import hemisphere

    return {"half-cylinder": half_cylinder, "hemisphere": hemisphere}[name](n, order=order)


def child(args) -> None:
    """One run (one path) in this process; prints a JSON record."""
    from alcontact.contact import solve

    prob = _problem(args.problem, args.n, args.order)
    steps = []
    state = {"cpu": time.process_time(), "wall": time.perf_counter(), "cg": 0, "cgn": 0, "setups": 0}
    holder = {}

    def on_step(done, total, t):  # solve's progress: before the first step (done = 0), after every accepted one
        solver = holder.get("solver")
        if solver is None:
            return
        info = solver.info()
        cpu, wall = time.process_time(), time.perf_counter()
        steps.append({"step": len(steps) + 1,
                      "cg_newton": int(info.get("newton_cg_iterations", 0)) - state["cgn"],
                      "cg_all": int(info.get("cg_iterations", 0)) - state["cg"],
                      "amg_setups": int(info.get("amg_setups", 0)) - state["setups"],
                      "cpu_s": cpu - state["cpu"], "wall_s": wall - state["wall"]})
        state.update(cpu=cpu, wall=wall, cg=int(info.get("cg_iterations", 0)),
                     cgn=int(info.get("newton_cg_iterations", 0)), setups=int(info.get("amg_setups", 0)))

    # the solver object of the run (for per-step counters): wrap the FiniteContact constructor
    from alcontact.contact.systems import _full_space as _finite

    init = _finite.FiniteContact.__init__

    def spy(self, *a, **k):
        init(self, *a, **k)
        holder["solver"] = self.solver

    _finite.FiniteContact.__init__ = spy
    state.update(cpu=time.process_time(), wall=time.perf_counter())
    sol = solve(prob, args.algorithm, args.penalty, steps=args.steps, linear_solver=args.linear_solver,
                on_step=on_step)
    frames = [f for f in sol.frames if f.t > 0]  # the accepted load steps (a run that reached none: the start)
    for row, f in zip(steps, frames):
        row.update(newton=int(f.newton_iterations), force=float(f.contact_force[1]))
    steps = [{k: row[k] for k in ("step", "newton", "cg_newton", "cg_all", "amg_setups", "cpu_s", "wall_s", "force")}
             for row in steps]
    np.save(args.u_file, sol.u)
    print(json.dumps({"success": bool(sol.success), "message": sol.result.message, "dofs": int(prob.model.ndofs),
                      "steps": steps, "extra": {k: v for k, v in sol.extra.items()
                                                if isinstance(v, (int, float, str)) and k not in FRAME_KEYS},
                      "timings": {k: float(v) for k, v in sol.timings.items()},
                      "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--problem", default="hemisphere", choices=("hemisphere", "half-cylinder"))
    ap.add_argument("--n", type=int, default=8)
    ap.add_argument("--order", type=int, default=1)
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--algorithm", default="simo-laursen")
    ap.add_argument("--penalty", default=None)
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "benchmarks"))
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--linear-solver", default="direct", help=argparse.SUPPRESS)
    ap.add_argument("--u-file", default="", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args)
        return
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    runs, us = {}, {}
    for path in ("direct", "amg"):
        ufile = f"/tmp/finite_amg_u_{os.getpid()}_{path}.npy"
        cmd = [sys.executable, __file__, "--child", "--problem", args.problem, "--n", str(args.n), "--order",
               str(args.order), "--steps", str(args.steps), "--algorithm", args.algorithm, "--linear-solver", path,
               "--u-file", ufile] + (["--penalty", args.penalty] if args.penalty else [])
        out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
        runs[path] = json.loads(out.strip().splitlines()[-1])
        us[path] = np.load(ufile)
        os.unlink(ufile)
        print(path, json.dumps({k: v for k, v in runs[path].items() if k != "steps"}), flush=True)
    fd = np.array([s["force"] for s in runs["direct"]["steps"]])
    fa = np.array([s["force"] for s in runs["amg"]["steps"]])
    dF = float(np.max(np.abs(fa - fd) / np.abs(fd))) if fa.shape == fd.shape else float("nan")
    dU = float(np.max(np.abs(us["amg"] - us["direct"])) / np.max(np.abs(us["direct"])))
    print(f"max relative force difference {dF:.2e}, displacement {dU:.2e}")
    target = Path(args.out) / "finite_amg.csv"
    new = not target.exists()
    with open(target, "a", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        if new:
            w.writeheader()
        for path, run in runs.items():
            for s in run["steps"]:
                w.writerow({"problem": args.problem, "n": args.n, "order": args.order, "dofs": run["dofs"],
                            "algorithm": args.algorithm, "penalty": args.penalty or "", "linear_solver": path,
                            **{k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in s.items()},
                            "peak_rss_mb": f"{run['peak_rss_mb']:.0f}", "max_rel_force_diff": f"{dF:.2e}",
                            "max_rel_u_diff": f"{dU:.2e}"})


if __name__ == "__main__":
    main()
