"""Uniaxial tension of the rubber laws against their closed-form nominal stress curves.

References (incompressible uniaxial tension, stretch lambda, I1 = lambda^2 + 2/lambda, nominal stress
P = force per reference area; the forms as collected in Holzapfel, Nonlinear Solid Mechanics, 2000,
section 6.5, and in the cited papers):

* neo-Hookean (Treloar 1943):        P = mu (lambda - lambda^-2)
* Mooney-Rivlin (Mooney 1940, Rivlin 1948): P = 2 (lambda - lambda^-2) (c10 + c01 / lambda)
* Yeoh (Yeoh 1993):                  P = 2 (lambda - lambda^-2) (c10 + 2 c20 (I1-3) + 3 c30 (I1-3)^2)
* Gent (Gent 1996):                  P = mu Jm (lambda - lambda^-2) / (Jm - I1 + 3)
* Arruda-Boyce (Arruda and Boyce 1993, five-term series):
                                     P = 2 (lambda - lambda^-2) mu_c sum_i i C_i I1^(i-1) / lambda_m^(2i-2)
* Ogden (Ogden 1972):                P = sum_p mu_p (lambda^(alpha_p - 1) - lambda^(-alpha_p/2 - 1))

Which limit: the INCOMPRESSIBLE one. The laws are compressible (volumetric term K/2 (J-1)^2), so

1. pointwise, the law is evaluated on the isochoric uniaxial state F = diag(lambda, lambda^-1/2,
   lambda^-1/2) (J = 1, where the volumetric stress vanishes) and the lateral traction is removed by
   the incompressibility pressure: P = P11 - (F22 / F11) P22. This must equal the closed form to
   round-off (1e-12 relative) over lambda in [0.5, 3];
2. the compressible homogeneous state (lateral stretch s from P22 = 0) tends to the incompressible
   curve as the bulk modulus grows: the error falls like 1/K (ratio ~10 per decade of K);
3. end to end, a 3D finite-element cube (Hyperelastic body: its assembled force and tangent in a
   Newton loop) stretched to lambda = 1.6 with free lateral faces reproduces the compressible homogeneous state to 1e-9 and, at nu = 0.4999
   (K = 5000 mu), the incompressible closed form to 1e-3 (the 1/K term).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from alcontact.fem import Hyperelastic, Material, available_materials, make_material, meshes
from alcontact.fem import example_material_parameters

MU = 0.9  # initial shear modulus of every documented example law (and of neo-Hookean below)
AB_C = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)


def _closed_form(name, p, lam):
    """Incompressible uniaxial nominal stress of law ``name`` with parameters ``p`` (module doc)."""
    I1 = lam**2 + 2 / lam
    g = lam - lam**-2
    if name == "neo-hookean":
        return MU * g
    if name == "mooney-rivlin":
        return 2 * g * (p["c10"] + p["c01"] / lam)
    if name == "yeoh":
        x = I1 - 3
        return 2 * g * (p["c10"] + 2 * p.get("c20", 0.0) * x + 3 * p.get("c30", 0.0) * x**2)
    if name == "gent":
        return MU * p["Jm"] * g / (p["Jm"] - I1 + 3)
    if name == "arruda-boyce":
        lm = p["lambda_m"]
        factor = 2 * sum(i * c * 3 ** (i - 1) / lm ** (2 * i - 2) for i, c in enumerate(AB_C, 1))
        muc = MU / factor
        return 2 * g * muc * sum(i * c * I1 ** (i - 1) / lm ** (2 * i - 2) for i, c in enumerate(AB_C, 1))
    if name == "ogden":
        return sum(m * (lam ** (a - 1) - lam ** (-a / 2 - 1)) for m, a in zip(p["mu"], p["alpha"]))
    raise KeyError(name)


RUBBER = ["neo-hookean", "mooney-rivlin", "yeoh", "gent", "arruda-boyce", "ogden"]


def test_every_rubber_law_of_the_registry_has_a_closed_form_here():
    """A newly registered law must add its closed form to this file (Saint Venant-Kirchhoff is not a rubber
    law: its uniaxial response softens and has no place among these curves)."""
    assert sorted(set(available_materials()) - {"saint-venant-kirchhoff"}) == sorted(RUBBER)


def _law(name):
    p = example_material_parameters(name)
    return make_material(name, **p), p


@pytest.mark.parametrize("name", RUBBER)
def test_isochoric_uniaxial_nominal_stress_equals_the_closed_form(name):
    law, p = _law(name)
    lam_ = np.linspace(0.5, 3.0, 26)
    s = lam_**-0.5
    F = np.zeros((lam_.size, 3, 3))
    F[:, 0, 0], F[:, 1, 1], F[:, 2, 2] = lam_, s, s
    K = 50.0 * MU
    P = law.stress(F, K - 2 * MU / 3, MU)
    nominal = P[:, 0, 0] - s / lam_ * P[:, 1, 1]
    ref = np.array([_closed_form(name, p, x) for x in lam_])
    np.testing.assert_allclose(nominal, ref, rtol=1e-12, atol=1e-13)
    assert np.all(np.diff(nominal) > 0)  # monotone: stable in tension and compression over the range


def _compressible(law, lam, K):
    """Homogeneous uniaxial state F = diag(lam, s, s) with P22 = 0: (s, P11)."""
    lame = K - 2 * MU / 3

    def p22(s):
        return law.stress(np.diag([lam, s, s])[None], lame, MU)[0, 1, 1]

    s = brentq(p22, 0.3 * lam**-0.5, 3.0 * lam**-0.5, xtol=1e-15, rtol=1e-15)
    return s, law.stress(np.diag([lam, s, s])[None], lame, MU)[0, 0, 0]


@pytest.mark.parametrize("name", RUBBER)
def test_compressible_uniaxial_stress_tends_to_the_incompressible_curve_like_one_over_K(name):
    law, p = _law(name)
    lam = 1.8
    ref = _closed_form(name, p, lam)
    errors = [abs(_compressible(law, lam, k * MU)[1] - ref) / ref for k in (1e2, 1e3, 1e4)]
    assert errors[-1] < 1e-3
    assert 5.0 < errors[0] / errors[1] < 20.0 and 5.0 < errors[1] / errors[2] < 20.0, errors


@pytest.mark.parametrize("name", ["mooney-rivlin", "ogden", "gent"])
def test_finite_element_cube_in_uniaxial_tension(name):
    """One-eighth symmetry cube [0,1]^3 (2x2x2 cells, P1), u_x = lam - 1 on x = 1, symmetry planes x, y, z = 0,
    lateral faces free, nu = 0.4999. Newton on the assembled internal force and tangent (sparse LU), started
    from the incompressible homogeneous guess. The state is homogeneous, so the FE solution is the exact one:
    reaction force = P11 of the compressible homogeneous state to 1e-9, lateral contraction to 1e-9, and the
    incompressible closed form within 1e-3 (the 1/K term at K = 5000 mu)."""
    import scipy.sparse.linalg as spla

    law, p = _law(name)
    lam, nu = 1.6, 0.4999
    mat = Material(E=2 * MU * (1 + nu), nu=nu)
    body = Hyperelastic(meshes.box(0, 1, 0, 1, 0, 1, 2, 2, 2), mat, model=law)
    fixed = {}
    for face, comp, value in [("left", 0, 0.0), ("front", 1, 0.0), ("bottom", 2, 0.0), ("right", 0, lam - 1.0)]:
        fixed.update({int(d): value for d in body.node_dofs(face)[1][:, comp]})
    dofs = np.array(sorted(fixed))
    free = np.setdiff1d(np.arange(body.ndofs), dofs)
    s0 = lam**-0.5
    u = body.interpolate(lambda x: np.stack([(lam - 1) * x[0], (s0 - 1) * x[1], (s0 - 1) * x[2]]))
    u[dofs] = [fixed[d] for d in dofs]
    for _ in range(20):
        r = body.internal_force(u)[free]
        if np.linalg.norm(r) <= 1e-12 * MU:
            break
        K = body.tangent(u)[free][:, free].tocsc()
        u[free] -= spla.spsolve(K, r)
    assert np.linalg.norm(body.internal_force(u)[free]) <= 1e-12 * MU
    _, right = body.node_dofs("right")
    force = float(np.sum(body.internal_force(u)[right[:, 0]]))
    K = mat.E / (3 * (1 - 2 * nu))
    s, P11 = _compressible(law, lam, K)
    assert force == pytest.approx(P11, rel=1e-9)
    _, back = body.node_dofs("back")  # y = 1
    assert np.allclose(u[back[:, 1]], s - 1.0, atol=1e-9)
    assert force == pytest.approx(_closed_form(name, p, lam), rel=1e-3)
