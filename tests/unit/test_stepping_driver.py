"""The one load-stepping driver (:func:`alcontact.contact.stepping._steps.step_through`) and the one step-record
shape (:class:`~alcontact.contact.solution._records.Frame`) of the three stepped solves.

The driver is exercised with scripted attempts whose outcome depends only on the increment, so the
cut-back schedule is known exactly; the solvers on the smallest problems that reach each path.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from alcontact.contact import (ContactProblem, FiniteFrictionSolution, LoadHistory, Ramp, Support, obstacles,
                               solve_finite, solve_finite_friction, solve_friction)
from alcontact.contact.stepping import Attempt, step_through
from alcontact.contact.solution import Frame
from alcontact.errors import ConvergenceError, InputError, InvertedElementError
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.problems import friction as fp
from alcontact.status import Status


class _Scripted:
    """Attempts that fail when the increment from the last committed time exceeds ``limit``."""

    def __init__(self, limit=np.inf, status=Status.NEWTON_FAILED):
        self.limit, self.status = limit, status
        self.t = 0.0
        self.tried: list[float] = []
        self.committed: list[float] = []

    def attempt(self, t):
        self.tried.append(t)
        if t - self.t > self.limit + 1e-12:
            return Attempt(False, self.status, "too far", newton=5, outer=1, linear_solves=5)
        return Attempt(True, Status.CONVERGED, "ok", newton=2, outer=1, linear_solves=2, value=t)

    def commit(self, t, att, rec):
        self.t = t
        self.committed.append(t)
        return rec


def test_steps_without_failure_are_the_requested_times():
    s = _Scripted()
    run = step_through((0.5, 1.0), s.attempt, s.commit)
    assert run.success and run.status == Status.CONVERGED and run.cutbacks == 0
    assert [r.t for r in run.records] == [0.5, 1.0] and all(r.requested for r in run.records)
    assert [r.index for r in run.records] == [0, 1]
    assert run.newton_iterations == 4 and run.linear_solves == 4 and run.outer_iterations == 2


def test_cut_back_retries_the_failed_time_after_the_smaller_step():
    """Increment limit 0.3 from t = 0 to 1 with halving: 1 and 0.5 fail, 0.25 and 0.5 pass, 1 fails again
    (increment 0.5), 0.75 and 1 pass: four accepted steps, three failed tries, the counters of the failed
    tries charged to the step that follows them."""
    s = _Scripted(limit=0.3)
    run = step_through((1.0,), s.attempt, s.commit, max_cutbacks=3)
    assert run.success, run.message
    assert s.tried == [1.0, 0.5, 0.25, 0.5, 1.0, 0.75, 1.0]
    assert [r.t for r in run.records] == [0.25, 0.5, 0.75, 1.0]
    assert [r.requested for r in run.records] == [False, False, False, True]
    assert [r.cutbacks for r in run.records] == [2, 0, 1, 0]
    assert [r.step_cutbacks for r in run.records] == [2, 2, 3, 3]
    assert [r.newton_iterations for r in run.records] == [12, 2, 7, 2]
    assert run.cutbacks == 3 and run.newton_iterations == 4 * 2 + 3 * 5


def test_failure_at_the_smallest_increment_is_reported_with_advice(caplog):
    """Every try fails: max_cutbacks = 2 allows the increments 1, 1/2, 1/4; the third failure ends the run
    with the attempt's status, a warning naming it and a message with the step, the reason and the advice."""
    s = _Scripted(limit=0.0, status=Status.MAXITER)
    with caplog.at_level(logging.WARNING):
        run = step_through((1.0,), s.attempt, s.commit, max_cutbacks=2, what="scripted",
                           advice="use more load steps")
    assert s.tried == [1.0, 0.5, 0.25]
    assert run.status == Status.MAXITER and not run.success and run.cutbacks == 3 and not run.records
    assert "t=0.25" in run.message and "smallest increment" in run.message and "too far" in run.message
    assert run.message.endswith("use more load steps")
    assert any(r.levelno == logging.WARNING and "maxiter" in r.getMessage() for r in caplog.records)


def test_final_failure_stops_without_cut_backs_and_commit_can_stop_the_run():
    def final(t):
        return Attempt(False, Status.UNBOUNDED, "slides away", final=True)

    run = step_through((0.5, 1.0), final, lambda t, a, r: r)
    assert run.status == Status.UNBOUNDED and run.message == "slides away" and run.cutbacks == 0

    class Bad:
        status, message = Status.NOT_VERIFIED, "fails the Coulomb check"

    s = _Scripted()
    run = step_through((0.5, 1.0), s.attempt, lambda t, a, r: Bad())
    assert run.status == Status.NOT_VERIFIED and run.message == "fails the Coulomb check"
    assert len(run.records) == 1  # the step is recorded, the next one is not tried


def test_recoverable_exceptions_are_failed_tries_and_bad_arguments_are_refused():
    calls = []

    def attempt(t):
        calls.append(t)
        if len(calls) == 1:
            raise InvertedElementError("element 3 inverted")
        return Attempt(True)

    run = step_through((1.0,), attempt, lambda t, a, r: r)
    assert run.success and calls == [1.0, 0.5, 1.0] and run.records[0].cutbacks == 1
    s = _Scripted()
    with pytest.raises(InputError, match="max_cutbacks"):
        step_through((1.0,), s.attempt, s.commit, max_cutbacks=-1)
    with pytest.raises(InputError, match="cutback_factor"):
        step_through((1.0,), s.attempt, s.commit, factor=1.0)


def test_before_step_and_on_step_hooks():
    s = _Scripted(limit=0.3)
    seen, before = [], []
    step_through((0.5, 1.0), s.attempt, s.commit, on_step=lambda rec: seen.append(rec.t),
                 before_step=lambda k, t, n: before.append((k, t, n)))
    assert before == [(0, 0.5, 2), (1, 1.0, 2)]
    assert seen == s.committed == [0.25, 0.5, 0.75, 1.0]


# --------------------------------------------------------------------------- the solvers on the driver
MAT = Material(E=1000.0, nu=0.3, plane="strain")


def _block(friction=0.0):
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2)
    return ContactProblem(Hyperelastic(mesh, MAT), obstacles.HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0)),
                          "bottom", supports=(Support("top"),), kinematics="finite", friction=friction)


def _path(t):
    return np.array([0.3 * max(t - 0.5, 0.0), 0.1 * min(t / 0.5, 1.0)])


def _check_frames(sol, frictional):
    frames = sol.frames
    assert len(frames) == len(sol.steps) > 0 and all(isinstance(f, Frame) for f in frames)
    m = frames[0].pressure.shape[0]
    for f, st in zip(frames, sol.steps):
        assert f.t == st.t and f.u.shape == (sol.steps[0].u.shape[0],) and f.gap.shape == (m,)
        np.testing.assert_array_equal(f.force, np.asarray(st.force))
        assert f.newton_iterations == st.newton_iterations and f.cutbacks == st.cutbacks
        assert (f.state is not None and f.slip is not None) == frictional
    np.testing.assert_array_equal(sol.times, [f.t for f in frames])
    np.testing.assert_array_equal(sol.normal_forces, [f.normal_force for f in frames])
    assert sol.tangential_forces.shape == (len(frames), frames[0].force.shape[0])


def test_the_three_stepped_solutions_share_the_frame_shape():
    """Small-deformation friction, finite frictionless and finite frictional solves give the same
    per-step frame (time, u, pressure, gap, force, counters; slip and state where frictional)."""
    prob, hist = fp.block_on_plane(dim=2, n=4)
    fr = solve_friction(prob, hist, steps=2)
    assert fr.success, fr.message
    _check_frames(fr, True)
    fin = solve_finite(_block(), "ssn", steps=2, obstacle_path=lambda t: np.array([0.0, 0.1 * t]))
    assert fin.success, fin.message
    _check_frames(fin, False)
    np.testing.assert_allclose(fin.frames[-1].u, fin.u, rtol=0, atol=0)
    assert fin.frames[-1].normal_force == pytest.approx(float(np.sum(fin.solution.weights * fin.solution.pressure)))
    ff = solve_finite_friction(_block(), 0.3, "ssn", steps=(0.5, 1.0), obstacle_path=_path)
    assert ff.success, ff.message
    _check_frames(ff, True)


def test_solve_friction_dispatches_finite_kinematics():
    """``solve_friction`` of a ``kinematics="finite"`` problem is ``solve_finite_friction`` with the
    problem's coefficient (same forces and displacement: the same arithmetic, to 1e-14 relative)."""
    problem = _block(friction=0.3)
    steps = (0.5, 1.0)
    seen = []
    a = solve_friction(problem, None, "ssn", steps=steps, obstacle_path=_path,
                       on_step=lambda k, t, n: seen.append((k, t, n)))
    b = solve_finite_friction(problem, 0.3, "ssn", steps=steps, obstacle_path=_path)
    assert isinstance(a, FiniteFrictionSolution) and a.success, a.message
    assert seen == [(0, 0.5, 2), (1, 1.0, 2)]
    np.testing.assert_allclose(a.forces, b.forces, rtol=1e-14, atol=1e-14 * np.abs(b.forces).max())
    np.testing.assert_allclose(a.u, b.u, rtol=0, atol=1e-14 * np.abs(b.u).max())
    assert np.any(np.abs(a.tangential_forces[:, 0]) > 0)  # the plane drags the block


def test_solve_friction_refuses_what_the_kinematics_cannot_do():
    prob, hist = fp.block_on_plane(dim=2, n=4)
    with pytest.raises(InputError, match="obstacle_path.*kinematics='finite'"):
        solve_friction(prob, hist, obstacle_path=lambda t: np.zeros(2))
    ramped = LoadHistory((), (0.5, 1.0), Ramp((0.0, 1.0), (0.0, 1.0)))
    with pytest.raises(InputError, match="friction amplitude"):
        solve_friction(_block(friction=0.3), ramped)


def test_a_failed_finite_friction_run_raises_on_request():
    """Every try limited to one outer (multiplier) iteration, no cut-back allowed: a negative status, and
    ``raise_for_status`` raises with the message (the steps reached so far are kept: none)."""
    ff = solve_finite_friction(_block(), 0.3, "simo-laursen", steps=(1.0,), obstacle_path=_path, maxiter=1,
                               max_cutbacks=0)
    assert ff.status < 0 and not ff.steps and "smallest increment" in ff.message
    with pytest.raises(ConvergenceError, match="use more load steps"):
        ff.raise_for_status()
