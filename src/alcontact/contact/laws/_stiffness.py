"""The automatic penalty stiffness shared by every contact solve (small and finite, with and without friction)."""

from __future__ import annotations


def _modulus(body) -> float:
    """``E' = E/(1-nu^2)`` in plane strain and 3D, ``E`` in plane stress, of ``body``'s material."""
    mat = body.material
    return mat.E if (body.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus


def penalty_stiffness(model, h: float, scale: float = 1.0, *, pairs=None) -> float:
    """Automatic penalty stiffness ``scale * E' / h`` (pressure per length).

    ``E' = E/(1-nu^2)`` in plane strain and 3D, ``E`` in plane stress: the
    stiffness of a layer of thickness ``h`` under uniaxial strain, so the
    penalty spring is as stiff as the first element row under the surface.

    ``pairs`` (the :class:`~alcontact.contact.ContactPair` objects of a problem with a deformable
    master): per pair the two first element rows in series, :math:`E' = E'_s E'_m / (E'_s + E'_m)`
    (the slave's own against a rigid master), which tends to the rigid obstacle's penalty as the
    master stiffens; the smallest of the pairs. Without them ``model.material`` (of several bodies:
    the stiffest one's).
    """
    if pairs:
        moduli = []
        for pair in pairs:
            es = _modulus(pair.slave.body)
            em = None if getattr(pair, "rigid", True) else _modulus(pair.master.body)
            moduli.append(es if em is None else es * em / (es + em))
        return scale * min(moduli) / h
    return scale * _modulus(model) / h
