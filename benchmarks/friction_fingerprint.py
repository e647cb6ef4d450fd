"""Fingerprint of the small-kinematics frictional solvers, to check that a refactoring changes nothing.

Solves the friction tests' problems (block on a plane 2D stick / slip and 3D slip, the
Cattaneo-Mindlin cylinder 2D at 4 and 8 elements per a, the sphere 3D, the block held by
the obstacle only in 2D / 3D below and beyond the Coulomb limit) with Algorithm 6.2,
Algorithm 6.4 (exp-met1 and log-met1), and the semi-smooth Newton reference, on the direct
and the AMG path, with the default options, ``multiplier_update="first-order"`` (direct
path; the AMG path is first order anyway) and ``radius="traction"``: 170 runs, about 6
minutes on one core. Records per run (``contact.solve``) the status, message and counters and
per step (its frames) the iteration counts, forces, tractions (global components on the body),
displacements and open/stick/slip states.

The AMG path is made deterministic for the comparison: pyamg's spectral radius estimates
start from random vectors (the legacy NumPy generator is seeded before every run), and the
rebuild rule of the AMG hierarchy weighs wall time (``time.perf_counter`` is replaced by a
counter of 1 ms per call).

Usage::

    python benchmarks/friction_fingerprint.py record before.pkl     # on the old tree
    python benchmarks/friction_fingerprint.py record after.pkl      # on the new tree
    python benchmarks/friction_fingerprint.py compare before.pkl after.pkl

``compare`` lists every difference of a counter, a status or a state, and every field that
differs by more than 1e-12 of its largest value; it exits with 1 when there is any.
"""

from __future__ import annotations

import argparse
import itertools
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

ALGORITHMS = ("simo-laursen", "family-p", "family-p/log-met1", "ssn")
OPTIONS = {"default": {}, "first-order": {"multiplier_update": "first-order"}, "traction": {"radius": "traction"}}
FIELDS = ("normal_force", "tangential_force", "u", "pressure", "traction_t")


def cases():
    """(name, builder) of the problems: the friction tests' ones."""
    from _helpers import held_block

    from alcontact.problems import friction as fp

    return [
        ("block2d-stick", lambda: fp.block_on_plane(dim=2, n=8, shear_ratio=0.4)),
        ("block2d-slip", lambda: fp.block_on_plane(dim=2, n=8, shear_ratio=3.0)),
        ("block3d-slip", lambda: fp.block_on_plane(dim=3, n=4, shear_ratio=3.0)),
        ("curved2d", lambda: fp.cattaneo_mindlin_2d(4, size=5.0, normal_steps=1, tangential_steps=2)),
        ("curved3d", lambda: fp.sphere_shear_3d(2, size=3.0, normal_steps=1, tangential_steps=2)),
        ("held2d-0.5", lambda: held_block(2, 0.5)[:2]),
        ("held3d-0.5", lambda: held_block(3, 0.5)[:2]),
        ("held2d-1.5", lambda: held_block(2, 1.5)[:2]),
        ("held3d-1.5", lambda: held_block(3, 1.5)[:2]),
        ("mindlin8", lambda: fp.cattaneo_mindlin_2d(n_per_a=8)),
    ]


def record() -> dict:
    """Solve every run; the fingerprint keyed by (problem, algorithm, path, options)."""
    from alcontact.contact import solve

    tick = itertools.count()
    time.perf_counter = lambda: next(tick) * 1e-3  # the AMG rebuild rule weighs wall time
    out = {}
    for name, make in cases():
        for alg in ALGORITHMS:
            algorithm, _, penalty = alg.partition("/")
            for path in ("direct", "amg"):
                for oname, opts in OPTIONS.items():
                    if (algorithm == "ssn" and oname != "default") or (path == "amg" and oname == "first-order"):
                        continue
                    prob, hist = make()
                    np.random.seed(0)  # pyamg's spectral radius estimates start from random vectors
                    sol = solve(prob, algorithm, penalty or None, history=hist, linear_solver=path, **opts)
                    run = sol.record  # the run's totals (failed tries that cut-backs repeated included)
                    frames = sol.frames if run.steps else ()  # no converged step: one frame of the start
                    out[(name, alg, path, oname)] = dict(
                        status=int(sol.status), message=sol.result.message, outer=run.outer_iterations,
                        newton=run.newton_iterations, cutbacks=run.cutbacks, linear_solves=run.linear_solves,
                        extra={k: v for k, v in run.extra.items() if isinstance(v, (int, str))},
                        steps=[dict(t=f.t, outer=f.outer_iterations, newton=f.newton_iterations,
                                    state=np.array(f.state), **{k: np.array(getattr(f, k)) for k in FIELDS})
                               for f in frames])
                    print(name, alg, path, oname, sol.status.label, run.outer_iterations, run.newton_iterations,
                          flush=True)
    return out


def compare(a: dict, b: dict) -> tuple[float, list]:
    """Largest relative difference of the fields and the list of differences."""
    worst, bad = 0.0, []
    for key in sorted(set(a) | set(b)):
        if key not in a or key not in b:
            bad.append((key, "missing"))
            continue
        x, y = a[key], b[key]
        bad += [(key, f, x[f], y[f]) for f in ("status", "message", "outer", "newton", "cutbacks", "linear_solves",
                                                "extra") if x[f] != y[f]]
        if len(x["steps"]) != len(y["steps"]):
            bad.append((key, "steps", len(x["steps"]), len(y["steps"])))
            continue
        for s, r in zip(x["steps"], y["steps"]):
            bad += [(key, s["t"], f, s[f], r[f]) for f in ("t", "outer", "newton") if s[f] != r[f]]
            if not np.array_equal(s["state"], r["state"]):
                bad.append((key, s["t"], "state"))
            for f in FIELDS:
                d = float(np.max(np.abs(s[f] - r[f]), initial=0.0))
                scale = max(float(np.max(np.abs(s[f]), initial=0.0)), 1e-300)
                worst = max(worst, d / scale)
                if d > 1e-12 * scale:
                    bad.append((key, s["t"], f, d / scale))
    return worst, bad


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("record").add_argument("out", type=Path)
    cmp = sub.add_parser("compare")
    cmp.add_argument("a", type=Path)
    cmp.add_argument("b", type=Path)
    args = parser.parse_args(argv)
    if args.command == "record":
        args.out.write_bytes(pickle.dumps(record()))
        return 0
    a, b = (pickle.loads(p.read_bytes()) for p in (args.a, args.b))
    worst, bad = compare(a, b)
    print(f"{len(a)} runs compared; largest relative difference {worst:.3e}; {len(bad)} differences")
    for row in bad[:50]:
        print(*row)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
