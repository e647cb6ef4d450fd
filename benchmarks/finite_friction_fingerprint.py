"""Fingerprint of the finite-deformation frictional solvers, to check that a refactoring changes nothing.

Solves the problems of ``tests/verification/test_finite_friction*.py`` (the sliding block
2D and 3D, the frictional ironing 2D with slides 0.4 and 0.6, the rotating roller, the 3D
ironing with 3 slide steps; the builders are imported from the test modules, so they stay
the tests' problems) with Algorithm 6.2 (``simo-laursen``), Algorithm 6.4 (``family-p``
with ``exp-met1``, ``log-met1`` and ``quad-met1``) and the Alart-Curnier reference
(``ssn``), with the default options and, for the AL algorithms, ``radius="traction"``.
Prints one line per run (status, outer and Newton iterations, cut-backs, linear solves)
and one per step (status, outer, Newton, normal force and tangential force to 10
significant digits, largest displacement): ``diff`` of two outputs is the comparison.

Usage::

    python benchmarks/finite_friction_fingerprint.py > before.txt     # on the old tree
    python benchmarks/finite_friction_fingerprint.py > after.txt      # on the new tree
    diff before.txt after.txt

``--quick`` leaves out the ``radius="traction"`` runs and the 3D ironing.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

_TESTS = Path(__file__).resolve().parents[1] / "tests"
sys.path[:0] = [str(_TESTS), str(_TESTS / "verification")]

ALGORITHMS = ("simo-laursen", "family-p", "family-p/log-met1", "family-p/quad-met1", "ssn")
OPTIONS = {"default": {}, "traction": {"radius": "traction"}}


def cases(quick: bool):
    """(name, mu, problem builder ``-> (problem, obstacle_path, times)``) of the tests' problems."""
    import test_finite_friction as tf
    import test_finite_friction_rotation as tr
    import test_finite_friction_surface as ts

    def block2d():
        times, path = tf._block_path()
        return tf._block(), path, times

    def ironing2d():
        problem, path = tf._ironing(0.4)
        return problem, path, list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, 5)[1:])

    def roller():
        problem, path, _ = tr._roller()
        return problem, path, [0.1, 0.2, 0.4, 0.6]

    def block3d():
        problem, path, times, _ = ts._block_3d()
        return problem, path, times

    rows = [("block2d", 0.3, block2d), ("ironing2d", 0.3, ironing2d), ("arc2d", 0.3, ts._ironing_2d),
            ("roller", 0.3, roller), ("block3d", 0.3, block3d)]
    if not quick:
        rows.append(("ironing3d", 0.3, lambda: ts._ironing_3d(3)))
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="default options only, no 3D ironing")
    parser.add_argument("--only", default=None, help="run only the problems whose name contains this")
    args = parser.parse_args(argv)
    from alcontact.contact import solve

    for name, mu, make in cases(args.quick):
        if args.only and args.only not in name:
            continue
        for alg in ALGORITHMS:
            algorithm, _, penalty = alg.partition("/")
            for oname, opts in OPTIONS.items():
                if (algorithm == "ssn" or args.quick) and oname != "default":
                    continue
                problem, path, times = make()
                sol = solve(problem, algorithm, penalty or None, friction=mu, steps=times, obstacle_path=path, **opts)
                ex = sol.record.extra  # the run's totals (failed tries that cut-backs repeated included)
                frames = sol.frames if sol.record.steps else ()  # no accepted step: one frame of the start
                print(f"{name} {alg} {oname}: {sol.status.label} steps={len(frames)} newton={ex['newton_total']} "
                      f"solves={ex['linear_solves']} cutbacks={ex['cutbacks']}", flush=True)
                for s in frames:
                    T = " ".join(f"{v:.10g}" for v in s.tangential_force)
                    print(f"  t={s.t:.10g} {s.status.label} outer={s.outer_iterations} newton={s.newton_iterations} "
                          f"N={s.normal_force:.10g} T=[{T}] max|u|={float(np.max(np.abs(s.u))):.10g}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
