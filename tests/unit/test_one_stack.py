"""Issue 9, one stack: one options type, one algorithm registry, one contact setup for friction.

* ``ContactOptions`` carries the frictional options; ``FrictionOptions`` is the same type under
  its old name (only its messages differ) and every solver takes either.
* The automatic Newton options take the defaults of the algorithm's registry entry, so each
  algorithm keeps its former behaviour (1e-12 / 60 frictionless, 1e-11 / 200 with friction).
* One registry holds the frictionless, frictional and finite-deformation algorithms with what
  they support; ``alcontact list`` and the problem-file checks read it.

Reaches inside the package: the option merge of the algorithm registry
(``contact.algorithms._frictionless.options_with``) is checked directly (no public name).
"""

from __future__ import annotations

import dataclasses

import pytest
from typer.testing import CliRunner

from alcontact import linalg
from alcontact.cli import app
from alcontact.contact import ContactOptions, FrictionOptions, solve, solve_friction
from alcontact.contact.algorithms import Algorithm, algorithms, find_algorithm, friction_only_options, register, run_al
from alcontact.contact.algorithms._frictionless import options_with
from alcontact.errors import InputError, UnknownNameError
from alcontact.io import schema
from alcontact.io.config import load_problem_text
from alcontact.io.schema import declarations
from alcontact.problems import friction as fp
from alcontact.problems.blocks import patch_block


def test_friction_options_is_contact_options_under_its_old_name():
    """Same fields, declarations and defaults; only the word in messages differs."""
    assert issubclass(FrictionOptions, ContactOptions)
    assert declarations(FrictionOptions) == declarations(ContactOptions)
    assert dataclasses.asdict(FrictionOptions()) == dataclasses.asdict(ContactOptions())
    with pytest.raises(InputError, match="friction option radius"):
        FrictionOptions(radius="disc")
    with pytest.raises(InputError, match="contact option radius"):
        ContactOptions(radius="disc")


def test_friction_only_fields_are_declared_as_such():
    only = set(friction_only_options())
    assert only == {"eps_t", "tangential_scale", "tol_slip", "max_cutbacks", "cutback_factor", "eta_floor",
                    "margin", "radius", "multiplier_update"}
    for opt in declarations(ContactOptions):
        assert opt.doc.startswith(("Friction:", "Friction,")) == (opt.name in only), opt.name


@pytest.mark.parametrize("friction,kinematics,tol,iters", [
    (False, "small", 1e-12, 60), (False, "finite", 1e-12, 60),
    (True, "small", 1e-11, 200), (True, "finite", 1e-11, 200),
])
def test_automatic_newton_options_take_the_entry_defaults(friction, kinematics, tol, iters):
    """The former defaults of ContactOptions (frictionless) and FrictionOptions (frictional), exactly."""
    entry = find_algorithm("simo-laursen", friction=friction, kinematics=kinematics)
    opts = options_with(None, ContactOptions, {}, "contact", entry)
    assert (opts.newton_tol, opts.maxiter_newton) == (tol, iters)
    given = options_with({"newton_tol": 1e-9}, ContactOptions, {"maxiter_newton": 7}, "contact", entry)
    assert (given.newton_tol, given.maxiter_newton) == (1e-9, 7)


def test_every_solver_takes_either_class():
    prob, hist = fp.block_on_plane(dim=2, n=2)
    a = solve_friction(prob, hist, options=ContactOptions(maxiter=1, max_cutbacks=0))
    b = solve_friction(prob, hist, options=FrictionOptions(maxiter=1, max_cutbacks=0))
    assert a.status == b.status and a.outer_iterations == b.outer_iterations
    sol = solve(patch_block(2, 1, n=2), options=FrictionOptions(maxiter=3))
    assert sol.result.outer_iterations <= 3


def test_unknown_friction_option_keeps_its_kind():
    prob, hist = fp.block_on_plane(dim=2, n=2)
    with pytest.raises(UnknownNameError, match="unknown friction option 'radiuss'. Did you mean 'radius'"):
        solve_friction(prob, hist, radiuss="traction")


def test_registry_holds_every_family_and_what_it_supports():
    keys = {e.key for e in algorithms()}
    for name in ("simo-laursen", "family-p", "ssn"):
        for friction in (False, True):
            for kin in ("small", "finite"):
                assert (name, friction, kin) in keys
    assert ("penalty", True, "small") not in keys  # no frictional pure penalty
    small = find_algorithm("ssn")
    assert "amg" in small.linear_solvers and small.penalty == "none"
    assert find_algorithm("family-p", friction=True).penalty is None


def test_registry_lookup_names_the_family():
    with pytest.raises(UnknownNameError, match="unknown friction algorithm 'penalty'.*Known friction algorithms: "
                                               "family-p, log-barrier, simo-laursen, ssn"):
        find_algorithm("penalty", friction=True)
    with pytest.raises(UnknownNameError, match="finite-deformation friction algorithm 'simo-laursn'"):
        find_algorithm("simo-laursn", friction=True, kinematics="finite")


def test_register_checks_what_an_entry_declares():
    with pytest.raises(ValueError, match="kinematics"):
        register(Algorithm("x", run_al, "doc", kinematics="large"))
    with pytest.raises(ValueError, match="linear-solver paths"):
        register(Algorithm("x", run_al, "doc", linear_solvers=("gmres",)))
    assert ("x", False, "large") not in {e.key for e in algorithms()}


def test_a_linear_solver_path_an_entry_lacks_is_refused():
    """An approximate solver (``SolverChoice.exact`` False) is refused by an entry that declares no path for
    one, whatever its name: the finite-deformation frictionless ``ssn`` (saddle-point systems) refuses ``"amg"``
    and a user-registered iterative solver alike, naming the way out. The finite-deformation frictional entries
    declare ``factor-gmres`` (the approximate solver's factors precondition GMRES; run and compared with the
    direct answer in ``test_registered_solver_runs``); the small-kinematics ones ``amg`` since issue 9/10."""
    from alcontact import linalg
    from alcontact.contact import solve_finite
    from alcontact.problems.half_cylinder import half_cylinder

    linalg.register_solver("test-approximate", linalg.AMGSolver, kind="iterative")
    try:
        for name in ("amg", "test-approximate"):
            with pytest.raises(InputError, match=f"linear_solver = '{name}'.*algorithm 'ssn' has no AMG path.*'direct'"):
                solve_finite(half_cylinder(2), "ssn", steps=1, linear_solver=name)
    finally:
        linalg.unregister_solver("test-approximate")
    for name in ("simo-laursen", "family-p", "ssn"):
        assert "amg" in find_algorithm(name, friction=True).linear_solvers
        assert find_algorithm(name, friction=True, kinematics="finite").linear_solvers == ("direct", "factor-gmres")


def test_direct_only_algorithms_take_a_direct_backend():
    """``linear_solver`` reaches the frictional factorization (same result with any direct backend).

    Reference: the run with the default backend; tolerance relative 1e-10 on the normal force
    (two direct factorizations of the same matrix).
    """
    prob, hist = fp.block_on_plane(dim=2, n=2)
    a = solve_friction(prob, hist, linear_solver="superlu")
    b = solve_friction(prob, hist)
    assert a.success and b.success
    assert a.extra["linear_solver"] == "superlu" and b.extra["linear_solver"] == linalg.choose_solver(2, prob.model.ndofs)
    assert abs(a.steps[-1].normal_force - b.steps[-1].normal_force) <= 1e-10 * abs(b.steps[-1].normal_force)


def test_list_reads_the_registry():
    result = CliRunner().invoke(app, ["list", "friction-algorithms"])
    assert result.exit_code == 0
    out = " ".join(result.output.split())
    for e in algorithms(friction=True):
        assert e.name in out
    # the AMG path of issue 9/10 at small kinematics; approximate solvers precondition GMRES at finite ones
    assert "[small: direct, amg; finite: direct, factor-gmres]" in out


def _friction_file(solver: str = "", friction_table: str = "") -> str:
    text = schema._EXAMPLE
    assert "[solver]\n" in text
    text = text.replace("[solver]\n", "[solver]\n" + solver, 1)
    return text + ("\n[solver.friction]\n" + friction_table if friction_table else "")


@pytest.mark.parametrize("solver,table", [('radius = "traction"\n', ""), ("", 'radius = "traction"\n'),
                                          ('radius = "traction"\n', 'radius = "traction"\n')])
def test_friction_only_keys_in_either_table_reach_the_frictional_run(solver, table):
    setup = load_problem_text(_friction_file(solver, table))
    assert setup.friction_options["radius"] == "traction"
    assert "radius" not in setup.options  # the frictionless runs do not get them


def test_friction_only_key_set_differently_in_both_tables_is_an_issue():
    from alcontact.errors import ConfigError

    with pytest.raises(ConfigError, match=r"solver.friction.margin = 0.75: solver.margin = 0.5 says otherwise"):
        load_problem_text(_friction_file("margin = 0.5\n", "margin = 0.75\n"))
