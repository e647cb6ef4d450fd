"""One ``contact.solve`` for every case, one ``ContactSolution`` with per-step ``ContactFrame`` frames.

Each case is checked against the stepping engine it dispatches to (reached through the
former entry points, now deprecated wrappers returning the engine's record, each checked to
warn with a DeprecationWarning that names ``contact.solve``): the frames
hold the engine's per-step states exactly (same arrays, tolerance 0), the tangential
traction in the one global ``(m, d)`` convention, and the decision of what runs follows
the problem (kinematics, friction coefficient). Tiny meshes: a few seconds in all.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact import contact
from alcontact.contact import (ContactFrame, ContactProblem, ContactSolution, LoadCase, LoadHistory, Pressure, Ramp,
                               Support, problem_at, solve)
from alcontact.contact.obstacles import HalfSpace
from alcontact.errors import InputError
from alcontact.fem import Hyperelastic, Material, meshes
from alcontact.problems import friction as fp
from alcontact.problems.blocks import patch_block

OPEN, STICK, SLIP = 0, 1, 2


def _finite_problem(friction: float = 0.0):
    """A 1 x 1 neo-Hookean block pushed 1 % onto a plane (finite kinematics)."""
    body = Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2), Material(E=1000.0, nu=0.3))
    return ContactProblem(model=body, obstacle=HalfSpace((0.0, 0.0), (0.0, 1.0)), contact_boundary="bottom",
                          supports=[Support("top", (1,), -0.01), Support("left", (0,))], kinematics="finite",
                          friction=friction)


def _same_frame_as_view(fr: ContactFrame, view: ContactSolution) -> None:
    np.testing.assert_array_equal(fr.u, view.u)
    np.testing.assert_array_equal(fr.pressure, view.pressure)
    np.testing.assert_array_equal(fr.gap, view.gap)
    np.testing.assert_array_equal(fr.contact_force, view.total_contact_force)
    assert fr.normal_force == view.normal_force


def test_static_solve_is_a_solution_with_one_frame():
    prob = patch_block(2, 1, n=2)
    sol = solve(prob)
    assert sol.result.success and len(sol.frames) == 1 and sol.record is None
    fr = sol.final
    assert fr.t == 1.0 and fr.requested and fr.status == sol.result.status
    _same_frame_as_view(fr, sol)
    m, d = sol.points.shape
    # frictionless: no tangential traction or slip; a closed point slides freely (SLIP), the rest is OPEN
    assert fr.traction_t.shape == (m, d) and not np.any(fr.traction_t) and not np.any(fr.slip)
    np.testing.assert_array_equal(fr.state, np.where(sol.active, SLIP, OPEN))
    assert (fr.newton_iterations, fr.outer_iterations, fr.linear_solves) == (
        sol.result.newton_iterations, sol.result.outer_iterations, sol.result.linear_solves)
    # the reaction force is the support reaction of the global balance F_c + F_ext + R = 0
    eq = sol.equilibrium()
    np.testing.assert_array_equal(fr.reaction_force, eq.reaction)
    assert eq.residual < 1e-8
    # a copy made by dataclasses.replace carries its own state as its frame
    other = dataclasses.replace(sol, u=2 * sol.u)
    np.testing.assert_array_equal(other.final.u, 2 * sol.u)


def test_frictionless_history_gives_one_independent_solve_per_step_time():
    prob = patch_block(2, 1, n=2)
    hist = LoadHistory((LoadCase(Pressure("top", 1.0), Ramp((0.0, 1.0), (0.0, 1.0))),), (0.5, 1.0))
    calls = []
    sol = solve(prob, history=hist, on_step=lambda done, total, t: calls.append((done, total, t)))
    assert [f.t for f in sol.frames] == [0.5, 1.0]
    assert calls == [(0, 2, 0.5), (1, 2, 0.5), (1, 2, 1.0), (2, 2, 1.0)]
    for fr, t in zip(sol.frames, hist.times):  # path independent: each step is the static solve of its loads
        ref = solve(problem_at(prob, hist, t))
        np.testing.assert_array_equal(fr.u, ref.u)
        np.testing.assert_array_equal(fr.pressure, ref.pressure)
    np.testing.assert_array_equal(sol.u, sol.frames[-1].u)
    assert len(sol.frame_solutions()) == 2 and sol.frame_solutions()[-1] is sol


def test_friction_is_decided_by_the_problem_and_frames_hold_the_engine_steps():
    prob, hist = fp.block_on_plane(dim=2, n=4)
    assert prob.friction > 0
    sol = solve(prob, history=hist)
    with pytest.warns(DeprecationWarning, match=r"solve_friction is deprecated.*contact\.solve\(problem, history="):
        rec = contact.solve_friction(prob, hist)  # the wrapper: the engine's own record
    assert isinstance(rec, contact.FrictionSolution) and isinstance(sol.record, contact.FrictionSolution)
    assert len(sol.frames) == len(rec.steps) > 1
    # per step; the run's total also counts the set-up solves (the stiffness condensed on the contact points)
    assert 0 < sum(f.linear_solves for f in sol.frames) <= rec.linear_solves
    for fr, st in zip(sol.frames, rec.steps):
        assert fr.t == st.t
        np.testing.assert_array_equal(fr.u, st.u)
        np.testing.assert_array_equal(fr.pressure, st.pressure)
        # the one convention: global (m, d) tangential traction on the body = the step's shear (-T t_T);
        # the engine's own traction_t is (m, d-1) in the local tangent bases
        assert fr.traction_t.shape == st.shear.shape != st.traction_t.shape
        np.testing.assert_array_equal(fr.traction_t, st.shear)
        np.testing.assert_array_equal(fr.slip, st.slip)
        np.testing.assert_array_equal(fr.slip_total, st.slip_total)
        np.testing.assert_array_equal(fr.state, st.state)
        np.testing.assert_array_equal(fr.tangential_force, st.tangential_force)
        assert (fr.newton_iterations, fr.outer_iterations, fr.linear_solves) == (
            st.newton_iterations, st.outer_iterations, st.linear_solves)
        # each frame's problem carries the history's loads at its time: its reaction closes the balance
        assert np.allclose(fr.reaction_force, rec.equilibrium(st).reaction, rtol=1e-12, atol=1e-12)
    assert np.any(sol.final.state == STICK) or np.any(sol.final.state == SLIP)
    # friction=0 overrides the problem's coefficient: the frictionless path runs (one static solve per step)
    free = solve(prob, history=hist, friction=0.0)
    assert free.record is None and not np.any(free.final.traction_t)
    ref = solve(problem_at(prob, hist, hist.times[-1])).u
    np.testing.assert_allclose(free.u, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_frictional_problem_without_history_is_one_step_of_its_own_loads():
    prob, _ = fp.block_on_plane(dim=2, n=4, strain=0.01)
    sol = solve(prob)
    assert len(sol.frames) == 1 and isinstance(sol.record, contact.FrictionSolution)
    assert sol.record.history.times == (1.0,)


def test_finite_deformation_frames_are_the_accepted_load_steps():
    prob = _finite_problem()
    sol = solve(prob, steps=2)
    with pytest.warns(DeprecationWarning, match=r"solve_finite is deprecated.*contact\.solve\(problem, steps="):
        rec = contact.solve_finite(prob, steps=2)
    assert isinstance(sol.record, contact.FiniteSolution) and sol.result.success
    assert [f.t for f in sol.frames] == [s.t for s in rec.steps] == [0.5, 1.0]
    for fr, st in zip(sol.frames, rec.steps):
        np.testing.assert_array_equal(fr.u, st.u)
        np.testing.assert_array_equal(fr.pressure, st.pressure)
        assert fr.newton_iterations == st.newton_iterations and fr.linear_solves == st.linear_solves
    assert sum(f.linear_solves for f in sol.frames) == sol.result.linear_solves
    np.testing.assert_array_equal(sol.u, rec.solution.u)
    assert sol.extra["load_steps"] == sol.record.steps


def test_finite_friction_frames_use_the_same_global_convention():
    prob = _finite_problem(friction=0.2)
    sol = solve(prob, steps=2)
    with pytest.warns(DeprecationWarning, match=r"solve_finite_friction is deprecated.*solve\(problem, friction=mu"):
        rec = contact.solve_finite_friction(prob, 0.2, steps=2)
    assert isinstance(sol.record, contact.FiniteFrictionSolution)
    assert len(sol.frames) == len(rec.steps) == 2
    for fr, st in zip(sol.frames, rec.steps):
        np.testing.assert_array_equal(fr.u, st.u)
        # FiniteFrictionStep.traction_t is global with the dissertation's sign: the force on the body is -t_T
        np.testing.assert_array_equal(fr.traction_t, -st.traction_t)
        np.testing.assert_array_equal(fr.state, st.states)


def test_options_reach_the_engine_and_bad_arguments_are_named():
    # max_cutbacks is an argument of the frictionless finite engine (not a ContactOptions field there):
    # its own check names it, so the value reached it
    with pytest.raises(InputError, match="max_cutbacks=-1"):
        solve(_finite_problem(), steps=1, max_cutbacks=-1)
    with pytest.raises(InputError, match="obstacle_path"):
        solve(patch_block(2, 1, n=2), obstacle_path=lambda t: (0.0, 0.0))
    with pytest.raises(InputError, match="on_step"):
        solve(patch_block(2, 1, n=2), on_step=3)
    fine = solve(_finite_problem(), steps=1, max_cutbacks=0)
    assert fine.result.success and len(fine.frames) == 1


def test_the_former_runner_module_re_exports_the_application_package():
    import alcontact.app as app
    import alcontact.runner as runner

    for name in app.__all__:
        assert getattr(runner, name) is getattr(app, name)
