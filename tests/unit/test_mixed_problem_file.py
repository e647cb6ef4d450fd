"""``[material] formulation`` in problem files: declared, checked, and ``mixed`` refused (not coupled to contact)."""

from __future__ import annotations

from pathlib import Path

import pytest

from alcontact.errors import ConfigError
from alcontact.io.config import load_problem_text
from alcontact.io.schema import render_markdown

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "finite_half_cylinder.toml"


def _with(line: str) -> str:
    text = EXAMPLE.read_text()
    return text.replace('model = "neo-hookean"\n', f'model = "neo-hookean"\n{line}\n', 1)


def test_displacement_formulation_loads():
    assert load_problem_text(_with('formulation = "displacement"'), base_dir=EXAMPLE.parent) is not None


def test_mixed_is_refused_with_the_key_and_the_way_out():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_with('formulation = "mixed"'), base_dir=EXAMPLE.parent)
    msg = str(info.value)
    assert "material.formulation" in msg and "'displacement'" in msg and "MixedHyperelastic" in msg


def test_unknown_formulation_names_the_choices():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_with('formulation = "mixd"'), base_dir=EXAMPLE.parent)
    msg = str(info.value)
    assert "formulation" in msg and "mixed" in msg


def test_documented():
    doc = render_markdown()
    assert "| `formulation`" in doc or "`formulation`" in doc
    assert (EXAMPLE.parents[1] / "docs" / "problem-file.md").read_text() == doc  # regenerated
