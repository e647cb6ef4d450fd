"""Schur window: CPU seconds of the contact solve for several ``SCHUR_WINDOW`` values.

For one Hertz mesh, each window in turn: the contact solve (ssn and family-p/exp-met1, each
with its own PARDISO factorization) over one linear solve (factorization + solve, no Schur
block), the fastest of ``reps`` runs in CPU seconds of the process, the Schur block size and
the candidates outside the block. Used to choose
:data:`alcontact.contact.systems._condensed.SCHUR_WINDOW` (``docs/benchmarks/hertz.md``).

Usage::

    OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 python benchmarks/schur_window.py 3d 3 1.07 1 0,0.5,1,2,4 2
    #                                                          dim n_per_a growth order windows reps
"""

from __future__ import annotations

import sys
import time

import alcontact.contact.systems._condensed as D
from alcontact.contact import solve
from alcontact.problems import hertz


def main(argv=None) -> int:
    dim, n, g, order, windows, reps = (argv or sys.argv[1:])[:6]
    n, g, order, reps = float(n), float(g), int(order), int(reps)
    prob = (hertz.hertz_3d if dim == "3d" else hertz.hertz_2d)(order=order, n_per_a=n, growth=g)
    m = prob.model
    m.stiffness()
    fixed, vals = prob.dirichlet()
    f = prob.load_vector()

    def plain():
        m.clear_factorization()
        c = time.process_time()
        m.factorize(fixed, backend="mkl-pardiso", reuse=False).solve_full(f, vals)
        return time.process_time() - c

    plain()  # loads the library
    p = min(plain() for _ in range(reps))
    print(f"{dim} n_per_a={n} growth={g} P{order}: {m.ndofs} DOFs, one linear solve {p:.3f} s CPU", flush=True)
    for w in (float(x) for x in windows.split(",")):
        D.SCHUR_WINDOW = w
        for alg, pen in (("ssn", None), ("family-p", "exp-met1")):
            best = float("inf")
            for _ in range(reps):
                m.clear_factorization()
                c = time.process_time()
                s = solve(prob, alg, pen, linear_solver="mkl-pardiso")
                best = min(best, time.process_time() - c)
            print(f"  window {w}: {alg}/{pen} {best:.3f} s CPU, ratio {best / p:.3f}, solves {s.result.linear_solves}, "
                  f"candidates {s.extra['candidates']}", flush=True)
        m.clear_factorization()
        dc = D.DiscreteContact(prob, linear_solver="mkl-pardiso")
        print(f"  window {w}: Schur block {dc._schur_kw['schur'].size} DOFs, candidates outside it "
              f"{int((~dc._schur[2][dc.cand]).sum())}", flush=True)
    print(f"one linear solve after: {min(plain() for _ in range(reps)):.3f} s CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
