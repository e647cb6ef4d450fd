"""Unit tests of ``LinearElasticity(volumetric=...)``: the P2-P0 (projected volumetric strain) option."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from _helpers import assert_rigid_modes_in_kernel
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.fem.elasticity import VOLUMETRIC_FORMULATIONS

E, S = 200.0, 2.5  # modulus, applied tension


def _mesh(dim):
    if dim == 2:
        return meshes.rectangle(0.0, 2.0, 0.0, 1.0, 4, 3,
                                refine=dict(center=(0.7, 1.0), h_min=0.1, width=0.2, depth=0.2, growth=1.5))
    return meshes.box(0.0, 2.0, 0.0, 1.0, 0.0, 1.0, 3, 2, 2)


def test_registry_names_and_default():
    assert set(VOLUMETRIC_FORMULATIONS) == {"full", "p0"}
    model = LinearElasticity(_mesh(2), Material(E=E, nu=0.3), order=2)
    assert model.volumetric == "full"


@pytest.mark.parametrize("kwargs, match", [
    (dict(order=2, volumetric="b-bar"), "volumetric='b-bar' is not known; use one of 'full', 'p0'"),
    (dict(order=2, volumetric=None), "is not known"),
    (dict(order=1, volumetric="p0"), "needs order in \\(2,\\); got order=1"),
])
def test_bad_volumetric_option(kwargs, match):
    with pytest.raises(InputError, match=match):
        LinearElasticity(_mesh(2), Material(E=E, nu=0.3), **kwargs)


@pytest.mark.parametrize("dim, plane", [(2, "strain"), (2, "stress"), (3, "strain")])
@pytest.mark.parametrize("nu", [0.3, 0.4999])
def test_p0_uniaxial_tension_patch(dim, plane, nu):
    """Patch test: uniaxial tension S gives the exact linear field (to 1e-9) and exact stresses.

    A linear displacement has a constant divergence, which the element-wise
    projection keeps, so P2-P0 must reproduce it like the standard element.
    """
    model = LinearElasticity(_mesh(dim), Material(E=E, nu=nu, plane=plane), order=2, volumetric="p0")
    names = ["left", "bottom"] if dim == 2 else ["left", "front", "bottom"]
    sup = [model.dirichlet(n, components=[c]) for c, n in enumerate(names)]
    t = np.zeros(dim)
    t[0] = S
    u = model.solve(model.traction_load("right", t), dirichlet=sup)
    if dim == 3 or plane == "stress":
        exx, eyy = S / E, -nu * S / E
    else:
        exx, eyy = (1 - nu**2) * S / E, -nu * (1 + nu) * S / E
    u_ex = model.interpolate(lambda x: np.array([exx * x[0]] + [eyy * x[i] for i in range(1, dim)]))
    assert np.max(np.abs(u - u_ex)) <= 1e-9 * np.max(np.abs(u_ex))
    sig = model.stress(u, include_zz=dim == 2)
    expected = np.zeros(sig.shape[1])
    expected[0] = S
    if dim == 2 and plane == "strain":
        expected[3] = nu * S  # szz = nu S in plane strain
    assert np.allclose(sig, expected, atol=1e-8 * S)


@pytest.mark.parametrize("dim", [2, 3])
def test_p0_stiffness_symmetric_positive_definite_with_rigid_kernel(dim):
    """K = K_dev + kappa B^T M0^-1 B: symmetric, rigid motions in its kernel, positive on the rest."""
    model = LinearElasticity(_mesh(dim), Material(E=E, nu=0.4999), order=2, volumetric="p0")
    K = model.stiffness()
    assert abs(K - K.T).max() == 0.0
    assert_rigid_modes_in_kernel(model, K)
    # supported on the left face: a Cholesky-type factor exists (SPD), and energies are positive
    fixed, _ = model.dirichlet("left")
    fac = model.factorize(fixed)
    rng = np.random.default_rng(0)
    v = rng.standard_normal(model.ndofs)
    v[fixed] = 0.0
    assert v @ (K @ v) > 0.0
    assert np.all(np.isfinite(fac.solve_full(K @ v, np.zeros(fixed.size))))


def test_p0_same_energy_as_full_for_linear_fields_and_softer_otherwise():
    """The projection only changes the energy of fields whose divergence varies in an element.

    For a linear field both stiffnesses give the same energy (to 1e-12); for any
    field the P2-P0 energy is at most the full one (Pi_0 is an L2 projection:
    ||Pi_0 div u|| <= ||div u||).
    """
    mesh = _mesh(2)
    mat = Material(E=E, nu=0.45)
    full = LinearElasticity(mesh, mat, order=2)
    p0 = LinearElasticity(mesh, mat, order=2, volumetric="p0")
    lin = full.interpolate(lambda x: np.array([0.3 * x[0] - 0.1 * x[1], 0.2 * x[0] + 0.5 * x[1]]))
    assert p0.strain_energy(lin) == pytest.approx(full.strain_energy(lin), rel=1e-12)
    rng = np.random.default_rng(1)
    for _ in range(5):
        v = rng.standard_normal(full.ndofs)
        assert p0.strain_energy(v) <= full.strain_energy(v) * (1 + 1e-12)


# ------------------------------------------------------------ problem files
_EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "cattaneo_mindlin.toml"


def test_problem_file_volumetric_option():
    """``[mesh] volumetric`` reaches the model; a bad value names the key and the registered choices."""
    from alcontact.errors import ConfigError
    from alcontact.io.config import load_problem_text

    text = _EXAMPLE.read_text(encoding="utf-8")
    assert 'volumetric = "p0"' in text
    setup = load_problem_text(text)
    assert setup.problem.model.volumetric == "p0"
    with pytest.raises(ConfigError, match=r"mesh\.volumetric.*'full', 'p0'"):
        load_problem_text(text.replace('volumetric = "p0"', 'volumetric = "b-bar"'))
    with pytest.raises(ConfigError, match=r"mesh\.(order|volumetric).*order=2 with 'p0'"):
        load_problem_text(text.replace("order = 2", "order = 1"))
