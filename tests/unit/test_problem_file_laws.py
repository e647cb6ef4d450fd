"""Hyperelastic laws in problem files: ``[material] model`` with ``[material.parameters]``, and a user
``[material] energy``.

Every registered law loads from a file with its documented example parameters and the body runs that
law with those values (generated from the registry); E is derived from the moduli a law fixes, or
checked against them; bad parameters, bad expressions and conflicting keys are refused by
``alcontact check`` (exit code 2, no traceback) naming the key, the value and the way out.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from _helpers import assert_check_rejects, runner
from alcontact.cli import app
from alcontact.errors import ConfigError
from alcontact.fem import available_materials
from alcontact.fem import example_material_parameters
from alcontact.io.config import load_problem_text

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXAMPLE = (EXAMPLES / "finite_mooney_rivlin.toml").read_text(encoding="utf-8")
MATERIAL = 'model = "mooney-rivlin"\nnu = 0.45\nparameters = { c10 = 0.5, c01 = 0.1 }'
assert MATERIAL in EXAMPLE


def _toml_value(v) -> str:
    return "[" + ", ".join(repr(float(x)) for x in v) + "]" if isinstance(v, (list, tuple)) else repr(float(v))


def _with(material: str) -> str:
    return EXAMPLE.replace(MATERIAL, material)


def _load(text: str):
    return load_problem_text(text, base_dir=EXAMPLES)


@pytest.mark.parametrize("name", available_materials())
def test_every_registered_law_runs_from_a_file_with_its_parameters(name):
    params = example_material_parameters(name)
    table = ", ".join(f"{k} = {_toml_value(v)}" for k, v in params.items())
    consts = "nu = 0.45" + ("" if params else "\nE = 3.0")
    text = _with(f'model = "{name}"\n{consts}\n' + (f"parameters = {{ {table} }}" if params else ""))
    if "E = 3.0" not in text and name in ("gent", "arruda-boyce"):  # these take mu from E
        text = text.replace("nu = 0.45", "nu = 0.45\nE = 3.0")
    setup = _load(text)
    law = setup.problem.model.law
    assert law.name == name
    for key, value in params.items():
        got = getattr(law, key)
        assert list(map(float, got)) == list(value) if isinstance(value, list) else float(got) == value
    mu0 = law.fixed_moduli()[0]
    mat = setup.problem.model.material
    if mu0 is not None:  # E derived from the law: E = 2 mu0 (1 + nu)
        assert mat.E == pytest.approx(2 * mu0 * 1.45, rel=1e-14)
    assert f"finite deformation ({name})" in setup.summary_line()


def test_a_given_E_must_agree_with_the_law():
    with pytest.raises(ConfigError, match=r"material\.E = 3\.0: model 'mooney-rivlin' with these parameters has "
                                          r"initial shear modulus mu0 = 1\.2, so E = 2 mu0 \(1 \+ nu\) = 3\.48"):
        _load(_with(MATERIAL + "\nE = 3.0"))
    assert _load(_with(MATERIAL + "\nE = 3.48")).problem.model.material.E == 3.48


def test_user_energy_fixes_E_and_nu():
    setup = _load(_with('energy = "c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2"\n'
                        "parameters = { c10 = 0.5, c01 = 0.1, K = 11.6 }"))
    mat = setup.problem.model.material
    mu, K = 1.2, 11.6
    assert mat.E == pytest.approx(9 * K * mu / (3 * K + mu), rel=1e-12)
    assert mat.nu == pytest.approx((3 * K - 2 * mu) / (2 * (3 * K + mu)), rel=1e-12)
    assert setup.problem.model.law.name == "energy-expression"


def _file(tmp_path: Path, text: str) -> Path:
    shutil.copy(EXAMPLES / "half_cylinder.msh", tmp_path / "half_cylinder.msh")
    p = tmp_path / "p.toml"
    p.write_text(text, encoding="utf-8")
    return p


CASES = {
    "range": (_with('model = "mooney-rivlin"\nnu = 0.45\nparameters = { c10 = 0.1, c01 = -0.3 }'),
              ["material.parameters.c01 = -0.3", "c10 + c01 = -0.2 must be > 0"]),
    "typo": (_with('model = "mooney-rivlin"\nnu = 0.45\nparameters = { c10 = 0.5, c0l = 0.1 }'),
             ["material.parameters.c0l = 0.1", "not a parameter of material 'mooney-rivlin'",
              "Its parameters: c10, c01"]),
    "missing": (_with('model = "gent"\nnu = 0.45\nE = 3.0'),
                ["material.parameters.Jm", "missing (required by material 'gent')"]),
    "gent-E": (_with('model = "gent"\nnu = 0.45\nparameters = { Jm = 30.0 }'),
               ["material.E", "missing (required for model 'gent'"]),
    "ogden-terms": (_with('model = "ogden"\nnu = 0.45\nparameters = { mu = [1.0, 0.1], alpha = [2.0] }'),
                    ["material.parameters.alpha = [2.0]", "as many exponents as mu has terms (2)"]),
    "linear": (_with('model = "mooney-rivlin"\nnu = 0.45\nparameters = { c10 = 0.5, c01 = 0.1 }')
               .replace('kinematics = "finite"', 'kinematics = "small"').replace('"mooney-rivlin"', '"linear"')
               .replace("nu = 0.45", "nu = 0.45\nE = 3.0"),
               ["material.parameters", "not used by the linear elastic model"]),
    "both": (_with(MATERIAL + '\nenergy = "c10*(I1b-3)"'),
             ["material.energy", "given together with model = 'mooney-rivlin'"]),
    "energy-small": (_with('energy = "c10*(I1b-3) + K/2*(J-1)**2"\nparameters = { c10 = 0.5, K = 10.0 }')
                     .replace('kinematics = "finite"', 'kinematics = "small"'),
                     ["contact.kinematics = 'small'", "needs kinematics = 'finite'"]),
    "energy-code": (_with('energy = "c10*(I1b-3) + K/2*(J-1)**2 + __import__(\'os\').getpid()"\n'
                          "parameters = { c10 = 0.5, K = 10.0 }"),
                    ["material.energy = ", "is not allowed", "Allowed names: I1, I1b, I2, I2b, I3, J (invariants), "
                     "K, c10"]),
    "energy-name": (_with('energy = "c10*(I1b-3) + k/2*(J-1)**2"\nparameters = { c10 = 0.5, K = 10.0 }'),
                    ["material.energy = ", "unknown name 'k'", "Did you mean 'K'?"]),
    "energy-unused": (_with('energy = "c10*(I1b-3) + K/2*(J-1)**2"\nparameters = { c10 = 0.5, K = 10.0, c01 = 1.0 }'),
                      ["material.parameters.c01", "not used by material.energy"]),
    "energy-nu": (_with('energy = "c10*(I1b-3) + K/2*(J-1)**2"\nnu = 0.3\nparameters = { c10 = 0.5, K = 10.0 }'),
                  ["material.nu = 0.3", "so nu = 0.451612903", "remove nu"]),
    "energy-type": (_with('energy = 3.0\nparameters = { c10 = 0.5 }'),
                    ["material.energy = 3.0", "expected a string"]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_check_refuses_bad_laws_naming_the_key(tmp_path, case):
    text, expected = CASES[case]
    assert text != EXAMPLE
    result = runner.invoke(app, ["check", str(_file(tmp_path, text))])
    assert_check_rejects(result, expected)


def test_check_accepts_the_example(tmp_path):
    result = runner.invoke(app, ["check", str(_file(tmp_path, EXAMPLE))])
    assert result.exit_code == 0, result.output
    assert "finite deformation (mooney-rivlin)" in result.output.replace("\n", " ")
