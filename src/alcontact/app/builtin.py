"""Built-in problems the command line runs by name (``alcontact run --problem NAME``)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..errors import InputError, UnknownNameError

__all__ = ["BuiltinProblem", "BUILTIN_PROBLEMS", "DEFAULT_PROBLEM", "build_problem"]


@dataclass(frozen=True)
class BuiltinProblem:
    """A benchmark problem the CLI can run by name."""

    name: str
    doc: str
    factory: Callable[..., Any]  # factory(level=..., order=...) -> ContactProblem
    default_level: int
    levels: int  # number of refinement levels (0 .. levels-1)
    units: tuple[str, str] | None = None  # (length, stress) units of the plots and the report


def _hertz(kind: str):
    def factory(level: int, order: int):
        from ..problems import hertz

        return (hertz.hertz_2d if kind == "2d" else hertz.hertz_3d)(level=level, order=order)

    return factory


def _two_cylinders(level: int, order: int):
    from ..problems import two_body

    return two_body.hertz_cylinders(level=level, order=order)


#: Built-in problems by name. Default levels: about 10k DOFs, a few seconds.
BUILTIN_PROBLEMS: dict[str, BuiltinProblem] = {
    "hertz-2d": BuiltinProblem(
        "hertz-2d", "rigid cylinder on an elastic block, plane strain, half model (Hertz line contact)",
        _hertz("2d"), default_level=2, levels=6, units=("mm", "MPa"),
    ),
    "hertz-3d": BuiltinProblem(
        "hertz-3d", "rigid sphere on an elastic block, quarter model (Hertz point contact)",
        _hertz("3d"), default_level=0, levels=6, units=("mm", "MPa"),
    ),
    "hertz-2body": BuiltinProblem(
        "hertz-2body", "two elastic cylinders of different E and nu pressed together, plane strain, half model "
        "(mortar contact between two bodies; Hertz with the effective modulus and radius)",
        _two_cylinders, default_level=2, levels=6, units=("mm", "MPa"),
    ),
}


DEFAULT_PROBLEM = "hertz-2d"


def build_problem(name: str = DEFAULT_PROBLEM, level: int | None = None, order: int = 1):
    """Build the built-in problem ``name`` at refinement ``level`` (default: its default level).

    Raises
    ------
    UnknownNameError
        ``name`` is not a built-in problem.
    InputError
        ``level`` is out of range.
    """
    if name not in BUILTIN_PROBLEMS:
        raise UnknownNameError("problem", name, list(BUILTIN_PROBLEMS))
    spec = BUILTIN_PROBLEMS[name]
    lvl = spec.default_level if level is None else int(level)
    if not 0 <= lvl < spec.levels:
        raise InputError(f"level={level!r} is out of range for {name!r}; use 0 .. {spec.levels - 1}.")
    return spec.factory(level=lvl, order=order)
