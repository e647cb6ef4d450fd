"""Run-to-run spread of one contact solve repeated in one process (issue 21).

Each variant solves the same problem ``--repeats`` times (a fresh factorization each time,
variants in round robin so that they sample the same machine load) and records, per run,
CPU seconds of the process (user + system), wall seconds, the load average of the machine,
outer / Newton iterations, linear solves and the total contact force to all digits (a run
that takes another path through the iterations shows up there). Writes
``<out>/<name>.csv`` and ``<out>/<name>.md`` (the text above ``<!-- tables -->`` kept).

With ``--fresh`` every run is a process of its own (the mesh built, the stiffness assembled and the
libraries loaded again; variants in round robin): the spread between processes, which includes
what one process's first solve pays and what the allocator and the page cache leave to the next.

Usage::

    python benchmarks/repeat_spread.py [--case 3d-39k] [--drive platen] [--repeats 5]
        [--variants simo-laursen quad-met2 ssn] [--out DIR] [--name STEM] [--fresh]
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from alcontact.contact import solve
from alcontact.io.results import write_text_atomic
from alcontact.problems import hertz

#: name -> (builder, keyword arguments, linear solver)
CASES = {
    "3d-39k": (hertz.hertz_3d, dict(n_per_a=8, growth=1.3), "mkl-pardiso"),
    "3d-p2-78k": (hertz.hertz_3d, dict(order=2, n_per_a=2.0, growth=1.3), "mkl-pardiso"),
    "2d-100k": (hertz.hertz_2d, dict(n_per_a=64, growth=1.02), "mkl-pardiso"),
}
#: (label, algorithm, penalty)
VARIANTS = {"simo-laursen": ("simo-laursen", None), "quad-met2": ("family-p", "quad-met2"), "ssn": ("ssn", None),
            "exp-met1": ("family-p", "exp-met1")}
FIELDS = ["case", "drive", "variant", "run", "process", "threads", "status", "outer_iterations", "newton_iterations",
          "linear_solves", "factorizations", "cpu_s", "wall_s", "load_avg_1min", "normal_force"]


def run_fresh(case: str, drive: str, variants: list[str], repeats: int) -> list[dict]:
    """:func:`run` with one run per process (``--one``), variants in round robin."""
    rows = []
    for k in range(repeats):
        for label in variants:
            cmd = [sys.executable, str(Path(__file__).resolve()), "--case", case, "--drive", drive, "--one", label]
            out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
            row = json.loads(out.strip().splitlines()[-1])
            rows.append({**row, "run": k, "process": "fresh"})
            print(rows[-1], file=sys.stderr, flush=True)
    return rows


def run(case: str, drive: str, variants: list[str], repeats: int) -> list[dict]:
    builder, kw, solver = CASES[case]
    prob = builder(drive=drive, **kw)
    prob.model.stiffness()
    rows = []
    for k in range(repeats):
        for label in variants:
            alg, pen = VARIANTS[label]
            prob.model.clear_factorization()
            c0, t0 = time.process_time(), time.perf_counter()
            sol = solve(prob, alg, pen, linear_solver=solver)
            cpu, wall = time.process_time() - c0, time.perf_counter() - t0
            r = sol.result
            rows.append({"case": case, "drive": drive, "variant": label, "run": k, "process": "same",
                         "threads": os.environ.get("MKL_NUM_THREADS", "default"), "status": r.status.label,
                         "outer_iterations": r.outer_iterations, "newton_iterations": r.newton_iterations,
                         "linear_solves": r.linear_solves, "factorizations": r.factorizations,
                         "cpu_s": round(cpu, 3), "wall_s": round(wall, 3), "load_avg_1min": os.getloadavg()[0],
                         "normal_force": repr(float(sol.normal_force))})
            print(rows[-1], file=sys.stderr, flush=True)
    return rows


def _spread(xs):
    return (max(xs) - min(xs)) / statistics.median(xs)


def report(rows) -> str:
    out = ["| case | drive | variant | processes | runs | iterations (outer / Newton / solves) | distinct forces | "
           "CPU s min-max | CPU spread (max-min)/median | wall s min-max | wall spread | load average |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in dict.fromkeys((r["case"], r["drive"], r["variant"], r.get("process", "same")) for r in rows):
        sub = [r for r in rows if (r["case"], r["drive"], r["variant"], r.get("process", "same")) == key]
        its = sorted({f"{r['outer_iterations']} / {r['newton_iterations']} / {r['linear_solves']}" for r in sub})
        cpu = [float(r["cpu_s"]) for r in sub]
        wall = [float(r["wall_s"]) for r in sub]
        load = [float(r["load_avg_1min"]) for r in sub]
        out.append(f"| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {len(sub)} | {', '.join(its)} | "
                   f"{len({r['normal_force'] for r in sub})} | {min(cpu):.2f}-{max(cpu):.2f} | {_spread(cpu):.1%} | "
                   f"{min(wall):.2f}-{max(wall):.2f} | {_spread(wall):.1%} | {min(load):.1f}-{max(load):.1f} |")
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="3d-39k", choices=list(CASES))
    ap.add_argument("--drive", default="platen", choices=list(hertz.DRIVES))
    ap.add_argument("--variants", nargs="+", default=["simo-laursen", "quad-met2", "ssn"], choices=list(VARIANTS))
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks"))
    ap.add_argument("--name", default="repeat_spread")
    ap.add_argument("--fresh", action="store_true", help="every run in a process of its own")
    ap.add_argument("--append", action="store_true", help="keep the rows of <name>.csv")
    ap.add_argument("--one", choices=list(VARIANTS), help=argparse.SUPPRESS)  # a single run, printed as JSON
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(run(args.case, args.drive, [args.one], 1)[0]))
        return 0
    rows = (run_fresh if args.fresh else run)(args.case, args.drive, args.variants, args.repeats)
    if args.append and (args.out / f"{args.name}.csv").exists():
        with open(args.out / f"{args.name}.csv", newline="") as fh:
            rows = list(csv.DictReader(fh)) + rows
    args.out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS, lineterminator="\n", restval="same")
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(args.out / f"{args.name}.csv", buf.getvalue())
    md = args.out / f"{args.name}.md"
    text = md.read_text() if md.exists() else ""
    head = text.split("<!-- tables -->")[0] + "<!-- tables -->\n\n" if "<!-- tables -->" in text else ""
    write_text_atomic(md, head + report(rows))  # the text above <!-- tables --> is kept
    print(report(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
