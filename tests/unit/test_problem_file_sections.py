"""The problem-file loader builds one section at a time and reports the issues of every section together.

References: the issue order is the order of the sections in :mod:`alcontact.io._sections`
(mesh, material, supports, loads, loading, obstacle, solver, reference); the obstacle
parameters come from the registered factory's own signature (``inspect.signature``).

Reaches inside the package: ``alcontact._options.check_value`` (the one value check that every
section calls) is not public.
"""

from __future__ import annotations

import inspect

import pytest

from alcontact._options import check_value
from alcontact.contact import obstacles
from alcontact.errors import ConfigError, InputError, UnknownNameError
from alcontact.io.config import load_problem_text
from alcontact.io.schema import TYPES, Option

GOOD = """
[problem]
name = "tiny"

[mesh]
generator = "rectangle"
bounds = [0.0, 1.0, 0.0, 1.0]
cells = [2, 2]

[material]
E = 1000.0
nu = 0.3

[[support]]
boundary = "top"
components = [1]
value = -0.01

[[load]]
type = "traction"
boundary = "left"
vector = [0.0, 0.0]

[loading]
steps = 2

[obstacle]
type = "half-space"
point = [0.0, 0.0]
normal = [0.0, 1.0]

[contact]
boundary = "bottom"

[solver]
algorithm = "simo-laursen"

[reference]
kind = "hertz"
radius = 1.0
"""


def _bad(*pairs: tuple[str, str]) -> str:
    text = GOOD
    for old, new in pairs:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


def test_good_file_builds_every_section():
    setup = load_problem_text(GOOD)
    assert setup.times == (0.5, 1.0)
    assert [s.boundary for s in setup.problem.supports] == ["top"]
    assert [type(x).__name__ for x in setup.problem.loads] == ["Traction"]
    assert setup.reference is not None and setup.algorithm == "simo-laursen"


def test_issues_of_every_section_are_reported_together_in_section_order():
    text = _bad(('E = 1000.0\nnu = 0.3', 'E = 1000.0\nnu = 0.3\nplane = "strain"\n[[material.region]]\nname = "x"\n'
                 'E = 1.0\nnu = 0.3'),
                ('boundary = "top"', 'boundary = "topp"'),
                ('vector = [0.0, 0.0]', 'vector = [0.0, 0.0, 0.0]'),
                ('normal = [0.0, 1.0]', 'normal = [0.0, 1.0]\nradius = 2.0'),
                ('algorithm = "simo-laursen"', 'algorithm = "simo-laursen"\npenalty = "exp-met1"'),
                ('radius = 1.0', 'radius = 1.0\naxis = 2'))
    with pytest.raises(ConfigError) as err:
        load_problem_text(text)
    paths = [i.path for i in err.value.issues]
    assert paths == ["material.region[1].name", "support[1].boundary", "load[1].vector", "obstacle.radius",
                     "solver.penalty", "reference.axis"]
    assert "Did you mean 'top'?" in str(err.value)


def test_obstacle_signature_lists_what_make_accepts():
    """Reference: the list of accepted parameters in the error of ``obstacles.make`` (built from the factory)."""
    assert list(obstacles.signature("half-space").parameters) == ["point", "normal"]
    for name in obstacles.available():
        sig = obstacles.signature(name)
        assert isinstance(sig, inspect.Signature)
        with pytest.raises(InputError) as err:
            obstacles.make(name, no_such_parameter=1.0)
        assert str(err.value).endswith("accepted parameters: " + ", ".join(sig.parameters))
    with pytest.raises(UnknownNameError, match="half-space"):
        obstacles.signature("half-spac")


def test_obstacle_parameters_are_checked_against_the_signature():
    with pytest.raises(ConfigError) as err:
        load_problem_text(_bad(('normal = [0.0, 1.0]\n', '')))
    assert [i.path for i in err.value.issues] == ["obstacle.normal"]
    assert "missing: obstacle 'half-space' needs normal (parameters: normal, point)" in str(err.value)


GOOD_VALUES = {"float": 1.5, "int": 3, "str": "a", "bool": True, "floats": [1.0, 2.0], "ints": [1, 2],
               "number-or-floats": 2.0, "knots": [[0.0, 0.0], [1.0, 1.0]]}


@pytest.mark.parametrize("kind", TYPES)
def test_every_declared_type_has_a_check(kind):
    opt = Option("x", kind, None if kind != "str" else "a", "An option.")
    value, issues = check_value(opt, GOOD_VALUES[kind])
    assert issues == [] and value is not None
    _, issues = check_value(opt, object())
    assert issues and issues[0][1].startswith("= <object")
