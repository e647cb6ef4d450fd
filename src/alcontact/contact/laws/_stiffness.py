"""The automatic penalty stiffness shared by every contact solve (small and finite, with and without friction)."""

from __future__ import annotations


def _modulus(body) -> float:
    """``E' = E/(1-nu^2)`` in plane strain and 3D, ``E`` in plane stress, of ``body``'s material."""
    mat = body.material
    return mat.E if (body.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus


def penalty_stiffness(model, h: float, scale: float = 1.0, *, pair=None) -> float:
    """Automatic penalty stiffness ``scale * E' / h`` (pressure per length).

    ``E' = E/(1-nu^2)`` in plane strain and 3D, ``E`` in plane stress: the
    stiffness of a layer of thickness ``h`` under uniaxial strain, so the
    penalty spring is as stiff as the first element row under the surface.

    ``pair`` (a :class:`~alcontact.contact.ContactPair` whose master is a deformable body): the
    two first element rows in series, :math:`E' = E'_s E'_m / (E'_s + E'_m)`, which tends to the
    slave's own (the rigid obstacle's penalty) as the master stiffens; without it ``model.material``
    (of several bodies: the stiffest one's).
    """
    if pair is not None and not getattr(pair, "rigid", True):
        es, em = _modulus(pair.slave.body), _modulus(pair.master.body)
        return scale * (es * em / (es + em)) / h
    return scale * _modulus(model) / h
