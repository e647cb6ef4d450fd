"""Problem-file schema: one declaration per option, generated documentation up to date, defaults in sync."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from alcontact.contact import ContactOptions
from alcontact.contact.algorithms import FrictionOptions
from alcontact.io import schema
from alcontact.io.config import load_problem_text

ROOT = Path(__file__).resolve().parents[2]


def test_generated_docs_are_up_to_date():
    committed = (ROOT / "docs" / "problem-file.md").read_text(encoding="utf-8")
    assert committed == schema.render_markdown(), "run `alcontact docs` (or python -m alcontact.io.schema)"


def test_every_option_has_type_default_and_one_line_doc():
    for tab in schema.schema():
        assert tab.doc and "\n" not in tab.doc
        for opt in tab.options:
            assert opt.doc and "\n" not in opt.doc, opt.name
            assert opt.type in schema.TYPES


def test_solver_options_cover_the_solver_dataclasses():
    solver = {o.name: o for o in schema.table("solver").options}
    for f in dataclasses.fields(ContactOptions):
        assert f.name in solver and solver[f.name].default == f.default, f.name
    fric = {o.name: o for o in schema.table("solver.friction").options}
    for f in dataclasses.fields(FrictionOptions):
        assert f.name in fric or f.name in solver, f.name
        if f.name in fric:
            assert fric[f.name].default == f.default, f.name


def test_docs_example_is_a_valid_problem_file():
    setup = load_problem_text(schema._EXAMPLE)
    assert setup.problem.model.dim == 2 and setup.reference is not None


def test_write_markdown(tmp_path):
    out = schema.write_markdown(tmp_path / "p.md")
    assert out.read_text().startswith("# Problem files")


def test_defaults_are_filled_in():
    setup = load_problem_text(schema._EXAMPLE)
    assert setup.data["solver"]["penalty_scale"] == ContactOptions().penalty_scale
    assert setup.data["output"]["vtu"] is True and setup.data["loading"]["steps"] == 1
    assert setup.data["solver"]["friction"]["radius"] == FrictionOptions().radius
