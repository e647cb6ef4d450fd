r"""Coulomb friction at finite deformation (:func:`alcontact.contact.solve_finite_friction`).

Three references (plane strain, neo-Hookean bodies, E = 1000, nu = 0.3):

1. *Sliding block*: a unit block, top clamped, is pressed by 20 % (large strain) onto a
   rigid plane that is then moved sideways by 0.5, far beyond the stick limit. Coulomb's
   law: once every contact point slips, the tangential reaction equals mu times the normal
   reaction. The AL stopping test bounds the multiplier change by ``tol_multiplier`` p_max,
   and a slipping point carries |t_T| = mu lambda_N, so
   | |T| - mu N | <= mu tol_multiplier p_max sum(w) (round-off on top: factor 1.01).
   Before the limit (small sideways motion) every point sticks and |T| < mu N. The same
   for Algorithm 6.2, Algorithm 6.4 and the Alart-Curnier semi-smooth Newton reference
   (whose bound is tighter: it solves the complementarity exactly).
2. *mu -> 0*: with mu = 1e-9 the frictional solution is the frictionless finite-deformation
   one (:func:`alcontact.contact.solve_finite`): both solvers stop at relative tolerances
   1e-8 and friction changes the state by O(mu), so displacements and contact forces agree
   to 1e-6 relative.
3. *Ironing with friction*: a rigid cylinder pressed into a block and translated; energy
   balance of the sliding phase: work of the indenter's horizontal force on the body
   (trapezoidal rule over the load steps) = frictional dissipation
   sum_i w_i t_T,i . Delta s_T,i + change of the stored energy within 1 %. (The
   trapezoidal balance error converges with the step: -3.5 %, -0.55 %, -0.06 % for 8, 16,
   32 slide steps on this mesh; 20 steps are used: +0.08 %.)
4. *AL vs reference*: Algorithm 6.2 and the Alart-Curnier semi-smooth Newton solve the
   same time-discrete law; on the frictional ironing their displacements and contact
   forces agree to 1e-6 relative (the AL stops at relative tolerances 1e-8).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import ContactProblem, FrictionOptions, Ramp, Support, obstacles, solve_finite
from alcontact.contact import solve_finite_friction
from alcontact.contact.laws import OPEN, SLIP, STICK
from alcontact.errors import InputError, UnknownNameError
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic

MAT = Material(E=1000.0, nu=0.3, plane="strain")


def _block():
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    return ContactProblem(Hyperelastic(mesh, MAT), obstacles.HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0)),
                          "bottom", supports=(Support("top"),), kinematics="finite")


def _block_path():
    press = Ramp((0.0, 0.5), (0.0, 0.2), hold_after=True)
    slide = Ramp((0.5, 1.0), (0.0, 0.5))
    times = list(np.linspace(0.0, 0.5, 5)[1:]) + list(np.linspace(0.5, 1.0, 6)[1:])
    return times, (lambda t: np.array([slide(t), press(t)]))


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn"])
def test_block_slides_with_mu_times_normal_force(algorithm):
    """Reference 1 (module doc): |T| = mu N within mu tol_multiplier p_max sum(w) once all points slip."""
    mu = 0.3
    times, path = _block_path()
    fs = solve_finite_friction(_block(), mu, algorithm, steps=times, obstacle_path=path)
    assert fs.success, fs.message
    opts = FrictionOptions()
    first_slide = fs.steps[4]  # t = 0.6: plane moved by 0.05, below the stick limit
    assert np.all(first_slide.states[first_slide.states != OPEN] == STICK)
    assert np.linalg.norm(first_slide.tangential_force) < mu * first_slide.normal_force
    last = fs.steps[-1]
    closed = last.states != OPEN
    assert np.sum(closed) >= 4 and np.all(last.states[closed] == SLIP)
    T = last.tangential_force
    assert T[0] > 0  # the plane moves to +x and drags the block along
    assert abs(T[1]) <= 1e-12 * abs(T[0])  # tangent to the plane
    bound = mu * opts.tol_multiplier * float(np.max(fs.pressure)) * float(np.sum(fs.extra["weights"]))
    assert abs(np.linalg.norm(T) - mu * last.normal_force) <= 1.01 * bound
    assert last.normal_force > 0.2 * 1000.0 * 0.2  # large strain: the normal force is substantial


def _ironing(slide_to: float):
    mesh = meshes.rectangle(0.0, 2.0, 0.0, 0.5, 20, 4)
    radius = 0.5
    problem = ContactProblem(Hyperelastic(mesh, MAT), obstacles.Circle(center=(0.5, 0.5 + radius), radius=radius),
                             "top", supports=(Support("bottom"),), kinematics="finite")
    press = Ramp((0.0, 0.2), (0.0, -0.05), hold_after=True)
    slide = Ramp((0.2, 1.0), (0.0, slide_to))
    return problem, (lambda t: np.array([slide(t), press(t)]))


def test_mu_to_zero_is_frictionless():
    """Reference 2 (module doc): mu = 1e-9 reproduces solve_finite to 1e-6 relative (u and forces)."""
    problem, path = _ironing(0.4)
    times = list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, 5)[1:])
    f0 = solve_finite(problem, "simo-laursen", steps=times, obstacle_path=path)
    f1 = solve_finite_friction(problem, 1e-9, steps=times, obstacle_path=path)
    assert f0.success and f1.success, (f0.message, f1.message)
    assert np.max(np.abs(f1.u - f0.u)) <= 1e-6 * np.max(np.abs(f0.u))
    assert np.max(np.abs(f1.forces - f0.forces)) <= 1e-6 * np.max(np.abs(f0.forces))


def test_ironing_energy_balance():
    """Reference 3 (module doc): W_horizontal = dissipation + change of stored energy within 1 %."""
    problem, path = _ironing(0.4)
    n_press = 3
    times = list(np.linspace(0.0, 0.2, n_press + 1)[1:]) + list(np.linspace(0.2, 1.0, 21)[1:])
    fs = solve_finite_friction(problem, 0.3, steps=times, obstacle_path=path)
    assert fs.success, fs.message
    F = fs.forces
    c = np.array([s.offset for s in fs.steps])
    k0 = int(np.flatnonzero(np.isclose(fs.times, 0.2))[0])  # end of the pressing phase (cut-backs add steps)
    work = sum(0.5 * (F[k, 0] + F[k + 1, 0]) * (c[k + 1, 0] - c[k, 0]) for k in range(k0, len(F) - 1))
    stored = fs.steps[-1].stored_energy - fs.steps[k0].stored_energy
    dissipation = sum(s.dissipation for s in fs.steps[k0 + 1:])
    assert dissipation > 0.9 * work > 0  # friction dominates: the balance is not trivially met by stored energy
    assert abs(work - dissipation - stored) <= 1e-2 * abs(work)
    assert all(s.dissipation >= -1e-9 * dissipation for s in fs.steps)  # >= 0 up to round-off


def test_bad_input_names_the_way_out():
    problem = _block()
    with pytest.raises(InputError, match="mu"):
        solve_finite_friction(problem, -0.1)
    with pytest.raises(UnknownNameError):
        solve_finite_friction(problem, 0.3, "no-such-algorithm")
    with pytest.raises(InputError, match="family-p"):
        solve_finite_friction(problem, 0.3, "simo-laursen", penalty="exp-met1")


def test_al_matches_semismooth_reference_on_ironing():
    """Reference 4 (module doc): Algorithm 6.2 = Alart-Curnier SSN to 1e-6 relative (u and forces)."""
    problem, path = _ironing(0.4)
    times = list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, 5)[1:])
    fa = solve_finite_friction(problem, 0.3, "simo-laursen", steps=times, obstacle_path=path)
    fr = solve_finite_friction(problem, 0.3, "ssn", steps=times, obstacle_path=path)
    assert fa.success and fr.success, (fa.message, fr.message)
    ta, tr = fa.times, fr.times
    common = [i for i, t in enumerate(tr) if np.any(np.isclose(ta, t))]
    fa_at = np.array([fa.forces[int(np.flatnonzero(np.isclose(ta, tr[i]))[0])] for i in common])
    assert np.max(np.abs(fa_at - fr.forces[common])) <= 1e-6 * np.max(np.abs(fr.forces))
    assert np.max(np.abs(fa.u - fr.u)) <= 1e-6 * np.max(np.abs(fr.u))
    assert np.any(fr.steps[-1].states == SLIP)  # the comparison covers sliding points
