r"""Safe parsing of a strain-energy expression written in a problem file.

The text is parsed by :func:`ast.parse` (``mode="eval"``) and the SymPy
expression is built node by node from a whitelist; nothing is evaluated as
Python and :func:`sympy.sympify` never sees the text. Accepted:

* numbers (integers and decimals, no complex numbers, no booleans),
* the parameter names given in ``material.parameters``,
* the invariants ``I1`` (:math:`\operatorname{tr}C`), ``I2``
  (:math:`\tfrac12(I_1^2 - \operatorname{tr}C^2)`), ``I3`` (:math:`\det C = J^2`),
  ``J`` (:math:`\det F`), ``I1b`` (:math:`J^{-2/3}I_1`) and ``I2b`` (:math:`J^{-4/3}I_2`),
* the operators ``+ - * / **`` and unary ``-``/``+``, parentheses,
* the functions ``log`` (natural), ``exp`` and ``sqrt`` of one argument.

The expression is returned in the three symbols ``I1, I2, J`` (positive).

Examples
--------
>>> expr = parse_energy("c10*(I1b-3) + K/2*(J-1)**2", {"c10": 0.5, "K": 10.0})
>>> sorted(str(s) for s in expr.free_symbols)
['I1', 'J', 'p_K', 'p_c10']
>>> parse_energy("__import__('os')", {})
Traceback (most recent call last):
...
alcontact.errors.InputError: energy = "__import__('os')": a call of '__import__' is not allowed; functions: log, exp, sqrt. Allowed names: I1, I1b, I2, I2b, I3, J (invariants), no parameters.
"""

from __future__ import annotations

import ast
import difflib
import math
from typing import Any

from alcontact.errors import InputError

__all__ = ["INVARIANTS", "FUNCTIONS", "SYMBOLS", "parse_energy"]

#: Invariant names an energy expression may use (meaning in the module doc).
INVARIANTS = ("I1", "I2", "I3", "J", "I1b", "I2b")
#: Functions an energy expression may call.
FUNCTIONS = ("log", "exp", "sqrt")
#: Longest expression text accepted, and most syntax-tree nodes.
MAX_CHARS, MAX_NODES = 4000, 2000


def SYMBOLS(parameters=()) -> dict[str, Any]:
    """The SymPy symbols ``I1, I2, J`` of the parsed expressions, and one per parameter name."""
    import sympy

    I1, I2, J = sympy.symbols("I1 I2 J", positive=True)
    return {"I1": I1, "I2": I2, "J": J, **{n: sympy.Symbol(f"p_{n}", real=True) for n in parameters}}


def _invariant_values() -> dict[str, Any]:
    import sympy

    s = SYMBOLS()
    I1, I2, J = s["I1"], s["I2"], s["J"]
    return {"I1": I1, "I2": I2, "I3": J**2, "J": J,
            "I1b": I1 * J ** sympy.Rational(-2, 3), "I2b": I2 * J ** sympy.Rational(-4, 3)}


_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}


def parse_energy(text: Any, parameters: dict[str, Any], *, key: str = "energy", params_key: str = "parameters"):
    """The SymPy expression of ``text`` (see module doc) in ``I1, I2, J`` and the parameter symbols.

    The parameters stay symbols (:func:`SYMBOLS`; their values are checked here and
    substituted by the caller at evaluation), so that SymPy keeps ``c10*(I1b-3)`` as
    written instead of distributing a rounded coefficient.

    Parameters
    ----------
    text : str
    parameters : dict of str to float
        Every name must be an identifier, not an invariant or function name, with a
        finite real value, and used by ``text``.
    key, params_key : str
        Key paths for messages (``material.energy``, ``material.parameters``).

    Raises
    ------
    alcontact.errors.InputError
        Naming the key, the offending token or value and the allowed names.
    """
    import sympy

    from alcontact._options import is_real, show

    params = dict(parameters or {})

    def allowed() -> str:
        p = ", ".join(sorted(params)) if params else "no parameters"
        return f"Allowed names: {', '.join(sorted(INVARIANTS))} (invariants), {p}."

    def fail(msg: str) -> InputError:
        return InputError(f"{key} = {show(text, 120)}: {msg}")

    if not isinstance(text, str):
        raise InputError(f"{key} = {show(text)}: expected a string with the strain energy, e.g. "
                         "\"c10*(I1b-3) + K/2*(J-1)**2\"; got {type(text).__name__}.")
    for name, value in params.items():
        where = f"{params_key}.{name}"
        if not isinstance(name, str) or not name.isidentifier():
            raise InputError(f"{where}: a parameter name must be an identifier (letters, digits, _).")
        if name in INVARIANTS or name in FUNCTIONS:
            raise InputError(f"{where}: {name!r} is an invariant or function name; choose another parameter name.")
        if not is_real(value) or not math.isfinite(float(value)):
            raise InputError(f"{where} = {show(value)}: expected a finite number.")
    if not text.strip():
        raise InputError(f"{key} = \"\": empty; write the strain energy, e.g. \"c10*(I1b-3) + K/2*(J-1)**2\".")
    if len(text) > MAX_CHARS:
        raise InputError(f"{key}: {len(text)} characters, at most {MAX_CHARS}.")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise fail(f"not a valid expression ({exc.msg} at column {exc.offset}). {allowed()}") from None
    except (RecursionError, MemoryError, ValueError):
        raise fail("too deeply nested to parse.") from None
    if sum(1 for _ in ast.walk(tree)) > MAX_NODES:
        raise fail(f"more than {MAX_NODES} terms; simplify it.")

    inv = _invariant_values()
    psym = SYMBOLS(params)
    used: set[str] = set()

    def number(x: float, node) -> Any:
        if not math.isfinite(x):
            raise fail(f"the constant part {ast.unparse(node)!r} is not a finite number.")
        return x

    def build(node) -> Any:  # noqa: C901 - one branch per accepted node type
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise fail(f"the constant {v!r} is not allowed (only real numbers). {allowed()}")
            return number(float(v), node)
        if isinstance(node, ast.Name):
            if node.id in inv:
                return inv[node.id]
            if node.id in params:
                used.add(node.id)
                return psym[node.id]
            known = list(INVARIANTS) + list(params)
            close = [k for k in known if k.lower() == node.id.lower()]  # names are case sensitive: K is not k
            close = close or difflib.get_close_matches(node.id, known, n=1, cutoff=0.6)
            mean = f" Did you mean {close[0]!r}?" if close else ""
            hint = "" if node.id in FUNCTIONS else f" (declare it in {params_key} if it is a parameter)"
            raise fail(f"unknown name {node.id!r}{hint}.{mean} {allowed()}")
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            v = build(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            a, b = build(node.left), build(node.right)
            op = _OPS[type(node.op)]
            if isinstance(a, float) and isinstance(b, float):  # fold constants in floats: no huge integers
                try:
                    v = {"+": a + b, "-": a - b, "*": a * b}.get(op)
                    if v is None:
                        v = a / b if op == "/" else math.pow(a, b)
                except ZeroDivisionError:
                    raise fail(f"division by zero in {ast.unparse(node)!r}.") from None
                except (OverflowError, ValueError):
                    raise fail(f"the constant part {ast.unparse(node)!r} is not a finite real number.") from None
                return number(v, node)
            if op == "+":
                return a + b
            if op == "-":
                return a - b
            if op == "*":
                return a * b
            if op == "/":
                if b == 0:
                    raise fail(f"division by zero in {ast.unparse(node)!r}.")
                return a / b
            return a**b
        if isinstance(node, ast.Call):
            fname = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
            if fname not in FUNCTIONS:
                raise fail(f"a call of {fname!r} is not allowed; functions: {', '.join(FUNCTIONS)}. {allowed()}")
            if node.keywords or len(node.args) != 1 or isinstance(node.args[0], ast.Starred):
                raise fail(f"{fname}(...) takes exactly one argument.")
            arg = build(node.args[0])
            if isinstance(arg, float):
                try:
                    v = {"log": math.log, "exp": math.exp, "sqrt": math.sqrt}[fname](arg)
                except (ValueError, OverflowError):
                    raise fail(f"{fname}({arg:g}) is not a finite real number.") from None
                return number(v, node)
            return {"log": sympy.log, "exp": sympy.exp, "sqrt": sympy.sqrt}[fname](arg)
        token = {ast.Attribute: "attribute access", ast.Subscript: "indexing", ast.Compare: "comparison",
                 ast.BoolOp: "and/or", ast.Lambda: "lambda", ast.IfExp: "if/else"}.get(type(node))
        what = token or type(node).__name__
        op = getattr(node, "op", None)
        if op is not None and not token:
            what = f"the operator {type(op).__name__}"
        raise fail(f"{what} ({ast.unparse(node)!r}) is not allowed; use numbers, + - * / **, unary -, "
                   f"{', '.join(FUNCTIONS)}. {allowed()}")

    try:
        expr = build(tree.body)
    except RecursionError:
        raise fail("too deeply nested.") from None
    expr = sympy.sympify(expr) if isinstance(expr, float) else expr  # a float, not text: nothing is parsed
    if expr.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo, sympy.I):
        raise fail("the expression is infinite, undefined or complex.")
    unused = sorted(set(params) - used)
    if unused:
        raise InputError(f"{params_key}.{unused[0]}: not used by {key}; remove it or use it in the expression "
                         f"(a typo?). Names in the expression: {', '.join(sorted(used)) or 'none'}.")
    if not expr.free_symbols & {psym["I1"], psym["I2"], psym["J"]}:
        raise fail("the energy does not depend on the deformation (no invariant in it).")
    return expr
