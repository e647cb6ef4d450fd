"""Declared options: one declaration per option (type, range, default, one line of doc), one checker.

An :class:`Option` declares a key of a problem file or a field of an options
dataclass. The same declaration is used by

* the problem-file loader (:mod:`alcontact.io.schema`, :mod:`alcontact.io.config`),
* the Python API: :class:`~alcontact.contact.ContactOptions` (the one options
  type of every contact solver) declares its fields with :func:`declared` and
  validates them with :func:`check_dataclass`,
* the generated ``docs/problem-file.md``.

:func:`check_value` is the one place where a value is compared with its
declaration; its messages name the value, what was expected (type and allowed
range) and the way out, and the caller prefixes the key path.

Examples
--------
>>> opt = Option("maxiter", "int", 100, "Outer iterations.", low=1, high=100_000)
>>> check_value(opt, 7)
(7, [])
>>> check_value(opt, "10")[1]
[('', "= '10': expected an integer in [1, 100000], got str. Write the number without quotes. Default: 100.")]
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass
from typing import Any, Callable

from .errors import InputError

__all__ = ["REQUIRED", "TYPES", "BAD", "MAX_STEPS", "VALUE_RANGE", "Option", "check_value", "declared",
           "declarations", "check_dataclass", "as_options", "is_real", "is_integer", "show", "LINEAR_MODEL",
           "ENERGY_MODEL", "OBSTACLE_PATH", "MAX_CUTBACKS",
           "LENGTH_UNITS", "STRESS_UNITS", "FORCE_UNITS", "UNITS_OPTIONS", "derived_force_unit", "units_issues",
           "check_args", "require", "is_path"]


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


class _Bad:
    def __repr__(self) -> str:
        return "BAD"


#: Default of an option that has to be given.
REQUIRED: Any = _Required()

#: Marker returned by :func:`check_value` for a value that failed its check.
BAD: Any = _Bad()

#: Types an option may have: ``float`` (an int is accepted), ``int``, ``str``, ``bool``,
#: ``floats`` (list of numbers), ``ints`` (list of ints), ``number-or-floats`` (a number or
#: a list of numbers), ``knots`` (list of ``[t, value]`` pairs with increasing ``t``).
TYPES = ("float", "int", "str", "bool", "floats", "ints", "number-or-floats", "knots")

_TYPE_TEXT = {
    "float": "a number",
    "int": "an integer",
    "str": "a string",
    "bool": "true or false",
    "floats": "a list of numbers",
    "ints": "a list of integers",
    "number-or-floats": "a number or a list of numbers",
    "knots": "a list of [t, factor] pairs",
}

#: Most load steps a problem or ``contact.solve(steps=...)`` may ask for (each step is a full solve).
MAX_STEPS = 100_000

#: Magnitudes of Young's modulus and of load values the solver's double precision carries (squares stay
#: finite): checked by :class:`~alcontact.fem.Material` and by ``alcontact check`` (:mod:`alcontact.io.preflight`).
VALUE_RANGE = (1e-100, 1e100)

#: Longest list an option accepts (vertices of a polygon, explicit step times, ramp knots).
MAX_LIST = 100_000


@dataclass(frozen=True)
class Option:
    """One option: a key of a problem file or a field of an options dataclass.

    Parameters
    ----------
    name : str
        Key inside its table (field name).
    type : str
        One of :data:`TYPES`.
    default : object
        Value when the key is absent; :data:`REQUIRED` when it must be given;
        ``None`` when absence means "automatic" (explained in ``doc``; in Python
        ``None`` may then be passed explicitly).
    doc : str
        One line.
    choices : tuple of str or callable, optional
        Allowed values of a ``str`` option, or a function returning them when
        the set can grow at run time (a registry's names).
    low, high : float, optional
        Range of a number (or of every list entry); ``low_open``/``high_open``
        make the bound strict.
    lengths : tuple of int, optional
        Allowed lengths of a list.
    only : str, optional
        ``"friction"``: a field of :class:`~alcontact.contact.ContactOptions` that only
        the frictional solvers read (``None``: every solver that has the notion reads it).
    """

    name: str
    type: str
    default: Any
    doc: str
    choices: tuple[str, ...] | Callable[[], tuple[str, ...]] | None = None
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    lengths: tuple[int, ...] | None = None
    only: str | None = None

    def __post_init__(self) -> None:
        if self.type not in TYPES:
            raise ValueError(f"option {self.name!r}: unknown type {self.type!r}")
        if "\n" in self.doc:
            raise ValueError(f"option {self.name!r}: the doc must be one line")

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def allowed(self) -> tuple[str, ...] | None:
        """The allowed values of a ``str`` option now (``choices``, called if it is a function)."""
        return tuple(self.choices()) if callable(self.choices) else self.choices

    def range_text(self) -> str:
        """``"> 0"``, ``"in [1, 2]"``, ``"one of a, b"`` or ``""``."""
        if self.allowed:
            return "one of " + ", ".join(f"`{c}`" for c in self.allowed)
        lo = None if self.low is None else f"{'(' if self.low_open else '['}{_num(self.low)}"
        hi = None if self.high is None else f"{_num(self.high)}{')' if self.high_open else ']'}"
        if lo and hi:
            return f"in {lo}, {hi}"
        if lo:
            return f"{'>' if self.low_open else '>='} {_num(self.low)}"
        if hi:
            return f"{'<' if self.high_open else '<='} {_num(self.high)}"
        return ""

    def expected(self) -> str:
        """What the option takes, e.g. ``"an integer in [1, 100000]"``."""
        rng = "" if self.allowed else self.range_text()
        return _TYPE_TEXT[self.type] + (f" {rng}" if rng else "")

    def default_hint(self, api: bool = False) -> str:
        """``" Default: 100.0."``, ``" Default: None (automatic)."`` (Python) or ``""``."""
        if self.required:
            return ""
        if self.default is None:
            return " Default: None (automatic)." if api else ""
        return f" Default: {self.default!r}."


def _num(x: float) -> str:
    """A bound as text: whole numbers without exponent (``100000``), others as ``%g``."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e16 else f"{x:g}"


def show(value: Any, limit: int = 60) -> str:
    """``repr(value)`` shortened to about ``limit`` characters (huge numbers, deep lists)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**40:
        digits = int(abs(value).bit_length() * 0.30102999566398120) + 1  # str() may refuse > 4300 digits
        return f"{'-' if value < 0 else ''}<integer of about {digits} digits>"
    try:
        text = repr(value)
    except (RecursionError, ValueError):
        text = f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[: limit - 3] + "..."


def is_real(v: Any) -> bool:
    """A real number that is not a bool (Python or NumPy)."""
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and type(v).__name__ != "bool_"


def is_integer(v: Any) -> bool:
    """An integer that is not a bool (Python or NumPy)."""
    return isinstance(v, numbers.Integral) and not isinstance(v, bool) and type(v).__name__ != "bool_"


def _finite_real(x: Any) -> bool:
    """A finite real number (a huge integer that no float holds is not)."""
    try:
        return math.isfinite(x)
    except OverflowError:
        return False


def _in_range(opt: Option, x: float) -> bool:
    if opt.low is not None and (x < opt.low or (opt.low_open and x == opt.low)):
        return False
    if opt.high is not None and (x > opt.high or (opt.high_open and x == opt.high)):
        return False
    return True


def check_value(opt: Option, value: Any, *, api: bool = False) -> tuple[Any, list[tuple[str, str]]]:
    """Check ``value`` against its declaration.

    Parameters
    ----------
    opt : Option
    value : object
        A parsed TOML value, or a value passed from Python.
    api : bool
        Word the fixes for Python callers (``maxiter=100``) instead of problem files.

    Returns
    -------
    value, issues
        The value converted to its Python type (``float``, ``int``, lists, tuples of
        knots) and ``[]``; or :data:`BAD` and a list of ``(suffix, message)`` pairs:
        ``suffix`` is appended to the key path (``""`` or ``"[2]"`` for a list
        entry), ``message`` starts with ``"= value: "`` and says what to do.
    """
    if value is None and opt.default is None:
        return None, []
    check = _Check(opt, value, api)
    return _CHECKS[opt.type](check), check.issues


class _Check:
    """One run of :func:`check_value`: the declaration, the value and the issues found so far.

    The methods ``bad_type`` and ``number`` record an issue and return :data:`BAD`, or
    return the converted value; the per-type checks in ``_CHECKS`` use them.
    """

    def __init__(self, opt: Option, value: Any, api: bool) -> None:
        self.opt, self.value, self.api = opt, value, api
        self.issues: list[tuple[str, str]] = []
        self.want = opt.expected()
        self.fix = opt.default_hint(api)

    def _type_hint(self, x: Any) -> str:
        opt, api = self.opt, self.api
        scalar = opt.type in ("float", "int", "floats", "ints", "number-or-floats")
        if scalar and isinstance(x, str):
            return " Pass a number, not a string." if api else " Write the number without quotes."
        if opt.type == "bool" and isinstance(x, str):
            return " Pass True or False." if api else " Write true or false without quotes."
        if opt.type in ("int", "ints") and is_real(x) and _finite_real(x):
            return f" Use a whole number, e.g. {max(int(round(x)), 1)}."
        if opt.type in ("int", "ints") and isinstance(x, bool):
            return " Booleans are not integers here; pass a whole number."
        return ""

    def bad_type(self, x: Any = None, where: str = "", *, whole: bool = True) -> Any:
        """Record "expected <type>, got <type>" for the value (``whole``) or the list entry ``x``."""
        if whole:
            x = self.value
        what = self.want if x is self.value else _TYPE_TEXT["float" if self.opt.type != "ints" else "int"]
        self.issues.append((where, f"= {show(x)}: expected {what}, got {type(x).__name__}.{self._type_hint(x)}"
                                   f"{self.fix}"))
        return BAD

    def _out_of_range(self, x: Any, where: str) -> Any:
        self.issues.append((where, f"= {show(x)}: out of range, must be {self.opt.range_text()}.{self.fix}"))
        return BAD

    def number(self, x: Any, where: str = "") -> Any:
        """``x`` as ``int`` or a finite ``float`` in the declared range, or :data:`BAD`."""
        opt = self.opt
        if opt.type in ("int", "ints"):
            if not is_integer(x):
                return self.bad_type(x, where, whole=False)
            return int(x) if _in_range(opt, x) else self._out_of_range(x, where)
        if not is_real(x):
            return self.bad_type(x, where, whole=False)
        try:
            xf = float(x)
        except (OverflowError, ValueError, TypeError):
            self.issues.append((where, f"= {show(x)}: too large (the largest number is about 1.8e308); must be "
                                       f"{opt.range_text() or 'a finite number'}.{self.fix}"))
            return BAD
        if not math.isfinite(xf):
            rng = opt.range_text()
            self.issues.append((where, f"= {show(x)}: must be a finite number{' ' + rng if rng else ''}.{self.fix}"))
            return BAD
        return xf if _in_range(opt, x) else self._out_of_range(x, where)

    def too_long(self, v: Any) -> bool:
        if len(v) > MAX_LIST:
            self.issues.append(("", f"= [...] ({len(v)} entries): too long, at most {MAX_LIST} entries."))
            return True
        return False

    def numbers(self, v: Any) -> Any:
        """Every entry of the list ``v`` checked by :meth:`number` (``[i]`` in the key path)."""
        out = [self.number(x, f"[{i}]") for i, x in enumerate(v)]
        return BAD if any(x is BAD for x in out) else out


def _seq(v: Any) -> bool:
    return isinstance(v, (list, tuple))


def _check_number(c: _Check) -> Any:
    return c.number(c.value)


def _check_bool(c: _Check) -> Any:
    v = c.value
    if isinstance(v, bool) or type(v).__name__ == "bool_":
        return bool(v)
    return c.bad_type()


def _check_str(c: _Check) -> Any:
    value = c.value
    if not isinstance(value, str):
        return c.bad_type()
    choices = c.opt.allowed
    if choices is not None and value not in choices:
        import difflib

        close = difflib.get_close_matches(value, [x for x in choices if x], n=1, cutoff=0.6)
        mean = f" Did you mean {close[0]!r}?" if close else ""
        allowed = ", ".join(repr(x) for x in choices if x)
        c.issues.append(("", f"= {show(value)}: not allowed.{mean} Allowed: {allowed}.{c.fix}"))
        return BAD
    return value


def _check_number_or_floats(c: _Check) -> Any:
    value = c.value
    if is_real(value):
        return c.number(value)
    if not _seq(value) or not value:
        return c.bad_type()
    return BAD if c.too_long(value) else c.numbers(value)


def _check_list(c: _Check) -> Any:
    value, opt = c.value, c.opt
    if not _seq(value):
        return c.bad_type()
    if opt.lengths is not None and len(value) not in opt.lengths:
        c.issues.append(("", f"= {show(value)}: needs {' or '.join(map(str, opt.lengths))} entries, "
                             f"got {len(value)}."))
        return BAD
    return BAD if c.too_long(value) else c.numbers(value)


def _finite(x: Any) -> bool:
    try:
        return is_real(x) and math.isfinite(float(x))
    except OverflowError:
        return False


def _check_knots(c: _Check) -> Any:
    value = c.value
    ok = _seq(value) and value and len(value) <= MAX_LIST and all(
        _seq(k) and len(k) == 2 and all(_finite(x) for x in k) for k in value)
    if not ok:
        c.issues.append(("", f"= {show(value)}: expected {c.want} of finite numbers (at most {MAX_LIST}), "
                             "e.g. [[0.0, 0.0], [1.0, 1.0]]."))
        return BAD
    ts = [float(k[0]) for k in value]
    if any(b <= a for a, b in zip(ts, ts[1:])):
        c.issues.append(("", f"= {show(value)}: the times (first entries) must increase strictly."))
        return BAD
    return [(float(k[0]), float(k[1])) for k in value]


#: The check of each declared type (:data:`TYPES`).
_CHECKS: dict[str, Callable[[_Check], Any]] = {
    "float": _check_number, "int": _check_number, "bool": _check_bool, "str": _check_str,
    "number-or-floats": _check_number_or_floats, "floats": _check_list, "ints": _check_list,
    "knots": _check_knots,
}


# --------------------------------------------------------------------------- options dataclasses
_KEY = "alcontact.option"


def declared(type: str, default: Any, doc: str, **limits: Any) -> Any:
    """A dataclass field declared as an :class:`Option` (the field name is the option name).

    ``limits`` are the keyword arguments of :class:`Option` (``low``, ``high``,
    ``low_open``, ``high_open``, ``choices``, ``lengths``, ``only``).

    Examples
    --------
    >>> @dataclasses.dataclass(frozen=True)
    ... class Opts:
    ...     maxiter: int = declared("int", 100, "Outer iterations.", low=1)
    ...     def __post_init__(self):
    ...         check_dataclass(self, "example")
    >>> declarations(Opts)[0].range_text()
    '>= 1'
    >>> Opts(maxiter=0)
    Traceback (most recent call last):
    ...
    alcontact.errors.InputError: example option maxiter = 0: out of range, must be >= 1. Default: 100.
    """
    meta = {_KEY: dict(type=type, doc=doc, **limits)}
    return dataclasses.field(default=default, metadata=meta)


_CACHE: dict[type, tuple[Option, ...]] = {}


def declarations(cls: type) -> tuple[Option, ...]:
    """The :class:`Option` of every field of an options dataclass, in field order."""
    if cls not in _CACHE:
        out = []
        for f in dataclasses.fields(cls):
            meta = f.metadata.get(_KEY)
            if meta is None:
                raise TypeError(f"{cls.__name__}.{f.name} is not declared with alcontact._options.declared")
            out.append(Option(f.name, default=f.default, **meta))
        _CACHE[cls] = tuple(out)
    return _CACHE[cls]


def check_dataclass(obj: Any, kind: str) -> Any:
    """Validate every field of an options dataclass against its declaration.

    Meant for ``__post_init__``: the options object is checked when it is made.

    Returns
    -------
    object
        ``obj``, every value converted to its declared type in place (``numpy``
        scalars become ``float``/``int``).

    Raises
    ------
    InputError
        Naming every bad field (``"contact option maxiter = '10': expected ..."``),
        the allowed range and the fix.
    """
    issues: list[str] = []
    changes: dict[str, Any] = {}
    for opt in declarations(type(obj)):
        value = getattr(obj, opt.name)
        new, found = check_value(opt, value, api=True)
        for suffix, msg in found:
            issues.append(f"{kind} option {opt.name}{suffix} {msg}")
        if not found and (type(new) is not type(value) or new != value):
            changes[opt.name] = new
    if issues:
        raise InputError("\n".join(issues) if len(issues) > 1 else issues[0])
    for name, value in changes.items():  # frozen dataclass: convert in place (called from __post_init__)
        object.__setattr__(obj, name, value)
    return obj


def check_args(where: str, checks: list[tuple[Option, Any]]) -> list[Any]:
    """Check the arguments of a public function against declarations made on the spot.

    For functions whose parameters are not an options dataclass (``hertz_2d(level=...)``):
    a wrong type or a value out of range raises here, naming the function, the
    parameter, the value and the fix, instead of a ``TypeError`` from deep inside.

    Parameters
    ----------
    where : str
        The function, e.g. ``"hertz_2d"``.
    checks : list of (Option, value)

    Returns
    -------
    list
        The values converted to their declared types (``None`` kept where the
        declaration's default is ``None``).

    Raises
    ------
    InputError
        ``"hertz_2d: level = 1.5: expected an integer, got float. Use a whole number, e.g. 2."``
    """
    from .errors import InputError

    issues, out = [], []
    for opt, value in checks:
        if value is None and opt.default is None:
            out.append(None)
            continue
        new, found = check_value(opt, value, api=True)
        issues += [f"{where}: {opt.name}{suffix} {msg}" for suffix, msg in found]
        out.append(new)
    if issues:
        raise InputError("\n".join(issues))
    return out


def require(where: str, name: str, value: Any, ok: bool, want: str, error: type | None = None) -> None:
    """Raise ``error`` (default :class:`~alcontact.errors.InputError`) unless ``ok``: the message names the
    function, the argument, its value and type, and what to pass instead."""
    if ok:
        return
    from .errors import InputError

    raise (error or InputError)(f"{where}: {name} = {show(value)}: expected {want}, got {type(value).__name__}.")


def is_path(value: Any) -> bool:
    """A file-system path argument: ``str`` or ``os.PathLike`` (not bytes, not a number)."""
    import os

    if not isinstance(value, (str, os.PathLike)):
        return False
    text = os.fspath(value)
    return isinstance(text, str) and "\0" not in text


def _names(cls_or_obj: Any) -> list[str]:
    return [f.name for f in dataclasses.fields(cls_or_obj)]


def as_options(cls: type, options: Any, overrides: dict, kind: str) -> Any:
    """An options dataclass from ``None``, an instance of ``cls`` or a dict, plus ``overrides``, validated.

    An instance of a dataclass that ``cls`` derives from without new fields (``ContactOptions``
    where its alias ``FrictionOptions`` is asked for) is accepted as it is.

    Raises
    ------
    InputError
        ``options`` of another type, unknown keys (with "did you mean"), or bad values.
    """
    from .errors import UnknownNameError

    if options is None:
        base: dict[str, Any] = {}
        opts = cls()
    elif isinstance(options, cls) or (dataclasses.is_dataclass(options) and issubclass(cls, type(options))
                                      and _names(options) == _names(cls)):
        base, opts = {}, options
    elif isinstance(options, dict):
        base, opts = dict(options), cls()
    else:
        raise InputError(f"options = {show(options)}: expected a {cls.__name__} or a dict of its fields, got "
                         f"{type(options).__name__}; e.g. options={{'maxiter': 50}}.")
    known = _names(cls)
    changes = {**base, **(overrides or {})}
    for key in changes:
        if not isinstance(key, str) or key not in known:
            raise UnknownNameError(f"{kind} option", str(key), known)
    if changes:
        opts = dataclasses.replace(opts, **changes)  # __post_init__ validates
    return opts



# --------------------------------------------------------------------------- finite deformation
#: ``material.model`` of a linear elastic body (small strains); every other value is a hyperelastic law.
LINEAR_MODEL = "linear"

#: Law name of a user strain energy given as ``[material] energy`` (not a ``model`` choice).
ENERGY_MODEL = "energy-expression"


#: ``[obstacle] path``: rigid translation of the obstacle per unit pseudo-time (finite kinematics).
OBSTACLE_PATH = Option("path", "floats", None, "Finite kinematics: translation of the obstacle per unit "
                       "pseudo-time, `[dx, dy]` / `[dx, dy, dz]` (the obstacle is at `t * path` at step time "
                       "t; default: it does not move).", lengths=(2, 3))

#: ``[loading] max_cutbacks``: halvings of a failed finite-deformation step.
MAX_CUTBACKS = Option("max_cutbacks", "int", 6, "Finite kinematics: halvings of a load step's increment allowed "
                      "when its Newton solve fails or an element inverts (at most 2^n sub-steps per step).",
                      low=0, high=20)


# --------------------------------------------------------------------------- units
#: Length units a problem file may declare (``[units] length``), in metres.
LENGTH_UNITS: dict[str, float] = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 0.0254, "ft": 0.3048}

#: Stress units (``[units] stress``, the unit of Young's modulus and of the pressure), in pascals.
STRESS_UNITS: dict[str, float] = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "psi": 6894.757293168361,
                                  "ksi": 6894757.293168361}

#: Force units (``[units] force``), in newtons.
FORCE_UNITS: dict[str, float] = {"uN": 1e-6, "mN": 1e-3, "N": 1.0, "kN": 1e3, "MN": 1e6, "GN": 1e9,
                                 "lbf": 4.4482216152605, "kip": 4448.2216152605}

#: ``[units]``: the units of the numbers of a problem file (labels only: nothing is converted).
UNITS_OPTIONS: tuple[Option, ...] = (
    Option("length", "str", None, "Unit of the mesh coordinates and every length (e.g. `mm`); default: unnamed "
           "(labels say `L`).", choices=tuple(LENGTH_UNITS)),
    Option("stress", "str", None, "Unit of Young's modulus, pressures and tractions (e.g. `MPa`); default: "
           "unnamed (labels say `[E]`).", choices=tuple(STRESS_UNITS)),
    Option("force", "str", None, "Optional check of the force unit: must be stress x length^2 (`N` for `MPa` "
           "and `mm`, `kN` for `GPa` and `mm`); default: derived.", choices=tuple(FORCE_UNITS)),
)


def derived_force_unit(length: str | None, stress: str | None) -> str | None:
    """The named force unit equal to ``stress x length^2`` (``"N"`` for MPa and mm), or ``None``.

    Examples
    --------
    >>> derived_force_unit("mm", "MPa"), derived_force_unit("m", "GPa"), derived_force_unit("cm", "MPa")
    ('N', 'GN', None)
    """
    if length not in LENGTH_UNITS or stress not in STRESS_UNITS:
        return None
    value = STRESS_UNITS[stress] * LENGTH_UNITS[length] ** 2
    return next((name for name, f in FORCE_UNITS.items() if math.isclose(f, value, rel_tol=1e-9)), None)


def units_issues(length: str | None, stress: str | None, force: str | None) -> list[tuple[str, str]]:
    """Inconsistencies of a ``[units]`` table: ``[(key, message)]`` (empty when consistent).

    The numbers of a problem file are used as they are (no conversion), so the units
    must form a consistent set: force = stress x length^2.

    Examples
    --------
    >>> units_issues("mm", "MPa", "N")
    []
    >>> units_issues("mm", "GPa", "N")[0][1][:58]
    "= 'N': inconsistent with stress = 'GPa' and length = 'mm' "
    """
    if force is None:
        return []
    if length is None or stress is None:
        return [("force", f"= {force!r}: a force unit is checked against stress x length^2; give [units] length "
                          "and stress too, or remove force.")]
    derived = derived_force_unit(length, stress)
    if derived == force:
        return []
    if derived is None:
        value = STRESS_UNITS[stress] * LENGTH_UNITS[length] ** 2
        return [("force", f"= {force!r}: inconsistent with stress = {stress!r} and length = {length!r} "
                          f"({stress} x {length}^2 = {value:g} N, no named unit); remove force (labels then say "
                          f"{stress}·{length}²) or change length/stress.")]
    return [("force", f"= {force!r}: inconsistent with stress = {stress!r} and length = {length!r} "
                      f"({stress} x {length}^2 = {derived}); set force = {derived!r}, remove force, or change "
                      "length/stress (the numbers of the file are not converted).")]
