"""Verification: the mixed u-p body in finite-deformation contact (the existing contact path).

Contact acts on the displacement DOFs only; the pressure rows of the mixed body are part of the
body's residual, so every contact algorithm runs unchanged (``contact.solve``), and the solution's
equilibrium check covers the incompressibility rows too (status converged).

1. Consistency at nu = 0.45, where both formulations work: the neo-Hookean half-cylinder
   (P2 on straight-sided triangles, delta/R = 0.4, 10 load steps) with the split law
   ``W = c10 (I1b - 3) + K/2 (J - 1)^2`` (Mooney-Rivlin with c01 = 0, c10 = mu/2) gives the same
   contact force with the mixed and the displacement body up to the discretization error:
   measured relative differences 3.0e-3 (n = 6), 5.1e-4 (n = 12), 9.5e-5 (n = 24); asserted
   below 5e-3 at n = 6 and below 1e-3 and smaller at n = 12.
2. nu = 0.4999 and nu = 0.5 (exactly incompressible): every algorithm converges in 10 load steps
   without cut-back; the augmented Lagrangian algorithms and ssn in at most 8 Newton iterations per
   step (measured 4-7), the pure penalty method in at most 12 (10 in its first step, measured);
   all algorithms give the same force to 1e-6 (the pure penalty to 1e-5, its penetration); at
   nu = 0.5 the constraint rows vanish (the deformed area equals the reference one to 1e-8;
   Taylor-Hood holds J = 1 weakly, not at every point).
   For comparison (not asserted: 86 s), the displacement P2 body at nu = 0.4999 on the same mesh
   (n = 12, simo-laursen) needed 39 cut-backs, up to 195 Newton iterations per step and 2737 linear
   solves; the mixed body 0 cut-backs and 41 linear solves.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact import contact
from alcontact.fem import Hyperelastic, Material, MixedHyperelastic, MooneyRivlin
from alcontact.problems.half_cylinder import half_cylinder

E = 1000.0


def _solve(body, base, algorithm="simo-laursen"):
    sol = contact.solve(dataclasses.replace(base, model=body), algorithm, steps=10)
    assert int(sol.result.status) > 0, sol.result.message
    assert all(int(f.status) > 0 for f in sol.frames)
    return sol


def test_mixed_matches_displacement_at_moderate_nu():
    nu = 0.45
    law = MooneyRivlin(c10=E / (4.0 * (1.0 + nu)))  # mu / 2
    diffs = []
    for n in (6, 12):
        base = half_cylinder(n, order=2, curved=False, nu=nu, delta=0.4)
        f_mixed = _solve(MixedHyperelastic(base.model.mesh, E=E, nu=nu, model=law), base).total_contact_force[1]
        f_disp = _solve(Hyperelastic(base.model.mesh, Material(E, nu, "strain"), order=2, model=law),
                        base).total_contact_force[1]
        diffs.append(abs(f_mixed - f_disp) / f_disp)
    assert diffs[0] < 5e-3 and diffs[1] < 1e-3 and diffs[1] < diffs[0]


@pytest.mark.parametrize("nu", [0.4999, 0.5])
def test_incompressible_half_cylinder_every_algorithm(nu):
    base = half_cylinder(6, order=2, curved=False, nu=0.3, delta=0.4)
    forces = {}
    for algorithm in contact.available_algorithms():
        body = MixedHyperelastic(base.model.mesh, E=E, nu=nu)
        sol = _solve(body, base, algorithm)
        newton = [f.newton_iterations for f in sol.frames]
        assert len(newton) == 10 and sum(f.cutbacks for f in sol.frames) == 0
        assert max(newton) <= (12 if algorithm == "penalty" else 8), (algorithm, newton)
        # the pressure is the multiplier of the weak constraint int (J - 1) q dV = 0 for every P1 q;
        # q = 1 is one of them: the deformed area equals the reference area
        if nu == 0.5:
            area = float(body.scalar_basis.dx.sum())
            rp = body.internal_force(sol.u)[body.ndofs_u:]
            assert abs(rp.sum()) <= 1e-8 * area and np.abs(rp).max() <= 1e-8 * area
        forces[algorithm] = sol.total_contact_force[1]
    ref = forces["ssn"]
    for algorithm, f in forces.items():
        assert abs(f - ref) <= (1e-5 if algorithm == "penalty" else 1e-6) * ref, (algorithm, f, ref)
