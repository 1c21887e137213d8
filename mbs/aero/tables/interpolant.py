"""Smooth interpolants of airfoil tables for the generated code: C¹ cubic Hermite pieces, so that
CasADi evaluates them (and their exact derivatives) in the generated C.

Angle of attack: a monotone cubic Hermite (Fritsch–Butland slopes, as scipy's
``PchipInterpolator``): between two table angles the coefficient lies between the two printed
values (no invented lift peak between 0.5°-spaced points near stall, no ringing across the 10–20°
steps beyond it), and the table is closed on itself over ±180° (the slopes at ±180° use the
neighbours across the cut), so reverse flow through 180° is as smooth as anywhere else.
Mach number: a cubic Hermite with three-point (parabolic) slopes, zero at the first and last Mach
number, beyond which the end values are held (as C81 programs hold them) without a kink.

Both directions together are one bicubic per cell of the grid. The tables of one airfoil (c_L,
c_D, c_M, each on its own grid) are merged onto the union of their grids, each interpolant's
pieces unchanged (a piecewise cubic on a grid is one on any finer grid).

In the generated code the whole interpolant is one small MX function, called once per blade
element (one call node in the SX graph, whose outputs are the coefficients). Equal bins whose
edges hold every grid point (a table printed in steps of 0.1° and of 0.05 in Mach) give the cell
from the bin without a search (on other grids the bin's inner points are counted by
comparisons); the cell's power-basis coefficients are read through a pointer into a constant
array, not copied, and Horner's rule evaluates the bicubics. A directional derivative of the SX
graph calls the function's forward derivative (CasADi's, of the MX function), in which the reads'
derivatives are structurally zero: a direction costs the bicubics' derivatives along alpha and
Mach, one number an output. (With the reads as a call node of their own and the bicubics in the
SX graph, each direction carried the derivatives of all the coefficients read, zero in value but
not in structure, since CasADi's SX differentiation of a call whose derivative is structurally
zero leaves stale values: 2.6 times the analytic section's trim time.)
"""
from __future__ import annotations

import casadi as ca
import numpy as np
from scipy.interpolate import BSpline

CLOSURE_TOLERANCE = 1e-9  # largest difference between the values at -180 and 180 deg


def pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Fritsch–Butland slopes at the interior points of ``x`` (n,) for values ``y`` (n, ...):
    zero where the secants change sign or one vanishes, else their weighted harmonic mean;
    (n - 2, ...)."""
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    delta = np.diff(y, axis=0) / h
    h0, h1, d0, d1 = h[:-1], h[1:], delta[:-1], delta[1:]
    w0, w1 = 2 * h1 + h0, h1 + 2 * h0
    same = (d0 * d1) > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = (w0 + w1) / (w0 / d0 + w1 / d1)
    return np.where(same, mean, 0.0)


def periodic_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Slopes at every point of a table closed over one period (``x[-1] - x[0]`` the period,
    ``y[0] == y[-1]``): :func:`pchip_slopes` of the table extended by one point across each end."""
    period = x[-1] - x[0]
    xe = np.concatenate([[x[-2] - period], x, [x[1] + period]])
    ye = np.concatenate([y[-2:-1], y, y[1:2]])
    return pchip_slopes(xe, ye)


def parabolic_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Three-point slopes (those of the parabola through each point and its neighbours) at the
    interior points, zero at both ends; linear in ``y`` (n, ...)."""
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    delta = np.diff(y, axis=0) / h
    inner = (h[1:] * delta[:-1] + h[:-1] * delta[1:]) / (h[:-1] + h[1:])
    zero = np.zeros_like(y[:1])
    return np.concatenate([zero, inner, zero])


def hermite_bspline(x: np.ndarray, y: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Knots (2n + 4,) and control points (2n, ...) of the cubic B-spline equal to the cubic
    Hermite through ``y`` (n, ...) with slopes ``d`` at ``x`` (n,)."""
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    after = y[:-1] + h * d[:-1] / 3  # second Bézier point of each piece
    before = y[1:] - h * d[1:] / 3  # third Bézier point of each piece
    inner = np.stack([after, before], axis=1).reshape((-1,) + y.shape[1:])
    knots = np.concatenate([[x[0]] * 4, np.repeat(x[1:-1], 2), [x[-1]] * 4])
    return knots, np.concatenate([y[:1], inner, y[-1:]])


def check_closed(alpha_deg: np.ndarray, values: np.ndarray, what: str) -> None:
    """ValueError unless the table spans -180..180 deg with the same values at both ends."""
    if abs(alpha_deg[0] + 180) > 1e-9 or abs(alpha_deg[-1] - 180) > 1e-9:
        raise ValueError(f"{what}: the angles of attack run from {alpha_deg[0]:g} to {alpha_deg[-1]:g} deg; a "
                         "rotor blade meets every angle, so the table must run from -180 to 180 deg")
    gap = np.abs(values[0] - values[-1])
    if gap.max() > CLOSURE_TOLERANCE:
        k = int(np.argmax(gap))
        raise ValueError(f"{what}: the value at -180 deg ({values[0, k]:g}) differs from the value at 180 deg "
                         f"({values[-1, k]:g}) in Mach column {k + 1}: the same flow, so the same number")


class HermiteTable:
    """One coefficient table (angles of attack ``alpha_deg`` over -180..180 deg, increasing
    ``mach``, ``values`` (len(alpha), len(mach))) as its cubic Hermite interpolant (module
    docstring); :meth:`corners` gives its values and slopes at the points of any finer grid."""

    def __init__(self, name: str, alpha_deg, mach, values):
        alpha_deg, mach, values = (np.asarray(v, float) for v in (alpha_deg, mach, values))
        check_closed(alpha_deg, values, name)
        self.name, self.alpha, self.mach = name, np.radians(alpha_deg), mach
        self.by_alpha = BSpline(*hermite_bspline(self.alpha, values, periodic_slopes(self.alpha, values)), 3)

    def corners(self, alpha: np.ndarray, mach: np.ndarray) -> np.ndarray:
        """(len(alpha), len(mach), 4): the value and the slopes along Mach, along alpha and along
        both, at the points of the grid ``alpha`` (rad) by ``mach``, which must hold this table's."""
        value, slope = self.by_alpha(alpha), self.by_alpha.derivative()(alpha)  # (n_alpha, own Mach)
        held, rate = _mach_basis(self.mach, mach)  # (n_mach, own Mach)
        return np.stack([value @ held.T, value @ rate.T, slope @ held.T, slope @ rate.T], axis=-1)


def _mach_basis(mach: np.ndarray, fine: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and slopes (len(fine), len(mach)) at ``fine`` of the Mach-direction Hermite through
    unit values at ``mach``, held beyond its ends (slope zero there)."""
    if len(mach) == 1:
        return np.ones((len(fine), 1)), np.zeros((len(fine), 1))
    eye = np.eye(len(mach))
    spline = BSpline(*hermite_bspline(mach, eye, parabolic_slopes(mach, eye)), 3)
    inside = (fine >= mach[0]) & (fine <= mach[-1])
    clipped = np.clip(fine, mach[0], mach[-1])
    return spline(clipped), np.where(inside[:, None], spline.derivative()(clipped), 0.0)


def union(grids) -> np.ndarray:
    """The sorted union of ``grids``, points closer than 1e-12 merged."""
    points = np.unique(np.concatenate(grids))
    return points[np.concatenate([[True], np.diff(points) > 1e-12])]


MAX_BINS = 4096
"""Equal bins over ±180 deg that find an angle's interval without a search."""

HERMITE = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [-3.0, 3.0, -2.0, -1.0], [2.0, -2.0, 1.0, 1.0]])
"""Power-basis coefficients (rows: 1, t, t², t³) of the cubic on [0, 1] from its values at 0 and
1 and its slopes (times the interval) at 0 and 1 (columns)."""


LATTICE_TOLERANCE = 1e-9
"""rad: a grid point this close to a bin edge lies on it."""


def lattice(x: np.ndarray) -> int | None:
    """The fewest equal bins over the grid ``x`` (at most :data:`MAX_BINS`) whose edges hold
    every grid point (a grid printed in steps of 0.5° or 0.1°), or None."""
    span, step = float(x[-1] - x[0]), float(np.diff(x).min())
    for q in range(1, 11):
        count = int(round(span / (step / q)))
        if count > MAX_BINS:
            return None
        position = (x - x[0]) * count / span
        if np.abs(position - np.round(position)).max() * span / count <= LATTICE_TOLERANCE:
            return count
    return None


class Bins:
    """Where a point of the grid ``x`` (n,) lies: equal bins over the grid (and one more at its end,
    holding its last point alone) give its interval as ``first[bin]`` plus the number of the bin's
    inner grid points at or below it. On a grid whose points all lie on bin edges (:func:`lattice`)
    there are no inner points: the bin alone gives the interval (``aligned``)."""

    def __init__(self, x: np.ndarray):
        self.x0, self.n = float(x[0]), len(x)
        span = float(x[-1] - x[0])
        aligned = lattice(x)
        self.aligned = aligned is not None
        self.count = aligned or int(min(MAX_BINS, np.ceil(span / np.diff(x).min() - 1e-9)))
        self.scale = self.count / span
        edges = x[0] + np.arange(self.count + 2) / self.scale
        tolerance = LATTICE_TOLERANCE if self.aligned else 0.0
        self.first = np.clip(np.searchsorted(x, edges[:-1] + tolerance, side="right") - 1, 0, len(x) - 2)
        after = np.searchsorted(x, edges[1:] - tolerance, side="left")  # points strictly inside follow first
        inner = [x[f + 1:min(a, len(x) - 1)] for f, a in zip(self.first, after)]
        self.inner = np.full((self.count + 1, max(len(i) for i in inner)), np.inf)
        for k, points in enumerate(inner):
            self.inner[k, :len(points)] = points

    def position(self, x):
        """``(x - x[0])`` in bins (MX): the bin holding ``x`` is its whole part, for ``x`` within the
        grid (the caller's to ensure)."""
        return (x - self.x0) * self.scale

    def interval(self, x, position):
        """The index of the interval holding ``x`` at ``position`` (MX, :meth:`position`):
        ``first[bin]`` plus the bin's inner points at or below ``x`` (none on an aligned grid).
        The reads truncate ``position`` to its bin; their derivatives are structurally zero."""
        first = _element(self.first, position)
        if not self.inner.shape[1]:
            return first
        points = _read(self.inner, position)
        return first + sum(x >= points[q] for q in range(self.inner.shape[1]))


def clamp(x, low: float, high: float):
    """``x`` held within ``[low, high]`` (MX; NaN gives ``low``) by two selections, no call."""
    x = ca.if_else(x > low, x, low)
    return ca.if_else(x < high, x, high)


def _element(values: np.ndarray, i):
    """``values[int(i)]`` (MX) for ``i`` within them; structurally zero derivative."""
    return ca.MX(ca.DM(np.asarray(values, float)))[i]


def _read(rows: np.ndarray, i):
    """Row ``floor(i)`` of the constant ``rows`` as a column (MX): a pointer into the constant
    array in the generated code, no copy. ``i`` within the rows (the caller's to ensure: the read
    is not checked); the ``floor`` makes its derivative structurally zero (an index of nonzero
    derivative would clear an array the size of the table in each directional derivative)."""
    return ca.MX(ca.DM(rows.T))[:, i]


def cell_rows(alpha: np.ndarray, mach: np.ndarray, data: np.ndarray) -> np.ndarray:
    """One row per grid cell (alpha interval j, Mach interval k; row j (n_mach - 1) + k, one Mach
    interval for a single Mach number): the power-basis coefficients ``P[o, a, b]`` of each
    output's bicubic in ``t^a u^b`` (t, u in [0, 1] across the cell), then alpha_j, 1/(alpha
    interval), M_k, 1/(Mach interval). ``data`` (n_alpha, n_mach, 4, n_out): value, Mach slope,
    alpha slope, both."""
    if len(mach) == 1:  # a bicubic constant in u over a unit Mach interval
        keep = np.array([1.0, 0.0, 1.0, 0.0])[None, None, :, None]  # values and alpha slopes; no Mach slopes
        data, mach = np.concatenate([data, data], axis=1) * keep, np.array([0.0, 1.0])
    h, hm = np.diff(alpha)[None, :, None], np.diff(mach)[None, None, :]
    v, vm, va, vam = (np.moveaxis(data[:, :, d, :], -1, 0) for d in range(4))  # (n_out, n_alpha, n_mach)
    lo, hi, ml, mh = slice(0, -1), slice(1, None), slice(0, -1), slice(1, None)
    alpha_data = [v[:, lo], v[:, hi], h * va[:, lo], h * va[:, hi]]  # values at j, j+1; scaled slopes
    mach_rows = [[q[:, :, ml], q[:, :, mh]] for q in alpha_data]
    mach_slopes = [[q[:, :, ml], q[:, :, mh]] for q in (vm[:, lo], vm[:, hi], h * vam[:, lo], h * vam[:, hi])]
    g = np.stack([np.stack(r + [hm * s[0], hm * s[1]], -1) for r, s in zip(mach_rows, mach_slopes)], -2)
    p = np.einsum("ap,onmpq,bq->nmoab", HERMITE, g, HERMITE)  # (n_a, n_m, n_out, 4, 4)
    n_a, n_m = p.shape[:2]
    extra = [alpha[:-1, None], 1 / np.diff(alpha)[:, None], mach[None, :-1], 1 / np.diff(mach)[None, :]]
    extra = np.stack([np.broadcast_to(e, (n_a, n_m)) for e in extra], -1)
    return np.concatenate([p.reshape(n_a, n_m, -1), extra], -1).reshape(n_a * n_m, -1)


class TableSpline:
    """Several coefficient tables (:class:`HermiteTable`) as one CasADi function of ``alpha``
    (rad) and the Mach number with one output each (module docstring); ``__call__(alpha, mach)``
    -> a column of the coefficients."""

    def __init__(self, name: str, tables: list[HermiteTable]):
        alpha, mach = union([t.alpha for t in tables]), union([t.mach for t in tables])
        self.size, self.mach_range = len(tables), (float(mach[0]), float(mach[-1]))
        data = np.stack([t.corners(alpha, mach) for t in tables], axis=-1)  # (n_alpha, n_mach, 4, n_out)
        angle, mach_number = ca.MX.sym("alpha"), ca.MX.sym("mach")
        m = clamp(mach_number, mach[0], mach[-1]) if len(mach) > 1 else ca.MX(0.0)
        c = _cell(alpha, mach, cell_rows(alpha, mach, data), angle, m)
        t, u = (angle - c[-4]) * c[-3], (m - c[-2]) * c[-1]
        out = [_horner([_horner([c[16 * o + 4 * a + b] for b in range(4)], u) if len(mach) > 1 else c[16 * o + 4 * a]
                        for a in range(4)], t) for o in range(self.size)]
        self.function = ca.Function(f"{name}_cells", [angle, mach_number], [ca.vertcat(*out)],
                                    {"never_inline": True})

    def __call__(self, alpha, mach):
        """The coefficients (n_out,) at ``alpha`` (rad, within ±π; beyond it the cubics of the cells
        at ±π are extended; NaN gives NaN) and Mach number ``mach`` (held at the merged tables' end
        values outside their Mach range): one call node in an SX graph."""
        return self.function(alpha, mach)


def _cell(alpha: np.ndarray, mach: np.ndarray, rows: np.ndarray, a, m):
    """The row of :func:`cell_rows` of the cell holding ``(a, m)`` (MX; ``m`` within the Mach
    grid; ``a`` beyond the angles reads the cell at the nearer end, NaN the first)."""
    bins, cells = Bins(alpha), max(len(mach) - 1, 1)
    k = 0
    if len(mach) > 2:
        mach_bins = Bins(mach)
        k = mach_bins.interval(m, mach_bins.position(m))
    return _read(rows, bins.interval(a, clamp(bins.position(a), 0, bins.count)) * cells + k)


def _horner(coefficients: list, t):
    """``sum(c_a t^a)`` by Horner's rule."""
    out = coefficients[-1]
    for c in coefficients[-2::-1]:
        out = out * t + c
    return out
