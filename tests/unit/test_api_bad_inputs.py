"""Python API bad inputs: every one raises a project error naming the key and the value (issue 8).

The table is generated from the option declarations (``alcontact.io.schema.declarations``): for every
field of ``ContactOptions`` and ``FrictionOptions``, a value of the wrong type, a bool
for an int, a string for a number, NaN/inf where a finite number is needed and values
outside the declared range. Each is passed three ways (keyword override, ``options=``
as a dataclass, ``options=`` as a dict) to ``solve``/``solve_friction``, which must
raise before any work is done. Hand-written rows cover the wrong problem object,
unknown algorithm/penalty/option names and ``optim.minimize`` options.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from _helpers import sq, sq_grad
from alcontact import errors
from alcontact.contact import ContactOptions, Support, solve
from alcontact.contact.algorithms import FrictionOptions
from alcontact.contact import solve_friction
from alcontact.fem import meshes
from alcontact.io.schema import declarations
from alcontact.optim import minimize
from alcontact.problems import friction as fp
from alcontact.problems.blocks import patch_block

PROJECT_ERRORS = (errors.AlcontactError,)


def _bad_values(opt):
    """``(label, value)`` pairs that violate the declaration ``opt``."""
    out = [("list", [1]), ("dict", {"a": 1})]
    if opt.type in ("float", "int"):
        out += [("string", "10"), ("bool", True), ("nan", math.nan), ("inf", math.inf), ("-inf", -math.inf),
                ("huge-int", 10**400)]
        if opt.default is not None:
            out.append(("none", None))
        if opt.type == "int":
            out += [("float-for-int", 2.5), ("numpy-bool", np.bool_(True))]
        if opt.low is not None:
            below = opt.low if opt.low_open else opt.low - 1
            out.append(("below-range", int(below) if opt.type == "int" else float(below)))
        if opt.high is not None:
            above = opt.high if opt.high_open else opt.high + 1
            out.append(("above-range", int(above) if opt.type == "int" else float(above)))
    elif opt.type == "str":
        out += [("number", 3), ("none", None), ("unknown-choice", opt.allowed[0] + "x")]
    return out


def _rows(cls, kind):
    for opt in declarations(cls):
        for label, value in _bad_values(opt):
            yield pytest.param(cls, kind, opt.name, value, id=f"{kind}-{opt.name}-{label}")


ROWS = list(_rows(ContactOptions, "contact")) + list(_rows(FrictionOptions, "friction"))


@pytest.fixture(scope="module")
def contact_problem():
    return patch_block(2, 1, n=2)


@pytest.fixture(scope="module")
def friction_problem():
    return fp.block_on_plane(dim=2, n=2)


def _key_and_value_named(exc, key, value):
    msg = str(exc)
    assert key in msg, msg
    text = repr(value) if not (isinstance(value, int) and abs(value) > 10**40) else "digits"
    if isinstance(value, float) and math.isnan(value):
        text = "nan"
    assert text in msg, (text, msg)


@pytest.mark.parametrize("cls,kind,key,value", ROWS)
def test_bad_option_value_is_a_project_error_naming_key_and_value(cls, kind, key, value, contact_problem,
                                                                  friction_problem):
    """Override, options dataclass and options dict all raise InputError with the key and the value."""
    if kind == "contact":
        def call(**kw):
            return solve(contact_problem, **kw)
    else:
        def call(**kw):
            prob, hist = friction_problem
            return solve_friction(prob, hist, **kw)
    ways = (lambda: {key: value}, lambda: {"options": cls(**{key: value})}, lambda: {"options": {key: value}})
    for kwargs in ways:  # the dataclass itself rejects the value when it is made
        with pytest.raises(errors.InputError) as info:
            call(**kwargs())
        _key_and_value_named(info.value, key, value)
        assert f"{kind} option" in str(info.value)


def test_every_option_has_a_bad_value_row():
    """The table covers every declared field of both options classes."""
    names = {(r.values[1], r.values[2]) for r in ROWS}
    for cls, kind in ((ContactOptions, "contact"), (FrictionOptions, "friction")):
        for f in dataclasses.fields(cls):
            assert (kind, f.name) in names, f.name


def test_out_of_range_message_gives_the_allowed_range_and_default():
    with pytest.raises(errors.InputError) as info:
        ContactOptions(tau=1.5).validate()
    msg = str(info.value)
    assert "tau = 1.5" in msg and "in (0, 1)" in msg and "Default: 0.25" in msg


def test_options_as_dict_are_accepted_and_converted(contact_problem):
    """``options={"maxiter": 3}`` works as in ``optim.minimize``; NumPy scalars become Python numbers."""
    sol = solve(contact_problem, options={"maxiter": 3, "penalty_scale": np.float64(10.0)})
    assert sol.result.outer_iterations <= 3
    opts = ContactOptions(maxiter=np.int64(7)).validate()
    assert type(opts.maxiter) is int and opts.maxiter == 7


def test_maxiter_true_is_rejected_not_one_iteration(contact_problem):
    with pytest.raises(errors.InputError, match="maxiter = True"):
        solve(contact_problem, maxiter=True)


BAD_CALLS = [
    ("problem-str", lambda p, f: solve("x"), ["problem", "'x'", "ContactProblem"]),
    ("problem-none", lambda p, f: solve(None), ["problem", "None", "ContactProblem"]),
    ("problem-model", lambda p, f: solve(p.model), ["problem", "ContactProblem"]),
    ("friction-problem-str", lambda p, f: solve_friction("x", f[1]), ["problem", "'x'", "ContactProblem"]),
    ("algorithm-unknown", lambda p, f: solve(p, "simo-laursn"), ["simo-laursn", "Did you mean"]),
    ("algorithm-number", lambda p, f: solve(p, 3), ["algorithm = 3", "simo-laursen"]),
    ("algorithm-list", lambda p, f: solve(p, ["ssn"]), ["algorithm = ['ssn']"]),
    ("penalty-unknown", lambda p, f: solve(p, "family-p", "exp-met3"), ["exp-met3", "exp-met1"]),
    ("penalty-number", lambda p, f: solve(p, "family-p", 1), ["penalty = 1"]),
    ("penalty-for-fixed", lambda p, f: solve(p, "ssn", "exp-met1"), ["exp-met1", "family-p"]),
    ("option-unknown", lambda p, f: solve(p, maxiters=3), ["maxiters", "Did you mean 'maxiter'"]),
    ("options-dict-unknown", lambda p, f: solve(p, options={"maxiterr": 3}), ["maxiterr", "maxiter"]),
    ("options-dict-nonstr-key", lambda p, f: solve(p, options={1: 3}), ["1", "contact option"]),
    ("options-wrong-type", lambda p, f: solve(p, options=[("maxiter", 3)]), ["options", "ContactOptions", "dict"]),
    ("options-wrong-class", lambda p, f: solve(p, options=Support("top")), ["options", "ContactOptions"]),
    ("friction-options-unknown", lambda p, f: solve_friction(*f, options={"tol_slp": 1.0}), ["tol_slp", "tol_slip"]),
    ("friction-algorithm", lambda p, f: solve_friction(*f, algorithm="penalty"), ["penalty", "friction algorithm"]),
    ("friction-coefficient-str", lambda p, f: solve_friction(*f, friction="0.3"), ["friction = '0.3'", ">= 0"]),
    ("friction-coefficient-nan", lambda p, f: solve_friction(*f, friction=math.nan), ["friction = nan"]),
    ("friction-history", lambda p, f: solve_friction(f[0], [1.0]), ["history", "LoadHistory"]),
    ("friction-steps-zero", lambda p, f: solve_friction(*f, steps=0), ["steps = 0", "[1, 100000]"]),
    ("friction-steps-huge", lambda p, f: solve_friction(*f, steps=10**9), ["steps = 1000000000"]),
    ("friction-steps-bool", lambda p, f: solve_friction(*f, steps=True), ["steps = True"]),
    ("friction-steps-decreasing", lambda p, f: solve_friction(*f, steps=[0.5, 0.2]), ["steps = [0.5, 0.2]"]),
    ("friction-steps-str", lambda p, f: solve_friction(*f, steps="3"), ["steps = '3'"]),
]


@pytest.mark.parametrize("label,call,words", BAD_CALLS, ids=[c[0] for c in BAD_CALLS])
def test_bad_call_is_a_project_error(label, call, words, contact_problem, friction_problem):
    with pytest.raises(errors.InputError) as info:
        call(contact_problem, friction_problem)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


MINIMIZE_BAD_OPTIONS = [
    ({"maxiter": "10"}, "maxiter"), ({"maxiter": True}, "maxiter"), ({"maxiter": 0}, "maxiter"),
    ({"maxiter": 2.5}, "maxiter"), ({"maxiter_inner": None}, "maxiter_inner"),
    ({"gtol": "1e-8"}, "gtol"), ({"gtol": math.inf}, "gtol"), ({"gtol": -1.0}, "gtol"),
    ({"tol": math.nan}, "gtol"), ({"ftol": True}, "feas_tol"), ({"ctol": None}, "ctol"),
    ({"eta0": "big"}, "eta0"), ({"eta0": -1.0}, "eta0"), ({"eta0": math.nan}, "eta0"), ({"eta0": [[1.0]]}, "eta0"),
    ({"mu0": "x"}, "mu0"), ({"mu0": math.inf}, "mu0"), ({"lam0": {"a": 1}}, "lam0"), ({"mu0": [1.0, 2.0, 3.0]}, "mu0"),
    ({"mu_min": "0"}, "mu_min"), ({"mu_min": -1.0}, "mu_min"), ({"mu_max": 0.0}, "mu_max"),
    ({"eta_min": 1.0, "eta_max": 0.5}, "eta_min"), ({"unbounded_below": "x"}, "unbounded_below"),
    ({"polish": "yes"}, "polish"), ({"scale": 1}, "scale"), ({"extrapolate": None}, "extrapolate"),
    ({"bound_push": 0.7}, "bound_push"), ({"bound_push": "0.1"}, "bound_push"), ({"bounds_as": "boxes"}, "bounds_as"),
    ({"bounds_as": ["box"]}, "bounds_as"), ({"strategy": 3}, "strategy"), ({"inner": None}, "inner"),
    ({"inner_options": [1]}, "inner_options"), ({"strategy_options": "tau=0.5"}, "strategy_options"),
    ({"penalty_options": 1.0}, "penalty_options"), ({"maxiterr": 3}, "maxiterr"), ({"stall_iter": -1}, "stall_iter"),
    ({"exp_cap": math.inf}, "exp_cap"), ({"eta0_factor": 0.0}, "eta0_factor"), ({"strategy": "kkkt"}, "kkkt"),
    ({"inner": "newtn"}, "newtn"),
]


@pytest.mark.parametrize("options,key", MINIMIZE_BAD_OPTIONS, ids=[str(o) for o, _ in MINIMIZE_BAD_OPTIONS])
def test_minimize_bad_options(options, key):
    """``optim.minimize`` rejects each bad option with a project error naming the option."""
    cons = [{"type": "ineq", "fun": lambda x: 1.0 - x[0], "jac": lambda x: np.array([-1.0, 0.0])}]
    with pytest.raises(PROJECT_ERRORS) as info:
        minimize(sq, np.array([2.0, 1.0]), jac=sq_grad, constraints=cons, options=options)
    assert key in str(info.value), str(info.value)


def test_minimize_options_not_a_dict():
    with pytest.raises(errors.InputError, match="options must be a dict"):
        minimize(sq, np.array([1.0]), jac=sq_grad, options=[("maxiter", 3)])


MESH_BAD_CALLS = [
    ("cells-huge", lambda: meshes.rectangle(0, 1, 0, 1, 2**63 - 1, 4), ["cells along x", "1000000"]),
    ("cells-nan", lambda: meshes.rectangle(0, 1, 0, 1, math.nan, 4), ["cells along x", "nan"]),
    ("cells-bool", lambda: meshes.box(0, 1, 0, 1, 0, 1, 2, True, 2), ["cells along y", "True"]),
    ("bounds-overflow", lambda: meshes.rectangle(-1e308, 1e308, 0, 1, 2, 2), ["x", "1e+30"]),
    ("bounds-string", lambda: meshes.rectangle("0", 1, 0, 1, 2, 2), ["x", "'0'"]),
    ("spacing-below-precision", lambda: meshes.rectangle(1e20, 1e20 + 1e6, 0, 1, 10**6, 1), ["x", "too small"]),
    ("too-thin", lambda: meshes.rectangle(0, 1e25, 0, 1e-20, 2, 2), ["y", "too thin"]),
    ("vertices", lambda: meshes.box(0, 1, 0, 1, 0, 1, 1000, 1000, 100), ["vertices", "fewer cells"]),
    ("h_min-subnormal", lambda: meshes.rectangle(0, 1, 0, 1, 2, 2, refine=dict(center=(0, 1), h_min=5e-324,
                                                                                width=0.1, depth=0.1)),
     ["h_min", "5e-324"]),
    ("h_min-many-cells", lambda: meshes.rectangle(0, 1, 0, 1, 2, 2, refine=dict(center=(0, 1), h_min=1e-9,
                                                                                 width=0.5, depth=0.5)),
     ["cells along", "h_min"]),
    ("h_max-many-cells", lambda: meshes.rectangle(0, 1, 0, 1, 2, 2, refine=dict(center=(0, 1), h_min=1e-7, width=0,
                                                                                 depth=0, h_max=1e-7)),
     ["cells along", "h_max"]),
    ("growth-barely-above-1", lambda: meshes.rectangle(0, 1, 0, 1, 2, 2, refine=dict(
        center=(0, 1), h_min=1e-8, width=0, depth=0, growth=1 + 1e-15)), ["cells along", "growth"]),
]


@pytest.mark.parametrize("label,call,words", MESH_BAD_CALLS, ids=[c[0] for c in MESH_BAD_CALLS])
def test_mesh_generator_limits(label, call, words):
    """Degenerate or absurd generator input is an InputError naming the input, never an overflow or a huge mesh."""
    with pytest.raises(errors.InputError) as info:
        call()
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_tiny_refine_depth_is_no_sliver():
    """depth = 4e-324 (issue 8) acts as depth 0: no cell thinner than h_min / 2 under the top face."""
    m = meshes.rectangle(0, 1, 0, 1, 4, 4, refine=dict(center=(0.5, 1.0), h_min=0.05, width=0.1, depth=4e-324))
    y = np.unique(m.p[1])
    assert np.diff(y).min() >= 0.025
