"""Read C81 airfoil tables: lift, drag and pitching-moment coefficients against angle of
attack and Mach number, as the US Army's C81 rotorcraft program and its successors print them.

Layout (Fortran fixed columns)::

    name (A30) NML NAL NMD NAD NMM NAM (6I2)       the counts of Mach numbers and angles of the
                                                     CL, CD and CM tables
    7 blanks, M(1..NML) in 7-column fields (9 a line, continued on lines that start with 7 blanks)
    alpha (deg, 7 columns), CL(alpha, M(1..NML)), 9 a line, continued likewise  (NAL rows)
    ... the same for CD (NMD, NAD) and CM (NMM, NAM)

A file typed by hand whose numbers are separated by blanks but not in their columns is read as
well: a line is split at its blanks when that gives the numbers the table expects, or cut where
numbers run together (``-1.0255-.99``), and cut into 7-column fields otherwise. The first 7 columns
of a Mach-number line are skipped whatever they hold, as Fortran's ``7X`` skips them (some decks
print a 0 there); a continuation line's must be blank. Every problem is one line naming the file,
its line number and what was expected.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

FIELD = 7  # columns of one number
PER_LINE = 9  # values per line after the first field
NAME_COLUMNS = 30
COEFFICIENTS = ("CL", "CD", "CM")


class C81Error(ValueError):
    """A C81 file that cannot be read: the message names the file, the line and the problem."""


@dataclass(frozen=True)
class CoefficientTable:
    """One coefficient against angle of attack and Mach number: ``alpha`` (deg, increasing),
    ``mach`` (increasing), ``values`` (len(alpha), len(mach))."""

    alpha: np.ndarray
    mach: np.ndarray
    values: np.ndarray


@dataclass(frozen=True)
class C81:
    """A C81 file: the airfoil's ``name`` and its ``CL``, ``CD`` and ``CM`` tables."""

    name: str
    path: Path
    CL: CoefficientTable
    CD: CoefficientTable
    CM: CoefficientTable

    def table(self, coefficient: str) -> CoefficientTable:
        return getattr(self, coefficient)


class _Lines:
    """The file's lines with their numbers, for messages."""

    def __init__(self, path: Path, text: str):
        self.path, self.lines, self.k = path, text.splitlines(), 0

    def next(self, what: str) -> str:
        while self.k < len(self.lines) and not self.lines[self.k].strip():
            self.k += 1  # blank lines between tables carry nothing
        if self.k >= len(self.lines):
            raise self.error(f"ends before {what}")
        self.k += 1
        return self.lines[self.k - 1].rstrip("\r\n")

    def error(self, what: str, line: int | None = None) -> C81Error:
        at = f", line {line if line is not None else self.k}" if self.lines else ""
        return C81Error(f"C81 file {self.path}{at}: {what}")


def read_c81(path: str | Path) -> C81:
    """The tables of the C81 file ``path``; :class:`C81Error` naming the line of a problem."""
    path = Path(path)
    try:
        text = path.read_text(encoding="latin-1")
    except OSError as exc:
        raise C81Error(f"C81 file {path}: cannot be read ({exc.strerror or exc})") from None
    return parse_c81(text, path)


def parse_c81(text: str, path: Path = Path("<text>")) -> C81:
    """The tables of the C81 ``text`` (:func:`read_c81`)."""
    lines = _Lines(path, text)
    name, counts = _header(lines)
    tables = [_table(lines, c, counts[2 * k], counts[2 * k + 1]) for k, c in enumerate(COEFFICIENTS)]
    return C81(name, path, *tables)


def _header(lines: _Lines) -> tuple[str, list[int]]:
    line = lines.next("the header")
    name, rest = line[:NAME_COLUMNS].strip(), line[NAME_COLUMNS:]
    fixed = [rest[k:k + 2] for k in range(0, 12, 2)]
    if all(f.strip().isdigit() for f in fixed):
        counts = [int(f) for f in fixed]
    else:  # counts separated by blanks after a shorter name
        words = line.split()
        if len(words) < 7 or not all(w.isdigit() for w in words[-6:]):
            raise lines.error("the header must hold the airfoil's name (30 columns) and six counts NML NAL NMD NAD "
                              f"NMM NAM (2 columns each), e.g. '{'NACA 0012':30s} 1 3 1 3 1 3'; found {line!r}")
        name, counts = " ".join(words[:-6]), [int(w) for w in words[-6:]]
    for c, (n_mach, n_alpha) in zip(COEFFICIENTS, zip(counts[::2], counts[1::2])):
        if n_mach < 1 or n_alpha < 2:
            raise lines.error(f"the header gives {n_mach} Mach numbers and {n_alpha} angles for {c}; "
                              "a table needs at least 1 Mach number and 2 angles", 1)
    return name, counts


def _numbers(lines: _Lines, line: str, expected: int, first_field: bool, mach_line: bool = False) -> list[float]:
    """The numbers on ``line``: split at blanks when that gives ``expected`` numbers, else cut
    into 7-column fields (a blank field between numbers reads as 0, as Fortran reads it). The
    first 7 columns of a continuation line must be blank; those of a Mach-number line are
    skipped, as Fortran's ``7X`` skips them, whatever they hold (some decks print a 0 there)."""
    for words in _readings(line, mach_line):
        if len(words) == expected:
            return [float(w) for w in words]
    body = line if first_field else line[FIELD:]
    if not first_field and not mach_line and line[:FIELD].strip():
        raise lines.error(f"a line of Mach numbers or a continuation line starts with {FIELD} blank columns; "
                          f"found {line!r}")
    fields = [body[k:k + FIELD] for k in range(0, len(body.rstrip()), FIELD)]
    try:
        values = [float(f) if f.strip() else 0.0 for f in fields]
    except ValueError:
        values = None
    if values is None or len(values) != expected:
        raise lines.error(f"expected {expected} numbers; found {len(line.split())} separated by blanks and "
                          f"{len(fields)} {FIELD}-column fields{'' if values is not None else ', not all numbers'} "
                          f"in {line!r}")
    return values


NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _readings(line: str, skip_first: bool) -> list[list[str]]:
    """The ways ``line`` reads as numbers apart from its columns: split at blanks, and cut where
    two numbers run together (``-1.161-1.161``, when nothing else is on the line); after its
    first 7 columns too when ``skip_first`` (Fortran's ``7X`` skips whatever they hold)."""
    out = []
    for text in [line, line[FIELD:]] if skip_first else [line]:
        out.append(text.split())
        found = NUMBER.findall(text)
        if "".join(found) == "".join(text.split()):
            out.append(found)
    return [words for words in out if words and _all_numbers(words)]


def _all_numbers(words: list[str]) -> bool:
    try:
        [float(w) for w in words]
    except ValueError:
        return False
    return True


def _row(lines: _Lines, n: int, what: str, leading: bool) -> list[float]:
    """``n`` values of one row (after an angle when ``leading``), 9 a line after the first field."""
    first = min(n, PER_LINE)
    line = lines.next(what)
    for words in _readings(line, not leading):  # a whole row typed on one line
        if n > PER_LINE and len(words) == n + leading:
            return [float(w) for w in words]
    values = _numbers(lines, line, first + leading, leading, mach_line=not leading)
    while len(values) < n + leading:
        left = n + leading - len(values)
        values += _numbers(lines, lines.next(what), min(left, PER_LINE), False)
    return values


def _table(lines: _Lines, coefficient: str, n_mach: int, n_alpha: int) -> CoefficientTable:
    start = lines.k + 1
    mach = np.array(_row(lines, n_mach, f"the Mach numbers of {coefficient}", False))
    rows = np.array([_row(lines, n_mach, f"row {k + 1} of {n_alpha} of {coefficient}", True) for k in range(n_alpha)])
    alpha, values = rows[:, 0], rows[:, 1:]
    for what, x in (("Mach numbers", mach), ("angles of attack", alpha)):
        if np.any(np.diff(x) <= 0):
            k = int(np.argmax(np.diff(x) <= 0))
            raise lines.error(f"the {what} of {coefficient} must increase; {x[k]:g} is followed by {x[k + 1]:g}",
                              start)
    return CoefficientTable(alpha, mach, values)


def _field(x: float) -> str:
    """``x`` in 7 columns with as many decimals as fit."""
    for decimals in range(4, -1, -1):
        text = f"{x:{FIELD}.{decimals}f}"
        if len(text) <= FIELD:
            return text
    raise ValueError(f"{x:g} does not fit in {FIELD} columns")


def _lines(first: str, values) -> list[str]:
    fields = [_field(v) for v in values]
    out = [first + "".join(fields[:PER_LINE])]
    out += [" " * FIELD + "".join(fields[k:k + PER_LINE]) for k in range(PER_LINE, len(fields), PER_LINE)]
    return out


def format_c81(name: str, tables: dict[str, CoefficientTable]) -> str:
    """The text of a C81 file of the airfoil ``name`` with ``tables["CL"]``, ``["CD"]``,
    ``["CM"]`` (values rounded to the 7-column fields)."""
    counts = "".join(f"{len(tables[c].mach):2d}{len(tables[c].alpha):2d}" for c in COEFFICIENTS)
    out = [f"{name[:NAME_COLUMNS]:{NAME_COLUMNS}s}{counts}"]
    for c in COEFFICIENTS:
        t = tables[c]
        out += _lines(" " * FIELD, t.mach)
        for alpha, row in zip(t.alpha, t.values):
            out += _lines(_field(alpha), row)
    return "\n".join(out) + "\n"
