"""Unit tests of the parametrized hyperelastic laws (Mooney-Rivlin, Yeoh, Gent, Arruda-Boyce, Ogden),
their declared parameters and stability ranges, the consistency with the body's Material, and the user
energy expression (alcontact.fem._hyper_laws, alcontact.fem._energy_expression).

The finite-difference checks of stress and tangent of every registered law (generated from the
registry) are in test_fem_hyperelastic.py; here: the branches those random F do not reach (equal
principal stretches of Ogden), and what is specific to parameters and user expressions.

Reaches inside the package: unit tests of private modules (``fem._hyper_laws``, the user energy-
expression parser ``fem._energy_expression``), which have no public names.
"""

from __future__ import annotations

import builtins

import numpy as np
import pytest

from alcontact.errors import InputError
from alcontact.fem import (
    EnergyExpression,
    Hyperelastic,
    Material,
    MooneyRivlin,
    NeoHookean,
    Ogden,
    available_materials,
    make_material,
    meshes,
)
from alcontact.fem._energy_expression import parse_energy
from alcontact.fem import check_material_parameters, example_material_parameters

LAM, MU = 1.7, 0.9


def _fd_check(law, F, lam=LAM, mu=MU, h=1e-6, rtol=1e-7):
    """Central differences of W -> P and of P -> A at the stack F (relative error below rtol)."""
    d = F.shape[-1]
    P, A = law.stress(F, lam, mu), law.tangent(F, lam, mu)
    for k in range(d):
        for m in range(d):
            dF = np.zeros((d, d))
            dF[k, m] = h
            dW = (law.energy(F + dF, lam, mu) - law.energy(F - dF, lam, mu)) / (2 * h)
            assert np.max(np.abs(dW - P[:, k, m])) <= rtol * max(np.abs(P).max(), 1.0)
            dP = (law.stress(F + dF, lam, mu) - law.stress(F - dF, lam, mu)) / (2 * h)
            assert np.max(np.abs(dP - A[:, :, :, k, m])) <= rtol * np.abs(A).max()


# ------------------------------------------------------------- Ogden spectral branches
@pytest.mark.parametrize("d", [2, 3])
def test_ogden_tangent_at_equal_and_nearly_equal_stretches(d):
    """The l'Hopital limit (Holzapfel eq. 6.197) at F = I, at two equal stretches, and just beside them
    (stretches 1e-7 apart, where the difference quotient is replaced by the limit) matches finite
    differences to 1e-7 relative."""
    law = make_material("ogden", **example_material_parameters("ogden"))
    R = np.linalg.qr(np.random.default_rng(0).standard_normal((3, 3)))[0]
    stacks = [np.eye(3), np.diag([1.3, 0.9, 0.9]), np.diag([0.8, 0.8, 0.8]), np.diag([1.2, 1.0 + 1e-7, 1.0]),
              R @ np.diag([1.1, 1.1, 0.7])]
    F = np.stack(stacks)
    if d == 2:
        F = np.stack([np.eye(2), np.diag([1.2, 1.0]), np.diag([1.1, 1.1]), np.diag([0.9, 0.9 + 1e-7]),
                      np.array([[1.0, 0.3], [0.0, 1.0]])])
    _fd_check(law, F)


def test_ogden_two_terms_alpha_2_is_mooney_rivlin_at_unit_jacobian():
    """Ogden with (mu, alpha) = (2 c10, 2), (-2 c01, -2) is Mooney-Rivlin: lb1^2+lb2^2+lb3^2 = I1b and
    lb1^-2+lb2^-2+lb3^-2 = I2b; energies, stresses and tangents agree to 1e-12 at random F."""
    c10, c01 = 0.35, 0.1
    og, mr = Ogden([2 * c10, -2 * c01], [2.0, -2.0]), MooneyRivlin(c10, c01)
    rng = np.random.default_rng(3)
    F = np.eye(3) + 0.25 * rng.standard_normal((20, 3, 3))
    F = F[np.linalg.det(F) > 0.2]
    for what in ("energy", "stress", "tangent"):
        a, b = getattr(og, what)(F, LAM, MU), getattr(mr, what)(F, LAM, MU)
        np.testing.assert_allclose(a, b, rtol=1e-11, atol=1e-11 * np.abs(b).max())


# ------------------------------------------------------------- declared parameters and ranges
BAD_PARAMETERS = [
    ("mooney-rivlin", {"c10": 0.1, "c01": -0.2}, "c01", "c10 \\+ c01"),
    ("mooney-rivlin", {"c01": 0.1}, "c10", "missing"),
    ("mooney-rivlin", {"c10": 0.3, "c11": 0.1}, "c11", "Did you mean"),
    ("yeoh", {"c10": 0.0}, "c10", "out of range"),
    ("yeoh", {"c10": 0.5, "c20": -0.1, "c30": 0.001}, "c20", "c20\\^2 < 3 c10 c30"),
    ("yeoh", {"c10": 0.5, "c30": -0.1}, "c30", "out of range"),
    ("gent", {"Jm": 0.0}, "Jm", "out of range"),
    ("arruda-boyce", {"lambda_m": 1.0}, "lambda_m", "out of range"),
    ("ogden", {"mu": [1.0], "alpha": [0.0]}, "alpha", "nonzero"),
    ("ogden", {"mu": [1.0, 0.1], "alpha": [2.0]}, "alpha", "as many exponents"),
    ("ogden", {"mu": [-1.0], "alpha": [2.0]}, "mu", "sum\\(mu_p alpha_p\\)"),
    ("ogden", {"mu": [1.0] * 7, "alpha": [2.0] * 7}, "mu", "needs 1 or 2"),
    ("neo-hookean", {"c10": 1.0}, "c10", "none \\(it takes its constants from E and nu\\)"),
]


@pytest.mark.parametrize("name, params, key, text", BAD_PARAMETERS)
def test_out_of_range_parameters_are_refused_with_the_parameter_named(name, params, key, text):
    values, issues = check_material_parameters(name, params)
    assert issues and any(k.startswith(key) for k, _ in issues), issues
    assert any(__import__("re").search(text, m) for _, m in issues), issues
    with pytest.raises(InputError, match=key):
        make_material(name, **params)


def test_every_registered_law_has_a_valid_documented_example():
    for name in available_materials():
        values, issues = check_material_parameters(name, example_material_parameters(name))
        assert issues == []
        make_material(name, **example_material_parameters(name))


def test_yeoh_stability_check_is_exact():
    """The Yeoh condition accepts exactly the (c10, c20, c30) with c10 + 2 c20 x + 3 c30 x^2 > 0 on a fine
    grid of x in [0, 1e4] (random parameters; none near the boundary is drawn with probability 1)."""
    rng = np.random.default_rng(11)
    x = np.concatenate([np.linspace(0, 10, 20001), np.logspace(1, 4, 2000)])
    for _ in range(300):
        c10, c20, c30 = rng.uniform(0.01, 1.0), rng.uniform(-0.3, 0.3), rng.uniform(0.0, 0.02)
        _, issues = check_material_parameters("yeoh", {"c10": c10, "c20": c20, "c30": c30})
        positive = bool(np.all(c10 + 2 * c20 * x + 3 * c30 * x * x > 0))
        if abs(c20 * c20 - 3 * c10 * c30) > 1e-3 * c20 * c20:  # away from the tangency where a grid cannot decide
            assert (issues == []) == positive, (c10, c20, c30)


def test_parameters_take_effect():
    """Different parameters give different stresses (the values are used, not the defaults)."""
    F = np.diag([1.4, 0.9, 0.85])[None]
    for name, a, b in [("mooney-rivlin", {"c10": 0.35, "c01": 0.1}, {"c10": 0.35, "c01": 0.2}),
                       ("yeoh", {"c10": 0.45}, {"c10": 0.45, "c30": 0.1}),
                       ("gent", {"Jm": 20.0}, {"Jm": 2.0}),
                       ("arruda-boyce", {"lambda_m": 3.0}, {"lambda_m": 1.5}),
                       ("ogden", {"mu": [0.9], "alpha": [2.0]}, {"mu": [0.6], "alpha": [3.0]})]:
        Pa = make_material(name, **a).stress(F, LAM, MU)
        Pb = make_material(name, **b).stress(F, LAM, MU)
        assert np.abs(Pa - Pb).max() > 1e-3 * np.abs(Pa).max(), name


# ------------------------------------------------------------- consistency with the Material
def test_body_refuses_a_material_whose_shear_modulus_differs_from_the_law():
    mesh = meshes.rectangle(0, 1, 0, 1, 2, 2)
    law = MooneyRivlin(c10=0.35, c01=0.1)  # mu0 = 0.9
    with pytest.raises(InputError, match=r"shear modulus 0\.9.*Material\(E=2\.34, nu=0\.3\)"):
        Hyperelastic(mesh, Material(E=10.0, nu=0.3), model=law)
    body = Hyperelastic(mesh, Material(E=2 * 0.9 * 1.3, nu=0.3), model=law)
    assert body.law is law
    # the linearization at u = 0 is the material's linear elasticity (tangent(0) = stiffness of E, nu)
    from alcontact.fem import LinearElasticity

    K = LinearElasticity(mesh, Material(E=2.34, nu=0.3)).stiffness()
    assert abs(body.tangent(np.zeros(body.ndofs)) - K).max() <= 1e-12 * abs(K).max()


@pytest.mark.parametrize("name", ["gent", "arruda-boyce", "neo-hookean"])
def test_laws_without_a_fixed_modulus_take_mu_from_the_material(name):
    """Gent and Arruda-Boyce (scaled so that mu0 = mu) linearize to the material's (lambda, mu) exactly."""
    law = make_material(name, **example_material_parameters(name))
    assert law.fixed_moduli() == (None, None)
    lam0, mu0 = law.reference_moduli(LAM, MU)
    assert lam0 == pytest.approx(LAM, rel=1e-13) and mu0 == pytest.approx(MU, rel=1e-13)


# ------------------------------------------------------------- the user energy expression
def test_energy_expression_of_mooney_rivlin_equals_the_builtin_law():
    c10, c01 = 0.35, 0.1
    K = LAM + 2 * MU / 3
    user = EnergyExpression("c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2", {"c10": c10, "c01": c01, "K": K})
    mr = MooneyRivlin(c10, c01)
    rng = np.random.default_rng(5)
    for d in (2, 3):
        F = np.eye(d) + 0.25 * rng.standard_normal((20, d, d))
        F = F[np.linalg.det(F) > 0.2]
        for what in ("energy", "stress", "tangent"):
            a, b = getattr(user, what)(F, LAM, MU), getattr(mr, what)(F, LAM, MU)
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    assert user.fixed_moduli() == pytest.approx((2 * (c10 + c01), K), rel=1e-12)


@pytest.mark.parametrize("text", [
    "mu/2*(I1-3) - mu*log(J) + lam/2*log(J)**2",
    "mu/2*(I1-3) - mu/2*log(I3) + lam/8*log(I3)**2",
    "mu/2*(I1-3) - mu*log(sqrt(I3)) + lam/2*(log(J))**2",
    "+mu/2*(I1 - 3.0) - -(-mu)*log(exp(log(J))) + lam/2*log(J)**2",
])
def test_energy_expression_forms_of_neo_hookean(text):
    """Every invariant (I1, I3, J) and function (log, sqrt, exp) is read as documented: each spelling
    of the compressible neo-Hookean energy equals the built-in law (1e-12)."""
    lam, mu = 1.3, 0.7
    user = EnergyExpression(text, {"lam": lam, "mu": mu})
    nh = NeoHookean()
    F = np.eye(3) + 0.2 * np.random.default_rng(2).standard_normal((10, 3, 3))
    for what in ("energy", "stress", "tangent"):
        a, b = getattr(user, what)(F, 0.0, 0.0), getattr(nh, what)(F, lam, mu)
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())


def test_energy_expression_with_exp_against_finite_differences():
    user = EnergyExpression("a/(2*b)*(exp(b*(I1b-3))-1) + c*(I2b-3) + K/2*(J-1)**2 + K/10*(J-1)**4",
                            {"a": 0.5, "b": 0.8, "c": 0.05, "K": 20.0})
    rng = np.random.default_rng(8)
    for d in (2, 3):
        F = np.eye(d) + 0.2 * rng.standard_normal((10, d, d))
        _fd_check(user, F[np.linalg.det(F) > 0.3])


BAD_TEXTS = [
    ("__import__('os').system('echo hacked')", "__import__('os').system\" is not allowed"),
    ("__import__('os')", "a call of '__import__' is not allowed"),
    ("I1.__class__", "attribute access"),
    ("(lambda: 1)()", "a call of"),
    ("[I1][0]", "indexing"),
    ("[I1]", "List"),
    ("I1 if J else I2", "if/else"),
    ("I1 < 2", "comparison"),
    ("'c10' * I1", "the constant 'c10'"),
    ("1j * I1", "the constant 1j"),
    ("True * I1", "the constant True"),
    ("log(I1, 2)", "exactly one argument"),
    ("log(x=I1)", "exactly one argument"),
    ("I1 // 2", "FloorDiv"),
    ("I1 % 2", "Mod"),
    ("I1 @ J", "MatMult"),
    ("sin(I1)", "a call of 'sin'"),
    ("c10*(I1b-3) + x", "unknown name 'x'"),
    ("c10*(Ib1-3)", "unknown name 'Ib1' (declare it in parameters if it is a parameter). Did you mean"),
    ("2.0**2.0**2.0**2.0**2.0 * I1", "not a finite"),
    ("1/0 * I1", "division by zero"),
    ("I1/(J-J)", "division by zero"),
    ("exp(1000.0)*I1", "not a finite"),
    ("sqrt(-1)*I1", "not a finite"),
    ("I1; import os", "not a valid expression"),
    ("(" * 400 + "I1" + ")" * 400, "nested"),
    ("c10 + 3", "does not depend on the deformation"),
    ("", "empty"),
]


@pytest.mark.parametrize("text, fragment", BAD_TEXTS)
def test_bad_energy_expressions_are_refused_with_the_token_and_the_allowed_names(text, fragment):
    with pytest.raises(InputError) as info:
        EnergyExpression(text, {"c10": 0.5}, key="material.energy")
    msg = str(info.value)
    assert msg.startswith("material.energy"), msg
    assert fragment in msg, msg
    if "unknown name" in fragment or "a call of" in fragment:
        assert "Allowed names: I1, I1b, I2, I2b, I3, J (invariants), c10." in msg


def test_parsing_never_evaluates_python():
    """parse_energy builds the expression without eval/exec, and compiles the text only to a syntax tree
    (ast.parse is compile(..., PyCF_ONLY_AST)); the patched builtins record any other use."""
    import ast

    calls = []
    saved = {name: getattr(builtins, name) for name in ("eval", "exec", "compile")}

    def refuse(name):
        def f(*args, **kwargs):
            calls.append(name)
            raise RuntimeError(f"{name} called")
        return f

    def compile_ast_only(source, filename, mode, flags=0, *args, **kwargs):
        if not flags & ast.PyCF_ONLY_AST:
            calls.append("compile")
            raise RuntimeError("compile to code called")
        return saved["compile"](source, filename, mode, flags, *args, **kwargs)

    builtins.eval, builtins.exec, builtins.compile = refuse("eval"), refuse("exec"), compile_ast_only
    try:
        expr = parse_energy("c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2 + 0.1*exp(log(sqrt(I3)))",
                            {"c10": 0.3, "c01": 0.1, "K": 5.0})
    finally:
        builtins.eval, builtins.exec, builtins.compile = saved["eval"], saved["exec"], saved["compile"]
    assert calls == []
    assert {str(s) for s in expr.free_symbols} == {"I1", "I2", "J", "p_c10", "p_c01", "p_K"}


@pytest.mark.parametrize("params, key, fragment", [
    ({"c10": 0.5, "K": 10.0, "c01": 0.1}, "parameters.c01", "not used"),
    ({"c10": 0.5, "K": "10"}, "parameters.K", "finite number"),
    ({"c10": 0.5, "K": float("nan")}, "parameters.K", "finite number"),
    ({"c10": 0.5, "K": 10.0, "J": 1.0}, "parameters.J", "invariant or function name"),
])
def test_bad_energy_parameters(params, key, fragment):
    with pytest.raises(InputError, match=fragment) as info:
        EnergyExpression("c10*(I1b-3) + K/2*(J-1)**2", params)
    assert str(info.value).startswith(key)


@pytest.mark.parametrize("text, fragment", [
    ("c10*(I1-3) + K/2*(J-1)**2", "not stress free"),
    ("-c10*(I1b-3) + K/2*(J-1)**2", "must both be > 0"),
    ("c10*(I1b-3)", "must both be > 0"),
])
def test_energy_expression_must_be_a_stable_stress_free_solid(text, fragment):
    with pytest.raises(InputError, match=fragment):
        EnergyExpression(text, {"c10": 0.5, "K": 10.0} if "K" in text else {"c10": 0.5})


def test_gent_beyond_its_locking_is_a_rejected_state_not_a_number():
    """Beyond I1b - 3 = Jm the Gent energy is undefined: the body raises LawDomainError (an
    InvertedElementError, so Newton solvers reject the step and cut back) naming the elements, instead of
    returning NaN (energy) or finite values of a meaningless branch (force, tangent)."""
    from alcontact.errors import InvertedElementError, LawDomainError

    law = make_material("gent", Jm=0.5)
    body = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=2 * MU * 1.3, nu=0.3), model=law)
    far = body.interpolate(lambda x: np.stack([1.0 * x[0], 0 * x[1]]))  # stretch 2: I1b - 3 ~ 1.3 > Jm
    for f in (body.energy, body.internal_force, body.tangent):
        with pytest.raises(LawDomainError, match=r"8 of 8 elements.*'gent'.*Jm") as info:
            f(far)
        assert isinstance(info.value, InvertedElementError) and info.value.elements.tolist() == list(range(8))
    near = body.interpolate(lambda x: np.stack([0.2 * x[0], 0 * x[1]]))  # I1b - 3 ~ 0.05 < Jm
    assert np.isfinite(body.energy(near)) and np.all(np.isfinite(body.internal_force(near)))
    F = np.diag([1.2, 1.0, 1.0])[None]
    assert not law.domain_violation(F).any() and law.domain_violation(np.diag([2.0, 1.0, 1.0])[None]).all()
