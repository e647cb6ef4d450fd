"""Finite-element layer: a thin wrapper over scikit-fem.

Meshes with named boundaries (:mod:`alcontact.fem.meshes`), isotropic
materials (:class:`Material`), small-strain linear elasticity with P1/P2
simplices (:class:`LinearElasticity`), total Lagrangian hyperelastic bodies
(:class:`Hyperelastic`, laws by name from :func:`make_material` or by strain
energy with :class:`SymbolicMaterial`), a reusable sparse factorization
(:class:`Factorization`) and the chapter 4 model problems
(:mod:`alcontact.fem.model_problems`).

Examples
--------
>>> from alcontact.fem import Material, LinearElasticity, meshes
>>> model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1.0e3, nu=0.3), order=2)
>>> model.ndofs
50
"""

from alcontact.fem import meshes, model_problems
from alcontact.fem._body import Body
from alcontact.fem._multibody import MultiBody
from alcontact.fem._geometry import GEOMETRIES, check_geometry
from alcontact.fem._hyper_materials import (
    HyperelasticLaw,
    NeoHookean,
    SaintVenantKirchhoff,
    SymbolicMaterial,
    available_materials,
    example_material_parameters,
    make_material,
    material_parameters,
    register_material,
)
from alcontact.fem._hyper_laws import (
    ArrudaBoyce,
    EnergyExpression,
    Gent,
    MooneyRivlin,
    Ogden,
    Yeoh,
    check_material_parameters,
)
from alcontact.fem._linalg import Factorization, nested_dissection
from alcontact.fem._material import Material, material_issues
from alcontact.fem.elasticity import LinearElasticity, numerical_rank, rigid_body_modes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.fem.mixed import MixedHyperelastic

__all__ = [
    "ArrudaBoyce",
    "Body",
    "EnergyExpression",
    "Gent",
    "MooneyRivlin",
    "Ogden",
    "Yeoh",
    "Factorization",
    "GEOMETRIES",
    "check_geometry",
    "Hyperelastic",
    "HyperelasticLaw",
    "LinearElasticity",
    "Material",
    "MixedHyperelastic",
    "MultiBody",
    "material_issues",
    "numerical_rank",
    "NeoHookean",
    "SaintVenantKirchhoff",
    "SymbolicMaterial",
    "available_materials",
    "check_material_parameters",
    "example_material_parameters",
    "make_material",
    "material_parameters",
    "register_material",
    "meshes",
    "model_problems",
    "nested_dissection",
    "rigid_body_modes",
]
