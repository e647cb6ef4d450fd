"""Large 3D Hertz contact on one machine: peak memory per DOF and time in linear solves (issue 11).

For each requested size (``--dofs 250k 1M 5M``, P1 tetrahedra; the graded quarter
block of :func:`alcontact.problems.hertz.hertz_3d` with ``growth`` 1.04 and the
elements per contact radius chosen to reach the size) a fresh subprocess builds the
problem, assembles the stiffness, sets up the factorization-free contact path
(:class:`alcontact.contact.systems._krylov.IterativeContact`: AMG of ``K`` plus one CG
solve, which is also the reference "one linear solve") and runs the requested
variants. Memory: the resident set is sampled every 10 ms in a thread; the peak of each
stage is reported, and the process peak (``resource.getrusage`` ``ru_maxrss``) divided
by the DOFs gives bytes/DOF. Time: each variant's total wall time (setup included)
less the stiffness assembly (``timings["assembly_s"]``; the model does not keep the
matrix between solves, so each solve assembles it) over one linear solve of the same
mesh measured in the same run: AMG setup for ``K`` plus one CG solve to 1e-10
(``timings["linear_solve_s"]``).

Writes ``<out>/hertz_3d_large.json`` (one record per size) and ``.csv`` (one row per
variant). Usage::

    python benchmarks/hertz_3d_large.py --dofs 250k 1M [--variants ssn simo-laursen exp-met1] [--out DIR]

``--solve-only`` leaves out the stiffness and contact-setup stages (the solves do both
again): the worker then meshes and solves, as a user's run does, and its whole wall and
CPU times are the time to a converged 5M-DOF solution.

Run big sizes in the background with a memory limit, e.g.
``prlimit --as=14000000000 timeout 2400 python benchmarks/hertz_3d_large.py --dofs 5M``.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import logging
import os
import resource
import subprocess
import sys
import threading
import time
from pathlib import Path

#: (label, algorithm, penalty)
VARIANTS = {
    "ssn": ("ssn", None),
    "simo-laursen": ("simo-laursen", None),
    "exp-met1": ("family-p", "exp-met1"),
    "penalty": ("penalty", None),
}
DEFAULT_VARIANTS = ["ssn", "simo-laursen", "exp-met1"]
GROWTH = 1.04
FIELDS = ["case", "dofs", "variant", "status", "outer_iterations", "newton_iterations", "linear_solves",
          "cg_iterations", "amg_setups", "amg_updates", "wall_s", "assembly_s", "linear_solve_s", "ratio",
          "a_err_pct", "p0_err_pct",
          "peak_gb", "bytes_per_dof"]


def parse_size(text: str) -> int:
    """``"250k"`` -> 250000, ``"1M"`` -> 1000000, ``"1200000"`` -> 1200000."""
    t = text.strip().lower()
    mult = {"k": 10**3, "m": 10**6}.get(t[-1:], 1)
    return int(float(t[:-1] if mult > 1 else t) * mult)


def predicted_dofs(n_per_a: float, growth: float = GROWTH) -> int:
    """DOFs of ``hertz_3d(n_per_a=..., growth=...)`` (P1) from the graded axes alone (nothing meshed)."""
    from alcontact.fem.meshes import graded_axis
    from alcontact.problems.hertz import mesh_spec

    md = mesh_spec(3, n_per_a, 1, growth=growth)
    b, r = md["bounds"], md["refine"]
    n = 3
    for ax in range(3):
        lo, hi = b[2 * ax], b[2 * ax + 1]
        h_max = (hi - lo) / md["cells"][ax]
        if ax < 2:  # fine for |x - xc| <= width
            flo, fhi = r["center"][ax] - r["width"], r["center"][ax] + r["width"]
        else:  # fine for z >= zc - depth
            flo, fhi = r["center"][2] - r["depth"], hi
        n *= graded_axis(lo, hi, flo, fhi, r["h_min"], r["growth"], h_max).size
    return int(n)


def n_per_a_for(dofs: int, growth: float = GROWTH) -> float:
    """Smallest elements per contact radius (to 1e-3) whose mesh has at least ``dofs`` DOFs."""
    lo, hi = 1.0, 80.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if predicted_dofs(mid, growth) < dofs:
            lo = mid
        else:
            hi = mid
    return float(f"{hi:.3f}") if predicted_dofs(float(f"{hi:.3f}"), growth) >= dofs else float(f"{hi + 1e-3:.3f}")


class _Memory:
    """Resident-set peaks per stage, sampled in a thread (Linux ``/proc/self/status``)."""

    def __init__(self):
        self.stage = "start"
        self.peaks: dict[str, int] = {}
        self._stop = False
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    @staticmethod
    def rss() -> int:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmRSS"):
                    return int(line.split()[1]) * 1024
        return 0

    def _run(self):
        while not self._stop:
            r, s = self.rss(), self.stage
            if r > self.peaks.get(s, 0):
                self.peaks[s] = r
            time.sleep(0.01)

    def enter(self, stage: str) -> None:
        r = self.rss()
        self.peaks[self.stage] = max(self.peaks.get(self.stage, 0), r)
        self.stage = stage
        self.peaks[stage] = max(self.peaks.get(stage, 0), r)


def _cpu_seconds() -> float:
    """User + system CPU seconds of this process so far."""
    ru = resource.getrusage(resource.RUSAGE_SELF)
    return ru.ru_utime + ru.ru_stime


def one_size(dofs_target: int, variants: list[str], log=print, solve_only: bool = False) -> dict:
    """Build, set up and solve one size in this process; the record of :func:`run`.

    ``solve_only`` skips the stiffness and contact-setup stages (every solve assembles, sets
    up and measures its own reference linear solve anyway): the process then does what a
    user's run does, meshing and the contact solves. ``process_wall_s`` and
    ``process_cpu_s`` are the whole worker's times, ``cpu_s`` of a variant its solve's.
    """
    from alcontact.contact import solve
    from alcontact.problems import hertz

    t_proc, cpu_proc = time.perf_counter(), _cpu_seconds()
    mem = _Memory()
    rec: dict = {"dofs_target": dofs_target, "growth": GROWTH, "stages": {}, "solve_only": solve_only}
    n = n_per_a_for(dofs_target)
    rec["n_per_a"] = n
    t0 = time.perf_counter()
    mem.enter("mesh+model")
    prob = hertz.hertz_3d(n_per_a=n, growth=GROWTH)
    model = prob.model
    rec["dofs"] = int(model.ndofs)
    rec["elements"] = int(model.mesh.t.shape[1])
    rec["stages"]["mesh+model"] = {"s": round(time.perf_counter() - t0, 2)}
    log(f"{rec['dofs']} DOFs, {rec['elements']} tetrahedra (n_per_a={n}) in {time.perf_counter() - t0:.1f} s")
    if not solve_only:
        _setup_stages(prob, rec, mem, log)
    rec["variants"] = []
    _partial(rec, mem)
    ref = prob.reference
    for label in variants:
        alg, pen = VARIANTS[label]
        mem.enter(f"solve {label}")
        cpu0 = _cpu_seconds()
        sol = solve(prob, alg, pen, linear_solver="amg")
        cpu_s = _cpu_seconds() - cpu0
        r = sol.result
        P = ref.load(sol.normal_force)
        a = sol.contact_half_width(axis=0, center=prob.meta["center"])
        t = sol.timings
        row = {"variant": label, "status": r.status.label, "outer_iterations": r.outer_iterations,
               "newton_iterations": r.newton_iterations, "linear_solves": r.linear_solves,
               "cg_iterations": sol.extra.get("cg_iterations"), "amg_setups": sol.extra.get("amg_setups"),
               "amg_updates": sol.extra.get("amg_updates"),
               "wall_s": round(t["total_s"], 2), "cpu_s": round(cpu_s, 2), "assembly_s": round(t.get("assembly_s", 0.0), 2),
               "linear_solve_s": round(t["linear_solve_s"], 3),
               "ratio": round((t["total_s"] - t.get("assembly_s", 0.0)) / t["linear_solve_s"], 2),
               "a_err_pct": round(100 * (a / ref.half_width(P) - 1), 3) if P > 0 else None,
               "p0_err_pct": round(100 * (sol.peak_pressure / ref.peak_pressure(P) - 1), 3) if P > 0 else None}
        rec["variants"].append(row)
        log(f"  {label}: {row}")
        del sol
        _partial(rec, mem)
    mem.enter("end")
    time.sleep(0.05)
    mem._stop = True
    _memory_fields(rec, mem)
    rec["process_wall_s"] = round(time.perf_counter() - t_proc, 2)
    rec["process_cpu_s"] = round(_cpu_seconds() - cpu_proc, 2)
    return rec


def _setup_stages(prob, rec: dict, mem: "_Memory", log=print) -> None:
    """The stiffness and contact-setup stages of :func:`one_size` (memory and the reference solve)."""
    from alcontact.contact.systems import IterativeContact

    model = prob.model
    t0 = time.perf_counter()
    mem.enter("stiffness")
    K = model.stiffness()
    rec["nnz"] = int(K.nnz)
    rec["stages"]["stiffness"] = {"s": round(time.perf_counter() - t0, 2)}
    log(f"stiffness nnz {K.nnz} in {time.perf_counter() - t0:.1f} s")
    # not kept on the model: each solve assembles it and keeps only K on the free DOFs (its
    # assembly time is reported and left out of the ratio, as hertz.py assembles outside the timings)
    del K
    model.clear_stiffness()
    t0 = time.perf_counter()
    mem.enter("contact setup")
    ic = IterativeContact(prob)
    rec["stages"]["contact setup"] = {"s": round(time.perf_counter() - t0, 2)}
    rec["linear_solve_s"] = round(ic.reference_seconds, 3)
    rec["amg_setup_s"] = round(ic.factor_seconds, 3)
    rec["reference_cg_iterations"] = int(ic.cg_iterations)
    rec["candidates"] = int(ic.cand.size)
    log(f"one linear solve {ic.reference_seconds:.1f} s (AMG setup {ic.factor_seconds:.1f} s, "
        f"{ic.cg_iterations} CG iterations)")
    del ic


def _memory_fields(rec: dict, mem: _Memory) -> None:
    """Stage peaks and the process peak (``ru_maxrss``) so far into ``rec``."""
    for s, b in list(mem.peaks.items()):
        if s in rec["stages"] or s.startswith("solve"):
            rec["stages"].setdefault(s, {})["peak_gb"] = round(b / 1e9, 3)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: kilobytes
    rec["peak_gb"] = round(peak / 1e9, 3)
    rec["bytes_per_dof"] = int(round(peak / rec["dofs"]))


def _partial(rec: dict, mem: _Memory) -> None:
    """Print the record so far (a run stopped by a time limit keeps what it measured)."""
    _memory_fields(rec, mem)
    print("RECORD " + json.dumps(rec), flush=True)


def _set_mmap_threshold(nbytes: int) -> None:
    """Fix glibc's mmap threshold (``mallopt(M_MMAP_THRESHOLD)``): arrays above it are returned to the
    system when freed. The default threshold grows to 32 MB after the first large free, and the
    heap then keeps freed arrays of up to that size (its resident set grows with fragmentation)."""
    import ctypes

    libc = ctypes.CDLL("libc.so.6")
    M_MMAP_THRESHOLD = -3
    if libc.mallopt(M_MMAP_THRESHOLD, int(nbytes)) != 1:
        raise RuntimeError("mallopt(M_MMAP_THRESHOLD) failed")


def run(sizes: list[int], variants: list[str], out: Path, log=print, mmap_threshold: int = 0,
        solve_only: bool = False) -> list[dict]:
    """Each size in its own subprocess (a clean ``ru_maxrss``); write JSON and CSV into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    recs = []
    for size in sizes:
        cmd = [sys.executable, __file__, "--worker", str(size), "--variants", *variants,
               "--mmap-threshold", str(mmap_threshold)] + (["--solve-only"] if solve_only else [])
        log(f"== {size} DOFs: {' '.join(cmd)}")
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, env=os.environ.copy())  # progress on stderr
        lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("RECORD ")]
        if not lines:
            recs.append({"dofs_target": size, "error": f"exit status {proc.returncode}"})
            log(f"   failed: exit status {proc.returncode}")
            continue
        rec = json.loads(lines[-1][len("RECORD "):])
        if proc.returncode != 0:  # stopped (time or memory limit): the variants done so far
            rec["error"] = f"exit status {proc.returncode} after {len(rec.get('variants', []))} variants"
        recs.append(rec)
    rows = []
    for rec in recs:
        for v in rec.get("variants", []):
            rows.append({"case": f"3d-p1-{rec['dofs_target']}", "dofs": rec["dofs"], **v,
                         "peak_gb": rec["peak_gb"], "bytes_per_dof": rec["bytes_per_dof"]})
    (out / "hertz_3d_large.json").write_text(json.dumps(recs, indent=1) + "\n")
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS, extrasaction="ignore")
    w.writeheader()
    w.writerows(rows)
    (out / "hertz_3d_large.csv").write_text(buf.getvalue())
    return recs


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dofs", nargs="*", default=["250k", "1M"], help="sizes, e.g. 250k 1M 5M")
    ap.add_argument("--variants", nargs="*", default=DEFAULT_VARIANTS, choices=list(VARIANTS))
    ap.add_argument("--out", default=str(Path(__file__).parent / "out"))
    ap.add_argument("--mmap-threshold", type=int, default=0,
                    help="glibc M_MMAP_THRESHOLD in bytes for the workers (0: the default, a dynamic threshold)")
    ap.add_argument("--solve-only", action="store_true",
                    help="skip the stiffness and contact-setup stages: mesh, then the solves (a user's run)")
    ap.add_argument("--worker", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    if args.worker is not None:
        if args.mmap_threshold:
            _set_mmap_threshold(args.mmap_threshold)
        rec = one_size(args.worker, args.variants, log=lambda s: print(s, file=sys.stderr, flush=True),
                       solve_only=args.solve_only)
        print("RECORD " + json.dumps(rec), flush=True)
        return 0
    recs = run([parse_size(s) for s in args.dofs], args.variants, Path(args.out), mmap_threshold=args.mmap_threshold,
               solve_only=args.solve_only)
    for rec in recs:
        print(json.dumps({k: v for k, v in rec.items() if k != "variants"}))
        for v in rec.get("variants", []):
            print("   ", json.dumps(v))
    return 0


if __name__ == "__main__":
    sys.exit(main())
