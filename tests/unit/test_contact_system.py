"""The declared contact system (:mod:`alcontact.contact.systems._protocol`) is all the frictionless algorithms call.

- every model class the frictionless algorithms run on (small deformation: condensed direct and
  AMG; finite deformation, and its frictional subclass) is a :class:`ContactSystem`: every member
  present, every method callable with the protocol's arguments, the declared capabilities booleans;
- the algorithm modules (frictionless and frictional) ask no model whether it has a member (no
  ``getattr`` / ``hasattr`` / ``isinstance`` on the system): a capability is a declared member with a
  "not available" value;
- the frictional Algorithms 6.2 / 6.4 drive every step system (condensed direct, AMG, finite
  deformation) through the declared ``_ALSystem`` protocol of :mod:`alcontact.contact.algorithms._coulomb`;
- the options that replaced the hidden class switches of the finite-deformation model reach it and
  take effect (``subproblems``, ``predictor``; ``slide_start_reach`` in
  ``tests/regression/test_issue18_ironing.py``).
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import ContactOptions, solve_finite
from alcontact.contact.systems._protocol import SYSTEM_MEMBERS
from alcontact.contact.systems import ContactSystem
from alcontact.errors import InputError
from alcontact.problems import hertz
from alcontact.problems.half_cylinder import half_cylinder

CAPABILITIES = ("inexact_subproblems", "physical_stopping", "warm_penalty_start", "penalty_continuation")


def _models():
    from alcontact.contact.systems import DiscreteContact
    from alcontact.contact.systems import FiniteContact
    from alcontact.contact.systems import FiniteFrictionContact
    from alcontact.contact.systems import IterativeContact

    small = hertz.hertz_2d(n_per_a=4, growth=1.3)
    finite = half_cylinder(4, order=1)
    return {"DiscreteContact": lambda: DiscreteContact(small), "IterativeContact": lambda: IterativeContact(small),
            "FiniteContact": lambda: FiniteContact(finite), "FiniteFrictionContact": lambda: FiniteFrictionContact(finite)}


MODELS = _models()


def _protocol_methods():
    return {name: fn for name, fn in vars(ContactSystem).items()
            if name in SYSTEM_MEMBERS and inspect.isfunction(fn)}


def test_members_list_is_the_protocol():
    """SYSTEM_MEMBERS names exactly the protocol's attributes, properties and methods."""
    declared = set(ContactSystem.__annotations__) | {
        n for n, v in vars(ContactSystem).items()
        if not n.startswith("_") and (inspect.isfunction(v) or isinstance(v, property))}
    assert declared == set(SYSTEM_MEMBERS)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_every_model_satisfies_the_protocol(name):
    """isinstance with the runtime-checkable protocol, every method binds the protocol's call, and the declared
    capabilities are booleans (the "not available" value False where a model has none)."""
    model = MODELS[name]()
    assert isinstance(model, ContactSystem), [m for m in SYSTEM_MEMBERS if not hasattr(model, m)]
    for member, fn in _protocol_methods().items():
        params = list(inspect.signature(fn).parameters.values())[1:]  # without self
        args = [object() for p in params if p.kind == p.POSITIONAL_OR_KEYWORD]
        kwargs = {p.name: object() for p in params if p.kind == p.KEYWORD_ONLY}
        try:
            inspect.signature(getattr(model, member)).bind(*args, **kwargs)
        except TypeError as exc:
            pytest.fail(f"{name}.{member} cannot be called as ContactSystem.{member}{inspect.signature(fn)}: {exc}")
    for flag in CAPABILITIES:
        assert isinstance(getattr(model, flag), bool), flag
    assert isinstance(model.active_converged, bool)
    assert model.h > 0 and model.cand.dtype.kind == "i"
    assert model.carried_stiffness is None  # nothing carried before a penalty run


@pytest.mark.parametrize("name", ["DiscreteContact", "IterativeContact"])
def test_not_available_values_leave_the_algorithms_unchanged(name):
    """The small-deformation models declare no capability: zero warm start, the plain semi-smooth rule,
    no multiplier shift, no second-order update."""
    model = MODELS[name]()
    n = model.cand.size
    assert not any(getattr(model, flag) for flag in CAPABILITIES if not (name == "IterativeContact"
                                                                          and flag == "inexact_subproblems"))
    np.testing.assert_array_equal(model.initial_multipliers(), np.zeros(n))
    lam, g = np.linspace(-1.0, 1.0, n), np.linspace(1.0, -1.0, n)
    np.testing.assert_array_equal(model.initial_active(lam, g, 2.0), lam + 2.0 * g > 0)
    assert model.entry_multipliers(lam, None) is lam
    assert model.multiplier_step(None, lam, None) is None and model.start_multiplier_step(None, lam, None) is None


def test_finite_model_declares_its_capabilities():
    """Finite deformation declares what it does differently (not hidden switches): all four capabilities."""
    model = MODELS["FiniteContact"]()
    assert all(getattr(model, flag) for flag in CAPABILITIES)


#: the frictionless algorithms and the frictional ones (Algorithms 6.2 / 6.4 and the Alart-Curnier reference run on
#: the declared step system ``_ALSystem`` of :mod:`alcontact.contact.algorithms._coulomb` and its model)
#: (module, top-level definitions checked; None: the whole module). The frictional code of the Krylov and
#: finite-deformation strategies lives with their systems; the definitions checked there are those.
ALGORITHM_MODULES = [
    ("algorithms/_frictionless.py", None),
    ("algorithms/_coulomb.py", None),
    ("algorithms/_subproblem.py", None),
    ("stepping/_coulomb.py", None),
    ("solution/_records.py", None),
    ("systems/_full_space.py", ("FiniteFrictionContact", "_FrictionSubproblem", "_Local")),
    ("systems/_krylov.py", ("IterativeFrictionalContact", "_AmortizedPreconditioner", "_block_matrix", "_psd_part",
                            "_FullCtx", "_FullSpaceFriction", "friction_newton", "_held_rigid_motions")),
]
SYSTEM_NAMES = {"dc", "fc", "ic", "ctx", "system", "model"}


def _probes(path: Path, names=None):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    if names is not None:
        found = [n for n in tree.body if getattr(n, "name", None) in names]
        assert sorted(n.name for n in found) == sorted(names), f"{path.name}: {names} not all defined"
        tree = ast.Module(body=found, type_ignores=[])
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id in ("getattr", "hasattr", "isinstance") and node.args
                and isinstance(node.args[0], ast.Name) and node.args[0].id in SYSTEM_NAMES):
            yield f"{path.name}:{node.lineno}: {ast.unparse(node)}"


@pytest.mark.parametrize("module, names", ALGORITHM_MODULES, ids=[m for m, _ in ALGORITHM_MODULES])
def test_algorithms_do_not_probe_the_system(module, names):
    """No getattr / hasattr / isinstance on the system in an algorithm module (a capability is a declared member)."""
    import alcontact.contact as contact

    path = Path(contact.__file__).parent / module
    assert list(_probes(path, names)) == []


def test_the_probe_check_can_fail(tmp_path):
    """The check above finds a probe where there is one."""
    p = tmp_path / "m.py"
    p.write_text("def run(dc):\n    return getattr(dc, 'multiplier_step', None)\n", encoding="utf-8")
    assert len(list(_probes(p))) == 1


def test_switch_options_are_declared_and_checked():
    """The former class switches are options with a declaration (TOML schema, docs, summary): bad values fail."""
    opts = ContactOptions()
    assert (opts.subproblems, opts.predictor, opts.slide_start_reach) == ("inexact", "auto", 0.05)
    for bad in ({"subproblems": "sloppy"}, {"predictor": "secant"}, {"slide_start_reach": -1.0}):
        with pytest.raises(InputError, match=next(iter(bad))):
            ContactOptions(**bad)


@pytest.fixture(scope="module")
def pressed():
    return half_cylinder(4, order=2)


def test_subproblems_option_takes_effect(pressed):
    """``subproblems="exact"``: every Newton solve of Algorithm 6.1 ends at newton_tol; the default (inexact)
    stops some earlier, and both reach the same forces within 1e-8 (the stopping tolerance)."""
    runs = {mode: solve_finite(pressed, "simo-laursen", steps=4, subproblems=mode) for mode in ("inexact", "exact")}
    for fs in runs.values():
        assert fs.success, fs.message
    tol = 1e-12  # newton_tol of the frictionless algorithms
    last = {mode: [log[-1] for log in fs.extra["residual_log"] if log] for mode, fs in runs.items()}
    assert max(last["exact"]) <= tol, max(last["exact"])
    assert max(last["inexact"]) > tol
    ref = runs["exact"].forces[:, 1]
    assert np.max(np.abs(runs["inexact"].forces[:, 1] - ref) / ref) <= 1e-8


def test_predictor_option_takes_effect(pressed):
    """``predictor="tangent"``: no secant extrapolation, so more assembly + solves than the default; same forces
    within 1e-8."""
    auto = solve_finite(pressed, "ssn", steps=6)
    tangent = solve_finite(pressed, "ssn", steps=6, predictor="tangent")
    assert auto.success and tangent.success
    assert sum(s.linear_solves for s in tangent.steps) > sum(s.linear_solves for s in auto.steps)
    ref = auto.forces[:, 1]
    assert np.max(np.abs(tangent.forces[:, 1] - ref) / ref) <= 1e-8


def _step_systems():
    from alcontact.contact.algorithms._coulomb import _FiniteALCtx
    from alcontact.contact.algorithms._coulomb import _Ctx
    from alcontact.contact.systems._krylov import _FullCtx

    return {"_Ctx": _Ctx, "_FullCtx": _FullCtx, "_FiniteALCtx": _FiniteALCtx}


@pytest.mark.parametrize("name", sorted(_step_systems()))
def test_friction_step_systems_declare_the_al_system(name):
    """Algorithms 6.2 / 6.4 drive a load step through the declared ``_ALSystem`` protocol: each of the three step
    systems (condensed direct, AMG, finite deformation) has every attribute (a dataclass field or a class member)
    and every method and property of it, the methods callable with the protocol's arguments."""
    import dataclasses

    from alcontact.contact.algorithms._coulomb import _ALSystem

    cls = _step_systems()[name]
    fields = {f.name for f in dataclasses.fields(cls)}
    missing = [a for a in _ALSystem.__annotations__ if a not in fields and not hasattr(cls, a)]
    assert missing == [], missing
    for member, value in vars(_ALSystem).items():
        if member.startswith("_"):
            continue
        if isinstance(value, property):
            # a property, a dataclass field or a class constant (a declared fact of that step system)
            assert member in fields or hasattr(cls, member), member
            assert not inspect.isfunction(getattr(cls, member, None)), member
        elif inspect.isfunction(value):
            params = list(inspect.signature(value).parameters.values())
            args = [object() for p in params if p.kind == p.POSITIONAL_OR_KEYWORD and p.default is p.empty]
            inspect.signature(getattr(cls, member)).bind(*args)
