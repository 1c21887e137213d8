"""A published law in an angle, as printed (``D/q = 12.5 + 30.2 sin²α``): an arithmetic
expression of the angle read safely (no names but the angle, ``pi`` and a few functions), valued
with numpy at the table's breakpoints.

Accepted: numbers, ``+ - * / **`` (or ``^``), parentheses, the angle (``alpha`` or ``α`` of a table
in alpha, ``beta`` or ``β`` in beta; in rad), ``pi``, and ``sin cos tan exp sqrt abs``.
"""
from __future__ import annotations

import ast

import numpy as np

FUNCTIONS = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "sqrt": np.sqrt, "abs": np.abs}
OPERATORS = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide, ast.Pow: np.power}
GREEK = {"α": "alpha", "β": "beta"}


def parse(text: str, angle: str) -> ast.Expression:
    """The checked syntax tree of ``text``, a law in ``angle`` ("alpha" or "beta"); ValueError
    naming what is not accepted."""
    if not isinstance(text, str) or not text.strip():
        raise ValueError("law = \"expression\": value must be the law as a text, e.g. \"12.5 + 30.2*sin(alpha)^2\"")
    source = text.replace("^", "**").replace("²", "**2").replace("·", "*").replace("−", "-")
    for letter, name in GREEK.items():
        source = source.replace(letter, name)
    try:
        tree = ast.parse(source.strip(), mode="eval")
    except SyntaxError:
        raise ValueError(f"law {text!r} is not an arithmetic expression") from None
    for node in ast.walk(tree):
        _check(node, angle, text)
    return tree


def _check(node, angle: str, text: str) -> None:
    if isinstance(node, ast.Name) and node.id not in (angle, "pi", *FUNCTIONS):
        raise ValueError(f"law {text!r}: {node.id!r} is not known; the law may use {angle} (rad), pi and "
                         f"{', '.join(FUNCTIONS)}")
    if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS
                                           and len(node.args) == 1 and not node.keywords):
        raise ValueError(f"law {text!r}: a call of one argument to {', '.join(FUNCTIONS)} only")
    allowed = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Call, ast.Load, ast.USub, ast.UAdd,
               *OPERATORS)
    if not isinstance(node, allowed) or (isinstance(node, ast.Constant) and not isinstance(node.value, (int, float))):
        raise ValueError(f"law {text!r}: {type(node).__name__} is not accepted (numbers, + - * / ^, parentheses, "
                         f"{angle}, pi, {', '.join(FUNCTIONS)})")


def value(tree: ast.Expression, angle: str, x) -> np.ndarray:
    """The law ``tree`` (of :func:`parse`) at the angles ``x`` (rad)."""
    return np.asarray(_eval(tree.body, {angle: np.asarray(x, dtype=float), "pi": np.pi}), dtype=float) \
        * np.ones_like(np.asarray(x, dtype=float))


def _eval(node, names: dict):
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.Name):
        return names[node.id]
    if isinstance(node, ast.UnaryOp):
        operand = _eval(node.operand, names)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.BinOp):
        return OPERATORS[type(node.op)](_eval(node.left, names), _eval(node.right, names))
    return FUNCTIONS[node.func.id](_eval(node.args[0], names))
