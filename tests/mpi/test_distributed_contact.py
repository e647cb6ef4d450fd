"""Distributed frictionless contact (``contact.solve_distributed``) on 1, 2 and 3 MPI ranks.

Reference: the serial path (``contact.solve`` with the default direct linear solver) on the same
Hertz problems (2D cylinder, 3D sphere; coarse meshes of ``scripts/contact.py``). Tolerance 1e-8
relative for the total contact force (its norm), the peak pressure, the contact extent (the
coordinates of the outermost active points) and the displacement field (max norm), on every rank
count and partition: the direct KSP solves the same systems exactly, CG + GAMG to a relative
residual of 1e-10 (measured: agreement 1e-13 and about 4e-10). Equilibrium of the returned
state: the free-DOF residual of ``K u - f - f_c`` and the global balance (contact force =
reactions + loads) below 1e-8 on every rank count. A partition forced through the contact zone
(element slabs along x inside it) gives the same answer. A rank that fails on bad input stops
every rank with one clear message and a non-zero exit (bounded by the mpirun timeout).

The pure penalty (6.10) ends at a stiffness of about 1e13 here (penetration tolerance 1e-8 h),
where its solution is only as accurate as the conditioning allows: the serial path itself gives
contact forces that differ by 1e-7 relative between its direct and AMG linear solvers (measured:
388.43507586 / -9050.95636114 against 388.43512763 / -9050.9572721). It is compared at 1e-6
(:data:`TOL_OF`), its equilibrium too (its Newton residual stalls at round-off, 2e-9); every
augmented Lagrangian algorithm at 1e-8.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import numpy as np
import pytest

from ._mpi import mpirun

SCRIPT = str(Path(__file__).parent / "scripts" / "contact.py")
TOL = 1e-8
#: tolerance of the comparison with the serial path where the algorithm's own accuracy is lower (module doc)
TOL_OF = {"penalty": 1e-6}

#: the solves of each mpirun (dimension, ranks): every algorithm on one rank, the augmented Lagrangian ones on more
AL_2D = ["simo-laursen:petsc-direct", "family-p:petsc:exp-met1", "ssn:petsc-direct"]
CASES = {(2, 1): AL_2D + ["penalty:petsc-direct"], (2, 2): AL_2D, (2, 3): AL_2D,
         (3, 1): ["simo-laursen:petsc", "family-p:petsc-direct:exp-met1"],
         (3, 2): ["simo-laursen:petsc", "family-p:petsc-direct:exp-met1"], (3, 3): ["family-p:petsc:exp-met1"]}


@functools.cache
def serial(dim: int, algorithm: str, penalty: str | None):
    """The serial solution: (force, peak, extent, u in mesh-node order, newton iterations)."""
    import importlib.util

    from alcontact.contact import solve

    spec = importlib.util.spec_from_file_location("contact_script", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    prob = mod.problem(dim)
    sol = solve(prob, algorithm, penalty)
    assert sol.result.status > 0, sol.result.message
    model = prob.model
    _, dmap = model.all_node_dofs()
    act = sol.active
    extent = np.column_stack([sol.points[act].min(axis=0), sol.points[act].max(axis=0)])
    return sol.total_contact_force, float(sol.pressure.max()), extent, sol.u[dmap], sol.result.newton_iterations


def _run(tmp_path, n: int, dim: int, partition: str, cases, timeout: float = 240.0) -> dict:
    out = tmp_path / f"contact_{dim}d_{n}_{partition}.json"
    proc = mpirun(n, SCRIPT, str(out), str(dim), partition, *cases, timeout=timeout)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return json.loads(out.read_text())


def _rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(b))), 1e-300))


def _check(results: dict, dim: int, ranks: int):
    for case in CASES[dim, ranks]:
        algorithm, _solver, *rest = case.split(":")
        got = results[case]
        assert got["ranks"] == ranks
        assert got["status"] > 0, got["message"]
        force, peak, extent, u, _ = serial(dim, algorithm, rest[0] if rest else None)
        tol = TOL_OF.get(algorithm, TOL)
        assert np.linalg.norm(np.subtract(got["force"], force)) <= tol * np.linalg.norm(force), case
        assert got["peak"] == pytest.approx(peak, rel=tol), case
        assert _rel(got["extent"], extent) <= tol, case
        assert _rel(got["u"], u) <= tol, case
        assert got["residual"] <= tol and got["balance"] <= tol, case  # contact force = reactions + loads
        assert got["extra"]["ranks"] == ranks and got["extra"]["strategy"] == "distributed"
        # the KSP named is the one that ran
        assert got["extra"]["linear_solver"] == _solver
        if _solver == "petsc":  # one GAMG hierarchy for the whole solve, updated (Galerkin) or lagged for a new matrix
            assert got["extra"]["gamg_setups"] == 1, case
            updates, reused = got["extra"]["gamg_updates"], got["extra"]["pc_reused"]
            assert updates > 0 and updates + reused + got["extra"]["pc_lagged"] == got["linear_solves"] - 1, case
            if algorithm == "simo-laursen":  # the piecewise-linear law: the matrix repeats once the active set settles
                assert reused > updates, case
            assert got["extra"]["fine_smoother"] == "pbjacobi", case


@pytest.mark.parametrize("ranks,partition", [(1, "metis"), (2, "metis"), (3, "zone")])
def test_hertz_2d_same_on_every_rank_count(tmp_path, ranks, partition):
    results = _run(tmp_path, ranks, 2, partition, CASES[2, ranks])
    _check(results, 2, ranks)
    if partition == "zone":  # the forced partition cuts through the contact zone
        assert all(r["ranks_with_contact"] >= 2 for r in results.values())


@pytest.mark.parametrize("ranks,partition", [(1, "metis"), (2, "zone"), (3, "metis")])
def test_hertz_3d_same_on_every_rank_count(tmp_path, ranks, partition):
    results = _run(tmp_path, ranks, 3, partition, CASES[3, ranks])
    _check(results, 3, ranks)
    if partition == "zone":
        assert all(r["ranks_with_contact"] >= 2 for r in results.values())


@pytest.mark.parametrize("ranks,case,expect", [
    (2, "fail:rank1", "bad obstacle input on rank 1"),  # the zone partition gives rank 1 contact points
    (3, "fail:tiny", "too small to distribute"),
])
def test_a_rank_that_fails_stops_every_rank(tmp_path, ranks, case, expect):
    out = tmp_path / "fail.json"
    proc = mpirun(ranks, SCRIPT, str(out), "2", "zone", case, timeout=120)
    assert proc.returncode != 0
    errors = [line for line in proc.stderr.splitlines() if line.startswith("error")]
    assert len(errors) == 1, proc.stderr  # one message, from rank 0, for every rank
    assert expect in errors[0] and "failed on rank" in errors[0]
    assert "Traceback" not in proc.stderr
    assert not out.exists()


def test_unknown_linear_solver_is_refused_with_the_choices():
    from alcontact.contact import solve_distributed
    from alcontact.distributed import DistributedError
    from alcontact.problems import hertz

    with pytest.raises(DistributedError, match="'amg' does not run on the distributed path; use 'petsc' or "
                                               "'petsc-direct'"):
        solve_distributed(hertz.hertz_2d(n_per_a=2), options={"linear_solver": "amg"})


def test_distributed_contact_is_a_contact_system():
    """The distributed model satisfies the declared protocol the serial algorithms call (as the serial models do in
    tests/unit/test_contact_system.py): every member present, every method binds the protocol's call, the declared
    capabilities booleans; here on one rank of this process."""
    import inspect

    from alcontact.contact.systems import ContactSystem, DistributedContact
    from alcontact.distributed import world
    from alcontact.problems import hertz

    model = DistributedContact(hertz.hertz_2d(n_per_a=2), comm=world())
    assert isinstance(model, ContactSystem)
    for member, fn in vars(ContactSystem).items():
        if inspect.isfunction(fn) and not member.startswith("_"):
            params = list(inspect.signature(fn).parameters.values())[1:]
            args = [object() for p in params if p.kind == p.POSITIONAL_OR_KEYWORD]
            kwargs = {p.name: object() for p in params if p.kind == p.KEYWORD_ONLY}
            inspect.signature(getattr(model, member)).bind(*args, **kwargs)
    for flag in ("inexact_subproblems", "physical_stopping", "warm_penalty_start", "penalty_continuation",
                 "active_converged"):
        assert isinstance(getattr(model, flag), bool), flag
    assert model.h > 0 and model.cand.dtype.kind == "i" and model.cand.size > 0
    # the candidates' gaps are one array over all of them (replicated), the state the owned displacement
    assert model.gaps(model.start()).shape == model.cand.shape


def _penalties():
    from alcontact.contact import contact_penalties

    return contact_penalties()


@pytest.mark.parametrize("penalty", _penalties())
def test_every_family_p_penalty_runs_on_the_distributed_path(penalty):
    """Algorithm 6.3 with each registered contact penalty (generated from the registry), on one rank of this
    process with the direct KSP: converged, and the serial (condensed, direct) contact force and displacement
    to 1e-8 (measured: 1e-15 to 9e-14)."""
    from alcontact.contact import solve, solve_distributed
    from alcontact.distributed import world
    from alcontact.problems import hertz

    dist = solve_distributed(hertz.hertz_2d(n_per_a=4), "family-p", penalty, {"linear_solver": "petsc-direct"},
                             comm=world())
    ref = solve(hertz.hertz_2d(n_per_a=4), "family-p", penalty)
    assert dist.result.status > 0 and ref.result.status > 0, dist.result.message
    assert dist.result.penalty == penalty
    assert dist.model_contact_force == pytest.approx(float(np.sum(ref.nodal_forces)), rel=TOL)
    _, dmap = ref.problem.model.all_node_dofs()
    u = np.empty_like(ref.u[dmap])
    u[dist.global_nodes] = dist.u.reshape(-1, 2)
    assert _rel(u, ref.u[dmap]) <= TOL


def test_gamg_hierarchy_rebuilt_when_reuse_is_switched_off():
    """The counter of GAMG hierarchies sees what PETSc built: with ``pc_gamg_reuse_interpolation = false`` (a PETSc
    option passed through) every KSP set-up builds new prolongators, so ``gamg_setups`` equals the linear solves,
    and the answer is the one with reuse to 1e-8 (the serial reference of the tests above)."""
    from alcontact.contact import solve_distributed
    from alcontact.distributed import world
    from alcontact.problems import hertz

    reuse = solve_distributed(hertz.hertz_2d(n_per_a=4), comm=world())
    fresh = solve_distributed(hertz.hertz_2d(n_per_a=4), petsc_options={"pc_gamg_reuse_interpolation": "false"},
                              comm=world())
    assert reuse.result.status > 0 and fresh.result.status > 0
    assert reuse.extra["gamg_setups"] == 1
    assert (reuse.extra["gamg_updates"] + reuse.extra["pc_reused"] + reuse.extra["pc_lagged"]
            == reuse.result.linear_solves - 1)
    assert (fresh.extra["gamg_setups"] == fresh.result.linear_solves - fresh.extra["pc_reused"]
            - fresh.extra["pc_lagged"] > 1)
    assert fresh.extra["gamg_updates"] == 0
    assert fresh.model_contact_force == pytest.approx(reuse.model_contact_force, rel=TOL)


def test_lagged_preconditioner_is_the_one_that_ran():
    """``lag_preconditioner``: with it, changed Newton matrices are solved with the last GAMG update's
    preconditioner (``pc_lagged`` > 0, fewer Galerkin updates); without it every changed matrix gets its update
    (``pc_lagged`` = 0). Both give the serial path's contact force to 1e-8 (the reference of the tests above)."""
    from alcontact.contact import solve, solve_distributed
    from alcontact.distributed import world
    from alcontact.problems import hertz

    for algorithm in ("simo-laursen", "family-p"):
        lagged = solve_distributed(hertz.hertz_2d(n_per_a=4), algorithm, comm=world())
        every = solve_distributed(hertz.hertz_2d(n_per_a=4), algorithm, comm=world(), lag_preconditioner=False)
        ref = solve(hertz.hertz_2d(n_per_a=4), algorithm)
        assert lagged.result.status > 0 and every.result.status > 0
        assert lagged.extra["pc_lagged"] > 0 and every.extra["pc_lagged"] == 0, algorithm
        assert lagged.extra["gamg_updates"] < every.extra["gamg_updates"], algorithm
        for sol in (lagged, every):
            assert (sol.extra["gamg_updates"] + sol.extra["pc_reused"] + sol.extra["pc_lagged"]
                    == sol.result.linear_solves - 1)
            assert sol.model_contact_force == pytest.approx(float(np.sum(ref.nodal_forces)), rel=TOL)


@functools.cache
def serial_p2(dim: int):
    """The serial P2 solution (Algorithm 6.1, default solver): force, largest nodal pressure (the multipliers, as
    the distributed path reports them: ``peak_pressure_nodal_max``), u at the scalar DOFs of the model."""
    import importlib.util

    from alcontact.contact import solve

    spec = importlib.util.spec_from_file_location("contact_script", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    sol = solve(mod.problem(dim, order=2), "simo-laursen")
    assert sol.result.status > 0, sol.result.message
    _, dmap = sol.problem.model.all_node_dofs()
    return sol.total_contact_force, float(sol.peak_pressure_nodal_max), sol.u[dmap]


@pytest.mark.parametrize("dim,ranks,partition,solver", [
    (2, 1, "metis", "petsc-direct"), (2, 2, "zone", "petsc"),
    pytest.param(2, 3, "metis", "petsc", marks=pytest.mark.slow),
    pytest.param(3, 2, "metis", "petsc", marks=pytest.mark.slow)])
def test_p2_hertz_same_on_every_rank_count(tmp_path, dim, ranks, partition, solver):
    """P2 elements (edge nodes distributed with their owner rank, the contact points at every P2 node of the
    surface): the serial P2 solve's contact force, largest nodal pressure (2D: the same recovery) and
    displacement at every scalar DOF to 1e-8 (references and tolerance as the module doc); equilibrium to 1e-8."""
    results = _run(tmp_path, ranks, f"{dim}p2", partition, [f"simo-laursen:{solver}"])
    got = results[f"simo-laursen:{solver}"]
    assert got["status"] > 0, got["message"]
    force, peak, u = serial_p2(dim)
    assert np.linalg.norm(np.subtract(got["force"], force)) <= TOL * np.linalg.norm(force)
    if dim == 2:  # 3D P2: the serial pressure is recovered by the boundary mass matrix, the distributed one is
        assert got["peak"] == pytest.approx(peak, rel=TOL)  # the multipliers (DistributedContactSolution doc)
    assert _rel(got["u"], u) <= TOL
    assert got["residual"] <= TOL and got["balance"] <= TOL
    assert got["extra"]["linear_solver"] == solver and got["extra"]["dofs"] == u.size


def test_lagged_preconditioner_that_fails_is_updated(monkeypatch):
    """A lagged solve that fails (CG breaks down with the old preconditioner: forced here) is redone after a
    Galerkin update: counted in ``lag_failures``, and the run still gives the serial path's force to 1e-8."""
    from alcontact.contact import solve, solve_distributed
    from alcontact.contact.systems import _distributed as sysd
    from alcontact.distributed import world
    from alcontact.problems import hertz

    plain = sysd.DistributedContact._ksp_solve

    def failing(self, rhs, rtol, *, lagged=False):
        if lagged:
            self.linear_solves += 1
            raise np.linalg.LinAlgError("forced breakdown")
        return plain(self, rhs, rtol)

    monkeypatch.setattr(sysd.DistributedContact, "_ksp_solve", failing)
    sol = solve_distributed(hertz.hertz_2d(n_per_a=4), comm=world())
    assert sol.result.status > 0, sol.result.message
    assert sol.extra["pc_lagged"] == sol.extra["lag_failures"] > 0
    assert sol.model_contact_force == pytest.approx(float(np.sum(solve(hertz.hertz_2d(n_per_a=4)).nodal_forces)),
                                                    rel=TOL)
