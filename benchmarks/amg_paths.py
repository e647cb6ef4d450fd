"""Direct vs factorization-free (AMG) path: outer iterations of every frictionless algorithm, 2D and 3D Hertz, P1 and P2.

For each case (:data:`CASES`: the 3D sphere on a P2 tetrahedral quarter block, 9k to 78k DOFs;
issue 21: the 2D cylinder on P1 and P2 triangles up to 1.1M DOFs and the 3D sphere on P1
tetrahedra up to 243k DOFs, the largest 3D factor of a few GB) and each algorithm/penalty the
script solves with ``linear_solver="direct"`` (where the case lists it) and ``"amg"``, and
records outer iterations, Newton iterations, CG iterations, AMG setups (hierarchies built
from scratch) and updates (Galerkin updates of the hierarchy of ``K``), wall time as a
ratio to one AMG-CG linear elastic solve of the same mesh (AMG setup + one CG solve to
1e-10, ``timings["linear_solve_s"]`` of the AMG run), the outer-iteration ratio AMG /
direct and the relative difference of the total contact force between the paths.
Writes ``<out>/<name>.csv``, ``<out>/<name>.json`` and the table ``<out>/<name>_table.md``
(``--name``, default ``amg_paths``), whose first table is the outer-iteration ratio per case
and variant.

Usage::

    python benchmarks/amg_paths.py [--out DIR] [--cases 3d-p2-9k 2d-p1-120k ...] [--name STEM] [--variants ssn simo-laursen ...] [--append]
        [--drive platen] [--tol-multiplier 1e-11] [--al]

``--drive`` (one of :data:`alcontact.problems.hertz.DRIVES`; the case is labelled ``NAME:DRIVE``)
chooses what moves the block into contact, ``--tol-multiplier`` the multiplier tolerance of both
paths (a tighter one than the default 1e-8 shows where the AMG path's stopping test meets its
solve accuracy); ``--al`` runs the augmented Lagrangian variants only (:data:`AL_VARIANTS`:
Algorithm 6.1 and Algorithm 6.3 with each kind of penalty), for the largest meshes.

Timings are ratios within one run; machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

from alcontact.contact import solve
from alcontact.io.results import write_text_atomic
from alcontact.problems import hertz

#: name -> (builder, keyword arguments, linear solvers run)
CASES = {
    "3d-p2-9k": (hertz.hertz_3d, dict(order=2, n_per_a=1, growth=1.6, size=6.0), ("direct", "amg")),
    "3d-p2-22k": (hertz.hertz_3d, dict(order=2, n_per_a=2, growth=2.0, size=6.0), ("direct", "amg")),
    # the ~37.6k-DOF case of issue 11: the graded box mesh jumps from 33,327 to 39,375 DOFs
    # (n_per_a 1.5-2.1, growth 1.3-1.8, size 6-10 give no count in between)
    "3d-p2-39k": (hertz.hertz_3d, dict(order=2, n_per_a=2, growth=1.5, size=8.0), ("direct", "amg")),
    # the mesh of examples/hertz_3d.toml with P2 elements; one factorization about 6 s
    "3d-p2-78k": (hertz.hertz_3d, dict(order=2, n_per_a=2), ("direct", "amg")),
    # issue 21: 2D and 3D P1, 2D P2 up to 1M DOFs (the 2D meshes of benchmarks/hertz.py)
    "2d-p1-120k": (hertz.hertz_2d, dict(n_per_a=64, growth=1.02), ("direct", "amg")),
    "2d-p1-984k": (hertz.hertz_2d, dict(n_per_a=512, growth=1.15), ("direct", "amg")),
    "2d-p2-222k": (hertz.hertz_2d, dict(order=2, n_per_a=32, growth=1.05), ("direct", "amg")),
    "2d-p2-1.1M": (hertz.hertz_2d, dict(order=2, n_per_a=128, growth=1.15), ("direct", "amg")),
    "3d-p1-39k": (hertz.hertz_3d, dict(n_per_a=8, growth=1.3), ("direct", "amg")),
    "3d-p1-111k": (hertz.hertz_3d, dict(n_per_a=6, growth=1.07), ("direct", "amg")),
    "3d-p1-243k": (hertz.hertz_3d, dict(n_per_a=9, growth=1.07), ("direct", "amg")),
}
DEFAULT_CASES = ["3d-p2-9k"]

#: (label, algorithm, penalty)
VARIANTS = [
    ("penalty", "penalty", None),
    ("simo-laursen", "simo-laursen", None),
    ("rockafellar", "family-p", "rockafellar"),
    ("exp-met1", "family-p", "exp-met1"),
    ("exp-met2", "family-p", "exp-met2"),
    ("log-met1", "family-p", "log-met1"),
    ("log-met2", "family-p", "log-met2"),
    ("quad-met1", "family-p", "quad-met1"),
    ("quad-met2", "family-p", "quad-met2"),
    ("ssn", "ssn", None),
]
#: the augmented Lagrangian variants: Algorithm 6.1 and Algorithm 6.3 with each kind of penalty
AL_VARIANTS = ["simo-laursen", "rockafellar", "exp-met1", "log-met2", "quad-met2"]

FIELDS = ["case", "dofs", "variant", "algorithm", "penalty", "linear_solver", "status", "outer_iterations",
          "newton_iterations", "linear_solves", "cg_iterations", "amg_setups", "amg_updates", "wall_s",
          "amg_linear_solve_s",
          "ratio", "outer_ratio_amg_direct", "force_rel_diff", "normal_force"]


def run(out_dir: Path, cases: list[str], variants: list[str] | None = None, name: str = "amg_paths",
        append: bool = False, drive: str = "obstacle", options: dict | None = None) -> list[dict]:
    chosen = [v for v in VARIANTS if variants is None or v[0] in variants]
    labels = [c if drive == "obstacle" else f"{c}:{drive}" for c in cases]
    rows = _previous_rows(out_dir, name, labels, [v[0] for v in chosen]) if append else []
    for case in cases:
        builder, kwargs, paths = CASES[case]
        prob = builder(drive=drive, **kwargs)
        case = case if drive == "obstacle" else f"{case}:{drive}"
        for label, alg, pen in chosen:
            sols = {}
            for path in paths:
                t0 = time.perf_counter()
                sol = solve(prob, alg, pen, linear_solver=path, **(options or {}))
                wall = time.perf_counter() - t0
                sols[path] = sol
                res = sol.result
                rows.append({
                    "case": case, "dofs": int(prob.model.ndofs), "variant": label, "algorithm": alg,
                    "penalty": res.penalty, "linear_solver": path, "status": res.status.label,
                    "outer_iterations": res.outer_iterations, "newton_iterations": res.newton_iterations,
                    "linear_solves": res.linear_solves, "cg_iterations": sol.extra.get("cg_iterations", ""),
                    "amg_setups": sol.extra.get("amg_setups", ""), "amg_updates": sol.extra.get("amg_updates", ""),
                    "wall_s": round(wall, 2),
                    "amg_linear_solve_s": "", "ratio": "", "outer_ratio_amg_direct": "", "force_rel_diff": "",
                    "normal_force": float(abs(sol.normal_force)),
                })
                print(f"{case} {label} {path}: {res.status.label}, {res.outer_iterations} outer, "
                      f"{res.newton_iterations} Newton, {wall:.1f} s", file=sys.stderr, flush=True)
                _write(out_dir, name, rows)  # a run stopped by a time limit keeps the paths it finished
            amg = sols["amg"]
            ref = amg.timings["linear_solve_s"]
            for row in rows[-len(paths):]:
                row["amg_linear_solve_s"] = round(ref, 3)
                row["ratio"] = round(row["wall_s"] / ref, 1)
            if "direct" in sols:
                d = sols["direct"]
                f_ref = float(np.max(np.abs(d.total_contact_force)))
                diff = float(np.max(np.abs(amg.total_contact_force - d.total_contact_force))) / f_ref
                ratio = amg.result.outer_iterations / max(d.result.outer_iterations, 1)
                rows[-1]["outer_ratio_amg_direct"] = round(ratio, 2)
                rows[-1]["force_rel_diff"] = f"{diff:.1e}"
            _write(out_dir, name, rows)
    return rows


def _previous_rows(out_dir: Path, name: str, cases: list[str], variants: list[str]) -> list[dict]:
    """Rows of an earlier run (``<name>.json``) except those of the (case, variant) pairs run now."""
    path = out_dir / f"{name}.json"
    if not path.exists():
        return []
    rows = json.loads(path.read_text())
    return [r for r in rows if not (r["case"] in cases and r["variant"] in variants)]


def _write(out_dir: Path, name: str, rows: list[dict]) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(out_dir / f"{name}.csv", buf.getvalue())
    write_text_atomic(out_dir / f"{name}.json", json.dumps(rows, indent=1) + "\n")
    write_text_atomic(out_dir / f"{name}_table.md", _markdown(rows))


def _ratio_summary(rows: list[dict]) -> list[str]:
    """Outer iterations AMG / direct per case (rows) and variant (columns), bold above 1.5; ``-``: not run."""
    cases = list(dict.fromkeys(r["case"] for r in rows))
    variants = [v for v, *_ in VARIANTS if any(r["variant"] == v for r in rows)]
    out = ["| case | DOFs | " + " | ".join(variants) + " | max (AL variants) |",
           "|" + "---|" * (len(variants) + 3)]
    for case in cases:
        cells, al = [], []
        for v in variants:
            by = {r["linear_solver"]: r for r in rows if r["case"] == case and r["variant"] == v}
            if "amg" not in by or "direct" not in by:
                cells.append("-")
                continue
            a, d = by["amg"], by["direct"]
            ratio = a["outer_iterations"] / max(d["outer_iterations"], 1)
            ok = a["status"] == "converged" and d["status"] == "converged"
            text = f"{a['outer_iterations']}/{d['outer_iterations']}"
            text = f"**{text}**" if ratio > 1.5 or not ok else text
            cells.append(text if ok else f"{text} ({a['status']}, {d['status']})")
            if v in AL_VARIANTS:
                al.append(ratio if ok else float("inf"))
        dofs = next(r["dofs"] for r in rows if r["case"] == case)
        out.append(f"| {case} | {dofs} | " + " | ".join(cells) + f" | {max(al):.2f} |" if al else
                   f"| {case} | {dofs} | " + " | ".join(cells) + " | - |")
    return out


def _markdown(rows: list[dict]) -> str:
    cols = ["case", "dofs", "variant", "linear_solver", "status", "outer_iterations", "newton_iterations",
            "cg_iterations", "amg_setups", "amg_updates", "ratio", "outer_ratio_amg_direct", "force_rel_diff"]
    lines = ["Outer iterations AMG / direct (bold: above 1.5 or not converged):", ""] + _ratio_summary(rows)
    lines += ["", "| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(str(r[c]) for c in cols) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks"))
    ap.add_argument("--cases", nargs="+", default=DEFAULT_CASES, choices=list(CASES))
    ap.add_argument("--variants", nargs="+", default=None, choices=[v[0] for v in VARIANTS])
    ap.add_argument("--name", default="amg_paths", help="stem of the output files")
    ap.add_argument("--append", action="store_true",
                    help="keep the rows of <name>.json of other cases/variants (one process per case and variant)")
    ap.add_argument("--drive", default="obstacle", choices=list(hertz.DRIVES))
    ap.add_argument("--tol-multiplier", type=float, default=None, help="tol_multiplier of both paths")
    ap.add_argument("--al", action="store_true", help="the augmented Lagrangian variants only (AL_VARIANTS)")
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    options = {} if args.tol_multiplier is None else {"tol_multiplier": args.tol_multiplier}
    run(args.out, args.cases, AL_VARIANTS if args.al else args.variants, args.name, args.append, args.drive, options)
    return 0


if __name__ == "__main__":
    sys.exit(main())
