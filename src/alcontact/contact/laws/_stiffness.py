"""The automatic penalty stiffness shared by every contact solve (small and finite, with and without friction)."""

from __future__ import annotations


def penalty_stiffness(model, h: float, scale: float = 1.0) -> float:
    """Automatic penalty stiffness ``scale * E' / h`` (pressure per length).

    ``E' = E/(1-nu^2)`` in plane strain and 3D, ``E`` in plane stress: the
    stiffness of a layer of thickness ``h`` under uniaxial strain, so the
    penalty spring is as stiff as the first element row under the surface.
    """
    mat = model.material
    e_prime = mat.E if (model.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus
    return scale * e_prime / h
