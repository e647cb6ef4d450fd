"""``[[material.region]]`` with ``nu = 0.5`` (exactly incompressible): accepted where the body supports it.

The mixed u-p body is the one body with ``nu = 0.5`` (its pressure the multiplier of J = 1). A region that
says ``nu = 0.5`` with a ``[material]`` that says it too builds that body; on a body that cannot take
it (``formulation = "displacement"``) the error names ``material.nu`` and the way out; a region whose ``nu``
differs from ``[material]`` (0.5 against 0.4999) is the "several materials" error, as for any constant.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest

from alcontact.errors import ConfigError
from alcontact.fem import MixedHyperelastic
from alcontact.io import load_problem

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _file(tmp_path: Path, material_nu: str, region_nu: str, extra: str = "") -> Path:
    shutil.copy(EXAMPLES / "half_cylinder.msh", tmp_path / "half_cylinder.msh")
    text = (EXAMPLES / "finite_half_cylinder.toml").read_text(encoding="utf-8")
    text = text.replace('file = "half_cylinder.msh"', 'file = "half_cylinder.msh"\norder = 2')
    text = text.replace("nu = 0.3", f"nu = {material_nu}{extra}")
    text += f'\n[[material.region]]\nname = "body"\nE = 1000.0\nnu = {region_nu}\n'
    p = tmp_path / "p.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_a_region_with_nu_one_half_builds_the_incompressible_mixed_body(tmp_path):
    setup = load_problem(_file(tmp_path, "0.5", "0.5"))
    body = setup.problem.model
    assert isinstance(body, MixedHyperelastic) and body.nu == 0.5 and math.isinf(body.kappa)


def test_a_region_with_nu_one_half_on_a_displacement_body_names_the_key_and_the_way_out(tmp_path):
    with pytest.raises(ConfigError) as err:
        load_problem(_file(tmp_path, "0.5", "0.5", '\nformulation = "displacement"'))
    msg = " ".join(str(err.value).split())
    assert "material.nu" in msg and "mixed" in msg


def test_a_region_nu_different_from_the_material_is_refused(tmp_path):
    with pytest.raises(ConfigError) as err:
        load_problem(_file(tmp_path, "0.4999", "0.5"))
    msg = " ".join(str(err.value).split())
    assert "material.region[1]" in msg and "nu=0.5" in msg and "different from [material]" in msg


def test_a_region_nu_above_one_half_is_out_of_range(tmp_path):
    with pytest.raises(ConfigError) as err:
        load_problem(_file(tmp_path, "0.5", "0.6"))
    assert "material.region[1].nu" in " ".join(str(err.value).split())
