"""Property-based fuzz test of the Python API (issue 19): wrong types and shapes give project errors.

Every entry of :data:`ENTRIES` is a public function or class of alcontact with a valid
call on a tiny problem; the property replaces one argument of that call by a value of a
wrong type or shape (``None``, strings, bools, nested or ragged lists, empty arrays,
arrays of the wrong rank, NaN, infinities, huge integers, objects, callables) and
requires the call to succeed or raise :class:`alcontact.errors.AlcontactError` (an
``InputError`` naming the argument): any other exception (``TypeError``,
``AttributeError``, ``IndexError`` from deep inside) is a bug. RuntimeWarnings of
alcontact are errors in the test suite (``pyproject.toml``), so they count too.

:func:`test_every_public_entry_point_is_in_the_table` keeps the table complete: a new
public function or class of the listed modules must be added (or listed in
:data:`NOT_CALLED` with the reason).

``make fuzz`` draws 40,000 examples (``ALCONTACT_FUZZ=1``); the default suite 1,000, and
:func:`test_every_bad_value_of_every_argument` calls every entry with every bad value in
every listed parameter once (deterministic, the whole product).
"""

from __future__ import annotations

import importlib
import inspect
import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from alcontact.errors import AlcontactError

FUZZ = bool(os.environ.get("ALCONTACT_FUZZ"))


def _examples(n: int) -> int:
    return settings.default.max_examples if FUZZ else n


#: wrong types and shapes: (label, value)
BAD_VALUES = [
    ("none", None), ("str", "x"), ("str-number", "1"), ("bool", True), ("int", 3), ("negative", -1),
    ("zero", 0), ("float", 2.5), ("nan", math.nan), ("inf", math.inf), ("-inf", -math.inf),
    ("huge-int", 10**400), ("huge-float", 1e308), ("tiny", 5e-324), ("complex", 1j),
    ("empty-list", []), ("list", [1.0, 2.0]), ("list-3", [1.0, 2.0, 3.0]), ("ragged", [[1.0], [1.0, 2.0]]),
    ("nested", [[[1.0]]]), ("list-of-str", ["a", "b"]), ("list-nan", [math.nan, 0.0]),
    ("empty-array", np.zeros(0)), ("matrix", np.ones((2, 2))), ("array-3d", np.ones((2, 2, 2))),
    ("int-array", np.arange(3)), ("dict", {"a": 1}), ("tuple", (1, 2)), ("object", object()),
    ("callable", lambda *a, **k: None), ("numpy-bool", np.bool_(True)), ("numpy-nan", np.float64("nan")),
    ("bytes", b"x"), ("set", {1, 2}),
]


# --------------------------------------------------------------------------- valid calls on tiny problems
def _mesh():
    from alcontact.fem import meshes

    return meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2)


def _material():
    from alcontact.fem import Material

    return Material(E=1000.0, nu=0.3)


def _model():
    from alcontact.fem import LinearElasticity

    return LinearElasticity(_mesh(), _material())


def _graph():
    """The node graph of :func:`_mesh` (edges as nonzeros)."""
    import scipy.sparse as sp

    m = _mesh()
    a, b = m.facets
    return sp.coo_matrix((np.ones(a.size), (a, b)), shape=(m.nvertices, m.nvertices)).tocsr()


def _problem():
    from alcontact.problems.blocks import patch_block

    return patch_block(2, 1, n=2)


def _history():
    from alcontact.contact import LoadCase, LoadHistory, Pressure, Ramp

    return LoadHistory((LoadCase(Pressure("top", 1.0), Ramp((0.0, 1.0), (0.0, 1.0))),), (0.5, 1.0))


_CACHE: dict = {}


def _solution():
    """A solved tiny patch test (cached: the writers only read it)."""
    if "solution" not in _CACHE:
        from alcontact.contact import solve

        _CACHE["solution"] = solve(_problem())
    return _CACHE["solution"]


def _finite_problem():
    """A 1 x 1 neo-Hookean block pushed 1 % onto a plane (finite kinematics, one step)."""
    from alcontact.contact import ContactProblem, Support
    from alcontact.contact.obstacles import HalfSpace
    from alcontact.fem import Hyperelastic

    body = Hyperelastic(_mesh(), _material())
    return ContactProblem(model=body, obstacle=HalfSpace((0.0, 0.0), (0.0, 1.0)), contact_boundary="bottom",
                          supports=[Support("top", (1,), -0.01), Support("left", (0,))], kinematics="finite")


def _rigid_problem():
    """A block under a rigid flat punch (a ``RigidBody``), its pose held: the problem of ``pair_start``."""
    from alcontact.contact import Boundary, ContactPair, ContactProblem, RigidBody, Support
    from alcontact.contact.obstacles import HalfSpace

    body = _model()
    punch = RigidBody(HalfSpace((0.0, 1.0), (0.0, -1.0)), [0.5, 1.0])
    return ContactProblem(bodies=[body, punch], pairs=[ContactPair(Boundary(body, "top"), punch)],
                          supports=[Support("body0/bottom"), Support("body1")])


def _pair_form():
    """Arguments of the pair form of ``ContactProblem`` (one body, one pair against a plane)."""
    from alcontact.contact import Boundary, ContactPair, Support
    from alcontact.contact.obstacles import HalfSpace

    body = _model()
    pair = ContactPair(Boundary(body, "bottom"), HalfSpace((0.0, 0.0), (0.0, 1.0)))
    return (), dict(bodies=[body], pairs=[pair], supports=[Support("top")])


def _spd():
    """A 4 x 4 symmetric positive definite tridiagonal matrix."""
    import scipy.sparse as sp

    return sp.diags([[-1.0] * 3, [2.0] * 4, [-1.0] * 3], [-1, 0, 1]).tocsr()


def _entries() -> dict:
    from alcontact import contact, distributed, fem, io, linalg, optim, penalties
    from alcontact.contact import obstacles
    from alcontact.fem import meshes
    from alcontact.problems import blocks, friction, hertz

    half = lambda: obstacles.HalfSpace((0.0, 0.0), (0.0, 1.0))  # noqa: E731
    return {
        # name: (callable, () -> (args, kwargs), parameters to replace: positions or names)
        "meshes.rectangle": (meshes.rectangle, lambda: ((0.0, 1.0, 0.0, 1.0, 2, 2), {}), [0, 1, 4, 5, "refine"]),
        "meshes.box": (meshes.box, lambda: ((0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1, 1, 1), {}), [0, 5, 6, 8, "refine"]),
        "meshes.interval": (meshes.interval, lambda: ((0.0, 1.0, 2), {}), [0, 1, 2]),
        "meshes.read": (meshes.read, lambda: (("missing.msh",), {}), [0]),
        "meshes.graded_axis": (meshes.graded_axis, lambda: ((0.0, 1.0, 0.4, 0.6, 0.1, 1.2, 0.5), {}),
                               [0, 1, 2, 3, 4, 5, 6, "axis"]),
        "fem.Material": (fem.Material, lambda: ((), {"E": 1000.0, "nu": 0.3}), ["E", "nu", "plane"]),
        "fem.LinearElasticity": (fem.LinearElasticity, lambda: ((_mesh(), _material()), {}),
                                 [0, 1, "order", "volumetric"]),
        "fem.Hyperelastic": (fem.Hyperelastic, lambda: ((_mesh(), _material()), {}), [0, 1, "order", "model"]),
        "fem.MixedHyperelastic": (fem.MixedHyperelastic, lambda: ((_mesh(),), {"E": 3.0, "nu": 0.5}),
                                  [0, "E", "nu", "model", "intorder", "linear_solver"]),
        "fem.make_material": (fem.make_material, lambda: (("neo-hookean",), {}), [0]),
        "fem.rigid_body_modes": (fem.rigid_body_modes, lambda: ((np.zeros((3, 2)),), {}), [0]),
        "contact.Support": (contact.Support, lambda: (("top",), {}), [0, "components", "value"]),
        "contact.Traction": (contact.Traction, lambda: (("top", (0.0, 1.0)), {}), [0, 1]),
        "contact.Pressure": (contact.Pressure, lambda: (("top", 1.0), {}), [0, 1]),
        "contact.BodyForce": (contact.BodyForce, lambda: (((0.0, 1.0),), {}), [0]),
        "contact.ContactProblem": (contact.ContactProblem, lambda: ((), dict(
            model=_model(), obstacle=half(), contact_boundary="bottom", supports=[contact.Support("top")])),
            ["model", "obstacle", "contact_boundary", "supports", "loads", "friction", "name", "kinematics", "meta"]),
        "contact.Boundary": (contact.Boundary, lambda: ((_model(), "bottom"), {}), [0, 1]),
        "contact.BodySurface": (contact.BodySurface, lambda: ((_model(), "top"), {}), [0, 1, "search_distance"]),
        "fem.MultiBody": (fem.MultiBody, lambda: (([_model(), _model()],), {}), [0, "names"]),
        "contact.RigidBody": (contact.RigidBody, lambda: ((contact.obstacles.HalfSpace((0.0, 1.0), (0.0, -1.0)),
                                                           [0.5, 1.0]), {}), [0, 1]),
        "contact.RigidLoad": (contact.RigidLoad, lambda: (("body1",), {"force": [0.0, -1.0], "moment": 0.0}),
                              [0, "force", "moment"]),
        "contact.pair_start": (contact.pair_start, lambda: ((_rigid_problem(),), {}), [0]),
        "contact.ContactPair": (contact.ContactPair, lambda: ((contact.Boundary(_model(), "bottom"), half()), {}),
                                [0, 1, "friction"]),
        "contact.ContactProblem(bodies, pairs)": (contact.ContactProblem, _pair_form, ["bodies", "pairs", "supports",
                                                                                       "friction", "kinematics"]),
        "contact.ContactOptions": (contact.ContactOptions, lambda: ((), {}), ["maxiter", "penalty_scale", "eps_n"]),
        "contact.solve": (contact.solve, lambda: ((_problem(),), {}), [0, "algorithm", "penalty", "options",
                                                                       "maxiter"]),
        "contact.solve_friction": (contact.solve_friction, lambda: (friction.block_on_plane(dim=2, n=2), {}),
                                   [0, 1, "algorithm", "penalty", "options", "steps", "friction"]),
        "contact.Ramp": (contact.Ramp, lambda: (((0.0, 1.0), (0.0, 1.0)), {}), [0, 1]),
        "contact.LoadCase": (contact.LoadCase, lambda: ((contact.Support("top"), contact.Ramp((0.0, 1.0), (0.0, 1.0))),
                                                        {}), [0, 1, "tangential", "name"]),
        "contact.LoadHistory": (contact.LoadHistory, lambda: ((_history().cases, (0.5, 1.0)), {}), [0, 1]),
        "contact.problem_at": (contact.problem_at, lambda: ((_problem(), _history(), 0.5), {}), [0, 1, 2]),
        "contact.algorithm_docs": (contact.algorithm_docs, lambda: ((), {}), ["friction", "kinematics"]),
        "obstacles.make": (obstacles.make, lambda: (("half-space",), dict(point=(0.0, 0.0), normal=(0.0, 1.0))),
                           [0, "point", "normal"]),
        "obstacles.HalfSpace": (obstacles.HalfSpace, lambda: (((0.0, 0.0), (0.0, 1.0)), {}), [0, 1]),
        "obstacles.Circle": (obstacles.Circle, lambda: (((0.0, 2.0), 1.0), {}), [0, 1, "inside"]),
        "obstacles.Sphere": (obstacles.Sphere, lambda: (((0.0, 0.0, 2.0), 1.0), {}), [0, 1, "inside"]),
        "obstacles.Cylinder": (obstacles.Cylinder, lambda: (((0.0, 0.0, 2.0), (1.0, 0.0, 0.0), 1.0), {}), [0, 1, 2]),
        "obstacles.ConvexPolytope": (obstacles.ConvexPolytope,
                                     lambda: ((np.array([[0.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]),
                                               np.array([0.0, 1.0, 1.0])), {}),
                                     [0, 1]),
        "obstacles.translate": (obstacles.translate, lambda: ((half(), (0.0, 1.0)), {}), [0, 1]),
        "obstacles.RigidMotion": (obstacles.RigidMotion, lambda: ((np.eye(2), (0.0, 1.0)), {}), [0, 1]),
        "penalties.make": (penalties.make, lambda: (("exp-met1",), {}), [0]),
        "penalties.theta": (penalties.theta, lambda: (("exp",), {}), [0]),
        "penalties.facts": (penalties.facts, lambda: ((penalties.make("exp-met1"),), {}), [0]),
        "optim.minimize": (optim.minimize, lambda: ((lambda x: float(x @ x), np.ones(2)), {}),
                           [1, "jac", "hess", "constraints", "bounds", "method", "penalty", "options"]),
        "hertz.hertz_2d": (hertz.hertz_2d, lambda: ((0,), {}), [0, "order", "E", "nu", "radius", "n_per_a"]),
        "hertz.hertz_3d": (hertz.hertz_3d, lambda: ((0,), dict(n_per_a=1, size=4.0, growth=1.6)),
                           [0, "order", "radius", "n_per_a"]),
        "hertz.hertz_axisym": (hertz.hertz_axisym, lambda: ((0,), dict(n_per_a=2, size=4.0, growth=1.6)),
                               [0, "order", "radius", "n_per_a"]),
        "hertz.mesh_spec": (hertz.mesh_spec, lambda: ((2, 4), {}), [0, 1, "order"]),
        "hertz.hertz_disc": (hertz.hertz_disc, lambda: ((4,), {}), [0, "order", "E", "nu", "radius", "delta", "drive"]),
        "blocks.patch_block": (blocks.patch_block, lambda: ((2, 1), dict(n=2)), [0, 1, "n", "E", "nu", "d"]),
        "blocks.signorini_block": (blocks.signorini_block, lambda: ((), dict(n=2)), ["order", "n", "gap"]),
        "friction.block_on_plane": (friction.block_on_plane, lambda: ((), dict(dim=2, n=2)), ["dim", "n", "mu"]),
        "io.load_problem": (io.load_problem, lambda: (("missing.toml",), {}), [0]),
        "io.check_output_dir": (io.check_output_dir, lambda: (("results-api-fuzz",), {}), [0, "force"]),
        "io.jsonable": (io.jsonable, lambda: (({"a": 1.0},), {}), [0]),
        "io.write_text_atomic": (io.write_text_atomic, lambda: (("note.txt", "x"), {}), [0, 1]),
        "io.write_json": (io.write_json, lambda: (("s.json", {"a": 1}), {}), [0, 1]),
        "io.write_history_csv": (io.write_history_csv, lambda: (("h.csv", ()), {}), [0, 1]),
        "io.prepare_output_dir": (io.prepare_output_dir, lambda: (("res",), {}), [0, "force", "create"]),
        "io.owned_entries": (io.owned_entries, lambda: ((".",), {}), [0]),
        "io.ResultsFolder": (io.ResultsFolder, lambda: (("res",), {}), [0]),
        "io.write_pvd": (io.write_pvd, lambda: (("s.pvd", [(0.0, "a.vtu")]), {}), [0, 1]),
        "io.solution_point_data": (io.solution_point_data, lambda: ((_solution(),), {}), [0, "deformed"]),
        "io.write_solution_vtu": (io.write_solution_vtu, lambda: (("s.vtu", _solution()), {}), [0, 1, "deformed"]),
        "contact.FrictionOptions": (contact.FrictionOptions, lambda: ((), {}),
                                    ["maxiter", "eps_t", "tangential_scale"]),
        "contact.solve_finite": (contact.solve_finite, lambda: ((_finite_problem(),), dict(steps=1)),
                                 [0, "algorithm", "steps", "history", "obstacle_path", "max_cutbacks", "on_step"]),
        "contact.solve_finite_friction": (contact.solve_finite_friction, lambda: ((_finite_problem(), 0.1),
                                                                                  dict(steps=1)),
                                          [0, 1, "steps", "history", "obstacle_path", "progress"]),
        "fem.NeoHookean": (fem.NeoHookean, lambda: ((), {}), []),
        "fem.Factorization": (fem.Factorization, lambda: ((_model().stiffness(), _model().dirichlet("left")[0]), {}),
                              [0, 1, "permc_spec", "backend"]),
        "fem.nested_dissection": (fem.nested_dissection, lambda: ((_mesh().p.T, _graph()), {}),
                                  [0, 1, "leaf_size"]),
        "penalties.Met1": (penalties.Met1, lambda: ((penalties.theta("exp"),), {}), [0, "eta0_factor"]),
        "penalties.Met2": (penalties.Met2, lambda: ((penalties.theta("exp"),), {}), [0, "eta0_factor"]),
        "penalties.safeguarded": (penalties.safeguarded, lambda: ((penalties.make("quad-met2"),), {}), [0]),
        "penalties.Safeguarded": (penalties.Safeguarded, lambda: ((penalties.make("quad-met2"),), {}), [0]),
        "penalties.properties_from_generator": (penalties.properties_from_generator,
                                                lambda: ((penalties.theta("exp"),), {}), [0]),
        "penalties.generator_zero": (penalties.generator_zero, lambda: ((penalties.theta("exp"),), {}), [0]),
        "penalties.minimizer_by_bisection": (penalties.minimizer_by_bisection,
                                             lambda: ((penalties.make("exp-met1"), 1.0), {}), [0, 1]),
        "obstacles.UserObstacle": (obstacles.UserObstacle, lambda: ((lambda x: -x[1],), dict(dim=2)),
                                   [0, "normal", "hessian", "dim", "length_scale", "label"]),
        "obstacles.Translated": (obstacles.Translated, lambda: ((half(), (0.0, 1.0)), {}), [0, 1]),
        "obstacles.Moved": (obstacles.Moved, lambda: ((half(), obstacles.RigidMotion(np.eye(2), (0.0, 1.0))), {}),
                            [0, 1]),
        "obstacles.move": (obstacles.move, lambda: ((half(), obstacles.RigidMotion(np.eye(2), (0.0, 1.0))), {}),
                           [0, 1]),
        "obstacles.frame": (obstacles.frame, lambda: ((half(),), {}), [0, "dim"]),
        "obstacles.surface_slip": (obstacles.surface_slip, lambda: ((half(), np.zeros((2, 2)), np.zeros((2, 2))), {}),
                                   [0, 1, 2]),
        "obstacles.transport_tangent": (obstacles.transport_tangent, lambda: ((np.array([[1.0, 0.0]]),
                                                                              np.array([[0.0, 1.0]]),
                                                                              np.array([[0.0, 1.0]])), {}), [0, 1, 2]),
        "blocks.patch_pressure": (blocks.patch_pressure, lambda: ((1000.0, 0.3, 2, 0.01, 1.0), {}), [0, 1, 2, 3, 4]),
        "friction.cattaneo_mindlin_2d": (friction.cattaneo_mindlin_2d, lambda: ((2,), dict(size=4.0)),
                                         [0, "mu", "q_ratio", "normal_steps", "order", "geometry"]),
        "optim.Options": (optim.Options, lambda: ((), {}), ["maxiter", "gtol", "eta0"]),
        "optim.make_strategy": (optim.make_strategy, lambda: (("infeasibility", {"feas_tol": 1e-8}), dict(tau=0.5)),
                                [0, 1, "tau", "factor", "feas_tol"]),
        "contact.check_state": (contact.check_state, lambda: ((np.array([-0.1, 0.0]), np.array([0.0, 1.0]), 0.5),
                                                              dict(tol_penetration=1e-6, tol_complementarity=1e-6,
                                                                   traction_t=np.zeros((2, 1)), slip=np.zeros((2, 1)),
                                                                   mu=0.3, equilibrium=1e-12, tol_equilibrium=1e-10,
                                                                   reach=1.0)),
                                [0, 1, 2, "tol_penetration", "tol_complementarity", "traction_t", "slip", "mu",
                                 "tol_friction", "equilibrium", "tol_equilibrium", "reach"]),
        "fem.MooneyRivlin": (fem.MooneyRivlin, lambda: ((), dict(c10=0.35, c01=0.1)), ["c10", "c01"]),
        "fem.Yeoh": (fem.Yeoh, lambda: ((), dict(c10=0.45, c20=-0.02, c30=0.005)), ["c10", "c20", "c30"]),
        "fem.Gent": (fem.Gent, lambda: ((), dict(Jm=20.0)), ["Jm"]),
        "fem.ArrudaBoyce": (fem.ArrudaBoyce, lambda: ((), dict(lambda_m=3.0)), ["lambda_m"]),
        "fem.Ogden": (fem.Ogden, lambda: ((), dict(mu=[0.88, 0.004, -0.01], alpha=[2.0, 5.0, -2.0])), ["mu", "alpha"]),
        "fem.EnergyExpression": (fem.EnergyExpression, lambda: (("c10*(I1b-3) + K/2*(J-1)**2", {"c10": 0.4, "K": 50.0}),
                                                                {}), [0, 1, "key", "params_key"]),
        "fem.check_material_parameters": (fem.check_material_parameters, lambda: (("gent", {"Jm": 20.0}), {}),
                                          [0, 1, "api"]),
        "fem.material_parameters": (fem.material_parameters, lambda: (("gent",), {}), [0]),
        "fem.example_material_parameters": (fem.example_material_parameters, lambda: (("ogden",), {}), [0]),
        "linalg.AMGSolver": (linalg.AMGSolver, lambda: ((), {}), ["rtol", "maxiter", "max_coarse"]),
        "linalg.select_solver": (linalg.select_solver, lambda: (("auto",), dict(dim=2, ndofs=100)),
                                 [0, "dim", "ndofs", "matrix_type", "allow_iterative"]),
        "linalg.SuperLUSolver": (linalg.SuperLUSolver, lambda: ((), {}), ["permc_spec", "use_ordering"]),
        "linalg.SequenceSolver": (linalg.SequenceSolver, lambda: ((), {}), ["name", "matrix_type", "keep", "fallback"]),
        "linalg.PardisoSymmetricFactor": (linalg.PardisoSymmetricFactor, lambda: ((_spd(),), {}), [0, "matrix_type"]),
        "linalg.SaddlePoint": (linalg.SaddlePoint, lambda: ((3, [1.0, 2.0]), {}), [0, 1, "label"]),
        "linalg.MatrixHints": (linalg.MatrixHints, lambda: ((), dict(dim=2)),
                               ["dim", "ordering", "near_null", "ordering_name", "schur", "matrix_type"]),
        "linalg.choose_solver": (linalg.choose_solver, lambda: ((2, 100), {}),
                                 [0, 1, "installed", "allow_iterative", "matrix_type"]),
        "linalg.is_installed": (linalg.is_installed, lambda: (("superlu",), {}), [0]),
        "linalg.make_solver": (linalg.make_solver, lambda: (("superlu",), {}), [0]),
        "linalg.solver_kind": (linalg.solver_kind, lambda: (("superlu",), {}), [0]),
        "linalg.check_backend_options": (linalg.check_backend_options, lambda: (({"ksp_rtol": 1e-9},), {}), [0]),
        "linalg.takes_backend_options": (linalg.takes_backend_options, lambda: (("petsc",), {}), [0]),
        "distributed.check_launch": (distributed.check_launch, lambda: (("alcontact run",), {}), [0]),
        "linalg.solver_matrix_types": (linalg.solver_matrix_types, lambda: (("superlu",), {}), [0]),
        "distributed.dual_graph": (distributed.dual_graph, lambda: ((_mesh().t,), {}), [0]),
        "distributed.owner_numbering": (distributed.owner_numbering,
                                        lambda: ((_mesh().t, np.zeros(_mesh().t.shape[1], dtype=int),
                                                  _mesh().nvertices), {}), [0, 1, 2]),
        "contact.find_algorithm": (contact.find_algorithm, lambda: (("simo-laursen",), {}),
                                   [0, "friction", "kinematics"]),
        "contact.describe_algorithms": (contact.describe_algorithms, lambda: ((), dict(friction=False)), ["friction"]),
        "fem.material_issues": (fem.material_issues, lambda: ((1000.0, 0.3), {}), [0, 1, "plane"]),
        "fem.check_geometry": (fem.check_geometry, lambda: (("axisymmetric", 2, np.ones((2, 3))), {}),
                               [0, 1, 2, "plane"]),
        "fem.numerical_rank": (fem.numerical_rank, lambda: ((np.eye(2),), {}), [0]),
        "obstacles.signature": (obstacles.signature, lambda: (("half-space",), {}), [0]),
        # one part: no METIS call (pymetis is in .venv-mpi only), the argument checks still run
        "distributed.partition_elements": (distributed.partition_elements, lambda: ((_mesh().t, 1), {}),
                                           [0, 1, "seed"]),
    }


#: public callables of the fuzzed modules that are not called, with the reason
NOT_CALLED = {
    **dict.fromkeys(["ContactStatus", "ContactIteration", "ContactResult", "ContactSolution", "ContactFrame",
                     "FrictionSolution",
                     "FrictionStep", "FiniteSolution", "FiniteStep", "FiniteFrictionSolution", "FiniteFrictionStep",
                     "ALResult", "IterationRecord", "Status", "PenaltyFacts", "ProblemSetup", "HertzReference",
                     "MindlinReference", "PairStart"], "a result or record the solvers build, not an input"),
    **dict.fromkeys(["Body", "HyperelasticLaw", "Obstacle", "Penalty", "PenaltyBase", "Generator",
                     "Master"],
                    "a protocol or abstract base class"),
    **dict.fromkeys(["available_algorithms", "contact_penalties", "friction_algorithms", "friction_algorithm_docs",
                     "finite_friction_algorithms", "available_materials", "available_methods", "available_strategies",
                     "available_inner_solvers", "available", "describe", "thetas", "docs", "friction_only_options"],
                    "takes no argument"),
    **dict.fromkeys(["register_material", "register", "unregister", "register_theta", "unregister_theta"],
                    "changes a process-wide registry: a fuzzed call that succeeds would leak into other tests"),
    **dict.fromkeys(["StrategyState", "NewtonRecord", "NewtonResult"], "a record the outer loops and newton build, "
                    "not an input"),
    **dict.fromkeys(["PenaltyUpdate", "NewtonSystem"], "a protocol or base class"),
    **dict.fromkeys(["describe_strategies"], "takes no argument"),
    **dict.fromkeys(["register_strategy", "unregister_strategy"],
                    "changes a process-wide registry: a fuzzed call that succeeds would leak into other tests"),
    **dict.fromkeys(["newton", "LineSearch", "NewtonSettings", "inner_failure"],
                    "the one Newton loop and its settings, for code that writes a NewtonSystem (not checked as user "
                    "input; its statuses are tested in tests/unit/test_newton.py)"),
    **dict.fromkeys(["atomic_path"], "a context manager (its path argument is the one of write_text_atomic)"),
    **dict.fromkeys(["backend_options"], "a context manager (its argument is checked by check_backend_options, "
                                         "fuzzed)"),
    **dict.fromkeys(["launch_rank", "launch_size", "mpi_extras_missing"],
                    "takes no argument (reads the MPI launcher's environment)"),
    **dict.fromkeys(["solve_distributed", "solve_distributed_friction"],
                    "runs on every rank of an MPI program (its argument checks: tests/mpi/test_distributed_contact.py "
                    "and tests/mpi/test_distributed_friction.py, through mpirun)"),
    **dict.fromkeys(["DistributedContactSolution", "DistributedFrictionSolution"],
                    "a result the distributed solve builds, not an input"),
    **dict.fromkeys(["release_memory"], "takes no argument"),
    **dict.fromkeys(["mg_hierarchy", "mg_smoothers"], "takes a petsc4py KSP, which only .venv-mpi has (make mpi); "
                                                      "checked in tests/mpi"),
    **dict.fromkeys(["SaintVenantKirchhoff", "Rockafellar", "HestenesPowell", "ExteriorQuadratic", "LogBarrier",
                     "InverseBarrier"], "optional name/doc strings only, like NeoHookean (which is called)"),
    **dict.fromkeys(["DistributedSolution", "LocalPiece", "DistributedError"],
                    "a result, record or exception the distributed solver builds, not an input"),
    **dict.fromkeys(["Factor", "LinearSolver"], "a protocol or abstract base class"),
    **dict.fromkeys(["SolverChoice"], "a result select_solver builds, not an input"),
    **dict.fromkeys(["NewtonKrylovSolver"], "takes the SolverChoice of select_solver (fuzzed there); its solves are "
                                            "checked in tests/verification/test_finite_amg.py"),
    **dict.fromkeys(["CholmodSolver", "PardisoSolver", "available_solvers", "registered_solvers",
                     "describe_solvers"], "takes no argument"),
    **dict.fromkeys(["register_solver", "unregister_solver"],
                    "changes a process-wide registry: a fuzzed call that succeeds would leak into other tests"),
    **dict.fromkeys(["PetscKrylovSolver", "PetscDirectSolver", "configure_ksp", "near_null_space", "petsc",
                     "direct_package", "DistributedElasticity", "run_ranks", "world", "report_unused_options"],
                    "needs petsc4py/mpi4py, which only .venv-mpi has (make mpi); in this environment every one "
                    "raises the InputError with the set-up command before reading its arguments "
                    "(tests/unit/test_linalg_petsc_missing.py, tests/mpi)"),
    **dict.fromkeys(["collective"], "a context manager over an mpi4py communicator (only .venv-mpi has mpi4py; "
                                    "tested on 1-3 ranks in tests/mpi)"),
    **dict.fromkeys(["contact_element_size", "merge_supports"],
                    "not covered yet (helpers of ContactProblem and of the problem-file checks: they take a built "
                    "model and the problem's own Support objects, and do not check their types)"),
    **dict.fromkeys(["Theta", "SymbolicMaterial", "sphere_shear_3d"],
                    "not covered yet (a generator from four callables; a sympy energy; a 3D problem too slow "
                    "for 1,000 calls)"),
}


ENTRIES = _entries()


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    """Relative paths (``missing.msh``, ``results-api-fuzz``) resolve in a temporary folder."""
    monkeypatch.chdir(tmp_path)


@st.composite
def bad_calls(draw):
    name = draw(st.sampled_from(sorted(n for n, entry in ENTRIES.items() if entry[2])))  # entries with arguments
    fn, base, params = ENTRIES[name]
    param = draw(st.sampled_from(params))
    label, value = draw(st.sampled_from(BAD_VALUES))
    return name, param, label, value


FUZZ_SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


def call(name: str, param, value):
    """``ENTRIES[name]`` with argument ``param`` replaced by ``value``."""
    fn, base, _ = ENTRIES[name]
    args, kwargs = base()
    if isinstance(param, int):
        args = list(args)
        args[param] = value
    else:
        kwargs[param] = value
    return fn(*args, **kwargs)


@settings(max_examples=_examples(1000), **FUZZ_SETTINGS)
@given(case=bad_calls())
def test_wrong_types_and_shapes_give_project_errors(case):
    name, param, label, value = case
    try:
        call(name, param, value)
    except AlcontactError as exc:
        assert str(exc), (name, param, label)


@pytest.mark.parametrize("name", sorted(n for n, entry in ENTRIES.items() if entry[2]))
def test_every_bad_value_of_every_argument(name):
    """The whole product for one entry, deterministic: every listed parameter times every value of
    :data:`BAD_VALUES` (the sampled test above draws from it; this sweep found the missing checks of
    ``check_state``, ``check_material_parameters``, ``EnergyExpression`` and the linalg/distributed
    functions that the sampled 1,000 examples may miss: about 10,000 calls, a few seconds in all)."""
    _, _, params = ENTRIES[name]
    for param in params:
        for label, value in BAD_VALUES:
            try:
                call(name, param, value)
            except AlcontactError as exc:
                assert str(exc), (name, param, label)
            except Exception as exc:  # report which argument and value, not only the traceback
                raise AssertionError(f"{name}({param!r} = {label}): {type(exc).__name__}: {exc}") from exc


MODULES = ["alcontact.contact", "alcontact.fem", "alcontact.optim", "alcontact.penalties", "alcontact.io",
           "alcontact.contact.obstacles", "alcontact.fem.meshes", "alcontact.problems.hertz",
           "alcontact.problems.blocks", "alcontact.problems.friction", "alcontact.linalg", "alcontact.distributed"]


def test_every_public_entry_point_is_in_the_table():
    """Every public function and class of :data:`MODULES` is fuzzed (:data:`ENTRIES`) or listed in
    :data:`NOT_CALLED` with the reason."""
    called = {name.split(".")[-1] for name in ENTRIES}
    missing = []
    for mod_name in MODULES:
        mod = importlib.import_module(mod_name)
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name, None)
            if callable(obj) and not inspect.ismodule(obj) and name not in called and name not in NOT_CALLED:
                missing.append(f"{mod_name}.{name}")
    assert not missing, f"add to ENTRIES (or NOT_CALLED with the reason): {missing}"


def test_the_valid_calls_work():
    """The starting points of the mutations are valid calls (else the fuzzing would only see errors)."""
    for name, (fn, base, _) in ENTRIES.items():
        if name in ("meshes.read", "io.load_problem"):  # a missing file: the error path is the base
            continue
        args, kwargs = base()
        fn(*args, **kwargs)
