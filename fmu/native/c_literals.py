"""C literals of the generated sources: exact doubles (``%.17g``), escaped strings and static tables
(of the native FMU's ``heli_data.c`` and the controller FMU's data header)."""
from __future__ import annotations

import math
import re


def c_real(x: float | None) -> str:
    """A C double literal that reads back exactly (``%.17g``); None is NAN."""
    if x is None or math.isnan(x):
        return "NAN"
    if math.isinf(x):
        return "INFINITY" if x > 0 else "-INFINITY"
    text = "%.17g" % x
    return text if re.search(r"[.eE]", text) else text + ".0"


def c_string(s: str | None) -> str:
    """A C string literal (octal escapes for anything but printable ASCII); None is NULL."""
    if s is None:
        return "NULL"
    out = []
    for b in s.encode():
        ch = chr(b)
        out.append(ch if 32 <= b < 127 and ch not in '"\\?' else "\\%03o" % b)
    return '"' + "".join(out) + '"'


def c_reals(values) -> str:
    """A C initializer ``{a, b, c}`` of exact doubles (:func:`c_real`)."""
    return "{" + ", ".join(map(c_real, values)) + "}"


def c_array(ctype: str, name: str, items: list[str]) -> str:
    return f"static const {ctype} {name}[{max(len(items), 1)}] = {{{', '.join(items) or '0'}}};\n"
