"""``heli bench stability``: measured stability limits of the fixed-step methods against the
limits predicted from the eigenvalues of the AD Jacobian (:mod:`mbs.linearize`).

Predicted limit: the largest ``h`` with ``|R(hλ)| <= 1`` for every eigenvalue ``λ`` of
``df/dx`` at states sampled along a reference run (RK4 at a quarter of its limit at the
initial state), ``R`` the method's stability function.

Measured limit: the first step size at which a run over a fixed span blows up (non-finite
state) or grows. "Grows" is judged on the energy for conservative and damped models (the
maximum rise ``(E - E0)/|E0|`` above :data:`ENERGY_RISE`; a stable run of a conservative
model only shows its accuracy error, far below, and a damped model never gains energy) and
on the state amplitude for driven models, whose energy is not conserved (``max |x|_inf``
above :data:`AMPLITUDE_GROWTH` times that of the reference run). Explicit methods: a
geometric sweep across the prediction, then bisection of the first stable/unstable bracket.

Explicit Euler has no stable step on the imaginary axis (``|R(iy)|^2 = 1 + y^2``): instead
of a limit, the growth per step of the fastest mode is measured (its amplitude, projected
with the mode's left eigenvector on the difference to an RK4 run) and compared with
``|R(hλ)|^2``. The implicit midpoint rule is A-stable (no limit): it is run at multiples of
RK4's limit until its Newton iteration fails, which is reported as such, not as instability.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from mbs.cli import add_json, emit

ENERGY_RISE = 1e-4
AMPLITUDE_GROWTH = 2.0
GRID = (0.5, 0.7, 0.85, 0.95, 1.0, 1.05, 1.15, 1.3, 1.6, 2.0)
BISECT_TOL = 2e-3
MIDPOINT_MULTIPLES = (1, 2, 5, 10, 20, 50, 100)
MIN_STEPS = 50
EULER_REACH = (0.4, 0.2, 0.1, 0.05)


@dataclass
class Probe:
    """One run: step ``h`` (s), verdict, solver status, growth (relative energy rise or
    amplitude ratio; inf when the run failed) and steps done."""

    h: float
    stable: bool
    status: str
    growth: float
    steps: int


@dataclass
class Judge:
    """How runs are judged: ``kind`` "energy" or "amplitude" (see the module docstring)."""

    kind: str
    x0: np.ndarray
    e0: float = 0.0
    amplitude: float = 1.0

    @property
    def limit(self) -> float:
        return ENERGY_RISE if self.kind == "energy" else AMPLITUDE_GROWTH

    def judge(self, problem, sol) -> tuple[float, bool]:
        """(growth, stable). The energy counts as growing when its rise exceeds the limit and
        is still increasing (the second half of the run rises more than twice the first):
        a bounded energy error, however large, is an accuracy matter, not instability."""
        if self.kind == "amplitude":
            g = float(np.abs(sol.x).max() / self.amplitude)
            return g, g <= self.limit
        rise = (np.array([problem.energy(x, t) for x, t in zip(sol.x, sol.t)]) - self.e0) / abs(self.e0)
        half = len(rise) // 2
        increasing = rise[half:].max() > 2 * max(rise[:half].max(), 0.0)
        return float(rise.max()), bool(rise.max() <= self.limit or not increasing)


def probe(problem, method: str, h: float, span: float, judge: Judge) -> Probe:
    """Run ``method`` with step ``h`` over about ``span`` s (a whole number of steps, at
    least :data:`MIN_STEPS`, so that a few huge steps cannot pass for stability)."""
    from mbs.solvers import solve

    n = max(MIN_STEPS, math.ceil(span / h - 1e-9))
    with np.errstate(all="ignore"):
        sol = solve(problem, method, n * h, h=h, x0=judge.x0, every=max(1, n // 400))
    if not sol.ok:
        return Probe(h, False, sol.status.name, math.inf, sol.nsteps)
    g, stable = judge.judge(problem, sol)
    return Probe(h, stable, sol.status.name, g, n)


# -- prediction ------------------------------------------------------------------------------

@dataclass
class Prediction:
    """Predicted limits (method -> :class:`mbs.linearize.StepLimit`), the fastest eigenvalue
    ``lam_max`` (1/s) with its dominant states, the sampled states and the judge."""

    limits: dict
    lam_max: complex
    mode: str
    states: np.ndarray
    judge: Judge
    samples: list = field(default_factory=list)


def _limiting_mode(problem, states, lam: complex) -> str:
    from mbs.linearize import modes

    best = min((m for x in states for m in modes(problem.jacobian(x), problem.info.state_names)),
               key=lambda m: abs(m.eigenvalue - complex(lam.real, abs(lam.imag))))
    return best.describe()


def predict(problem, span: float, x0=None, criterion: str = "energy", samples: int = 12) -> Prediction:
    """Eigenvalues of the AD Jacobian at ``samples`` states of an RK4 reference run over ``span`` s."""
    from mbs.integrators import RK4, TABLEAUX
    from mbs.linearize import max_stable_step, predicted_limits
    from mbs.solvers import solve

    x0 = problem.system.x0() if x0 is None else np.asarray(x0, dtype=float)
    h0 = max_stable_step(RK4, np.linalg.eigvals(problem.jacobian(x0))).h
    n = max(4 * samples, math.ceil(span / min(h0 / 4, span / 200)))
    ref = solve(problem, "rk4", span, h=span / n, x0=x0, every=max(1, n // samples))
    if not ref.ok:
        raise RuntimeError(f"the reference run failed ({ref.message}); the model is unstable at h = {span / n:.3g} s")
    eigs = [np.linalg.eigvals(problem.jacobian(x, t)) for x, t in zip(ref.x, ref.t)]
    lam = np.concatenate(eigs)
    lam_max = complex(lam[np.argmax(np.abs(lam))])
    judge = Judge(criterion, x0, problem.energy(x0), float(np.abs(ref.x).max()))
    return Prediction(predicted_limits(TABLEAUX.values(), eigs), lam_max,
                      _limiting_mode(problem, ref.x[:1], lam_max), ref.x, judge)


# -- measurement -----------------------------------------------------------------------------

def measure_explicit(problem, method: str, h_pred: float, span: float, judge: Judge,
                     progress=None) -> tuple[float | None, list[Probe]]:
    """First unstable step (s) near ``h_pred``: sweep :data:`GRID` (times ``h_pred``), then
    bisect the first stable/unstable bracket to :data:`BISECT_TOL`. None if stable up to 2x."""
    probes: list[Probe] = []

    def run(f: float) -> Probe:
        probes.append(probe(problem, method, f * h_pred, span, judge))
        if progress:
            progress(len(probes))
        return probes[-1]

    lo = hi = None
    for f in GRID:
        if not run(f).stable:
            hi = f
            break
        lo = f
    if hi is None:
        return None, probes
    while lo is None and hi > 1 / 64:
        lo = hi / 2 if run(hi / 2).stable else None
        hi = hi if lo is not None else hi / 2
    while lo is not None and hi / lo > 1 + BISECT_TOL:
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if run(mid).stable else (lo, mid)
    return hi * h_pred, probes


def measure_implicit(problem, method: str, h_unit: float, span: float, judge: Judge,
                     progress=None) -> tuple[float | None, list[Probe]]:
    """Run at :data:`MIDPOINT_MULTIPLES` of ``h_unit`` (s) until the first unstable run (its
    step is returned) or the first Newton failure (then None: no instability found)."""
    probes: list[Probe] = []
    for m in MIDPOINT_MULTIPLES:
        probes.append(probe(problem, method, m * h_unit, span, judge))
        if progress:
            progress(len(probes))
        p = probes[-1]
        if p.status == "newton":
            break
        if not p.stable:
            return p.h, probes
    return None, probes


def _amplitude_factor(tab, z: complex) -> float:
    num, den = tab.stability_function()
    return abs(np.polyval(num[::-1], z) / np.polyval(den[::-1], z))


def euler_growth(problem, x0, h: float, lam: complex, decades: float = 10.0) -> dict:
    """Growth per step of the fastest mode under explicit Euler with step ``h`` (s).

    The mode's amplitude is the projection, with its left eigenvector at ``x0``, of the
    difference between the Euler run and an RK4 run of the same step (which filters the
    slow modes and Euler's phase drift). Its growth rate is fitted over the last part of the
    linear range (difference below 1 % of the state); predicted ``|R(hλ)|`` = ``|1 + hλ|``.
    """
    from mbs.integrators import TABLEAUX
    from mbs.solvers import solve

    pred = _amplitude_factor(TABLEAUX["euler"], h * lam)
    n = math.ceil(decades * math.log(10) / math.log(pred))
    every = max(1, n // 2000)
    with np.errstate(all="ignore"):
        e = solve(problem, "euler", n * h, h=h, x0=x0, every=every)
        r = solve(problem, "rk4", n * h, h=h, x0=x0, every=every)
    k = min(len(e.t), len(r.t))
    w, vl = np.linalg.eig(problem.jacobian(x0).T)
    left = vl[:, np.argmin(np.abs(w - lam))]
    delta = e.x[:k] - r.x[:k]
    a = np.abs(delta @ left)
    linear = np.flatnonzero(np.abs(delta).max(axis=1) < 1e-2 * np.abs(r.x[:k]).max())
    idx = linear[linear >= int(0.6 * linear[-1])] if linear.size else linear
    idx = idx[a[idx] > 0]
    slope = np.polyfit(idx * every, np.log(a[idx]), 1)[0] if idx.size > 3 else math.nan
    measured = math.exp(slope)
    return {"h": h, "reach": abs(h * lam), "steps": int(n), "status": e.status.name,
            "predicted_energy_factor": pred**2, "measured_energy_factor": measured**2,
            "ratio": math.log(measured**2) / math.log(pred**2)}


def _pair(lam: complex | None) -> list[float] | None:
    """An eigenvalue as [real, imaginary] (1/s), for JSON."""
    return None if lam is None else [float(complex(lam).real), float(complex(lam).imag)]


# -- one model's table -----------------------------------------------------------------------

def limits_table(problem, span: float, criterion: str = "energy", x0=None,
                 methods=("euler", "rk4", "rk8", "midpoint"), euler_reach=EULER_REACH, progress=None) -> dict:
    """Predicted against measured limit per method, on ``problem`` over ``span`` s."""
    pred = predict(problem, span, x0, criterion)
    h_rk4 = pred.limits["rk4"].h
    out = {"span_s": span, "criterion": criterion, "lam_max": _pair(pred.lam_max), "fastest_mode": pred.mode,
           "methods": {}}
    for name in methods:
        lim = pred.limits[name]
        row = {"predicted_h": lim.h, "limiting_eigenvalue": _pair(lim.eigenvalue), "reach": lim.reach}
        if lim.h == 0:
            row["growth"] = [euler_growth(problem, pred.judge.x0, c / abs(pred.lam_max), pred.lam_max)
                             for c in euler_reach]
            row["measured_h"], row["ratio"] = None, None
        else:
            measure = measure_explicit if math.isfinite(lim.h) else measure_implicit
            h_meas, probes = measure(problem, name, lim.h if math.isfinite(lim.h) else h_rk4, span,
                                     pred.judge, progress)
            row["measured_h"], row["probes"] = h_meas, [asdict(p) for p in probes]
            row["ratio"] = h_meas / lim.h if h_meas and math.isfinite(lim.h) else None
            row["newton_failure_h"] = next((p.h for p in probes if p.status == "newton"), None)
            row["largest_stable_h"] = max((p.h for p in probes if p.stable), default=None)
        out["methods"][name] = row
    return out


# -- the tumbling body: quaternion against Euler angles --------------------------------------

def _euler_angle_rates(e: np.ndarray, w: np.ndarray) -> np.ndarray:
    """(phi, theta, psi)' for body rates ``w`` (ZYX angles, rad): singular at theta = +-90 deg."""
    phi, theta = e[0], e[1]
    s, c = math.sin(phi), math.cos(phi)
    return np.array([w[0] + (w[1] * s + w[2] * c) * math.tan(theta), w[1] * c - w[2] * s,
                     (w[1] * s + w[2] * c) / math.cos(theta)])


def _matrix_from_euler(e) -> np.ndarray:
    (cf, sf), (ct, st), (cp, sp) = ((math.cos(a), math.sin(a)) for a in e)
    return np.array([[cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
                     [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
                     [-st, ct * sf, ct * cf]])


def euler_angle_attitudes(inertia, w0, h: float, n: int) -> np.ndarray:
    """Torque-free attitude (n + 1, 3, 3) by RK4 on Euler angles and Euler's equations,
    starting level with body rates ``w0`` (rad/s); NaN once the angles are non-finite."""
    j = np.asarray(inertia, dtype=float)
    j_inv = np.linalg.inv(j)

    def f(y):
        w = y[3:]
        return np.r_[_euler_angle_rates(y[:3], w), j_inv @ -np.cross(w, j @ w)]

    y, out = np.r_[0.0, 0.0, 0.0, w0], [np.eye(3)]
    with np.errstate(all="ignore"):
        for _ in range(n):
            k1 = f(y)
            k2 = f(y + h / 2 * k1)
            k3 = f(y + h / 2 * k2)
            y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + f(y + h * k3))
            out.append(_matrix_from_euler(y[:3]) if np.all(np.isfinite(y)) else np.full((3, 3), np.nan))
    return np.array(out)


def _angle_between(r1: np.ndarray, r2: np.ndarray) -> np.ndarray:
    """Rotation angle (rad) of ``r1ᵀ r2`` for stacks (n, 3, 3), from ``|r1 - r2|_F = 2√2 sin(angle/2)``
    (accurate for small angles, unlike the trace); nan where either is nan."""
    d = np.sqrt(np.einsum("nij,nij->n", r1 - r2, r1 - r2))
    return 2 * np.arcsin(np.clip(d / (2 * math.sqrt(2)), 0, 1))


def tumbling(h: float = 0.02, span: float = 10.0, backend: str = "compiled", rates=(0.01, 2.0, 0.0)) -> dict:
    """The tumbling rigid body (:func:`mbs.models.stability_cases.tumbling_body`) with RK4
    at ``h``, ``h/2``, ``h/4`` (s) over ``span`` s: energy error and its order, pitch range,
    closest approach of the nose to the vertical, attitude error of the quaternion run and
    of RK4 on Euler angles at ``h`` (reference: the quaternion run at ``h/4``)."""
    from mbs.models.stability_cases import tumbling_body
    from mbs.solvers import Problem, solve

    problem = Problem(tumbling_body(rates), backend)
    x0, e0 = problem.system.x0(), problem.energy(problem.system.x0())
    runs = {k: solve(problem, "rk4", span, h=h / k, x0=x0, every=k) for k in (1, 2, 4)}
    err = {k: float(np.abs([problem.energy(x, t) / e0 - 1 for x, t in zip(s.x, s.t)]).max()) for k, s in runs.items()}
    att = {k: np.array([problem.system.poses(x, t)[1][0] for x, t in zip(s.x, s.t)]) for k, s in runs.items()}
    pitch = np.arcsin(np.clip(-att[4][:, 2, 0], -1, 1))
    euler = euler_angle_attitudes(problem.model.bodies["fuselage"].inertia, rates, h, len(runs[1].t) - 1)
    return {"h": h, "span_s": span, "energy_error": {str(k): v for k, v in err.items()},
            "energy_order": math.log2(err[1] / err[2]), "energy_order_half": math.log2(err[2] / err[4]),
            "pitch_min_deg": float(np.degrees(pitch.min())), "pitch_max_deg": float(np.degrees(pitch.max())),
            "nose_from_vertical_min_deg": float(np.degrees(np.arccos(np.abs(att[4][:, 2, 0]).max()))),
            "quaternion_attitude_error_rad": float(_angle_between(att[1], att[4]).max()),
            "euler_angle_attitude_error_rad": float(np.nanmax(_angle_between(euler, att[4])))
            if np.all(np.isfinite(euler)) else math.inf,
            "euler_angles_finite": bool(np.all(np.isfinite(euler)))}


# -- the failure cases and the command -------------------------------------------------------

CASES = ("euler", "tail-rotor", "stiff-damper", "tumbling")


def tail_rotor_case(progress=None) -> dict:
    """RK4 on the clamped rig with driven rotors, with and without the tail rotor."""
    from mbs.models.stability_cases import tail_rotor_rig
    from mbs.solvers import Problem

    span = 20 * 2 * math.pi / 44.4
    return {f"{'with' if tail else 'without'} tail rotor":
            limits_table(Problem(tail_rotor_rig(tail)), span, "amplitude", methods=("rk4",), progress=progress)
            for tail in (True, False)}


def stiff_damper_case(factor: float = 10.0, progress=None) -> dict:
    """RK4 and the implicit midpoint rule on the rotor with ``factor`` times stiffer lag dampers."""
    from mbs.models.stability_cases import stiff_damper_rotor
    from mbs.solvers import Problem

    out = limits_table(Problem(stiff_damper_rotor(factor)), 2 * 2 * math.pi / 44.4, "energy",
                       methods=("rk4", "midpoint"), progress=progress)
    return out | {"damper_factor": factor}


def run(scene: str = "structural", revs: float = 20.0, cases=CASES, progress=None) -> dict:
    """The predicted-against-measured table of ``scene`` (over ``revs`` main-rotor
    revolutions) and the named failure cases."""
    from mbs import scenes
    from mbs.bench.timing import machine
    from mbs.solvers import Problem

    bad = [c for c in cases if c not in CASES]
    if bad:
        raise ValueError(f"unknown case(s) {bad}; known: {', '.join(CASES)}")
    sc = scenes.get(scene)
    problem = Problem(sc.model())
    criterion = "energy" if sc.conservative else "amplitude"
    table = limits_table(problem, revs * sc.revolution(problem.system), criterion, progress=progress)
    out = {"benchmark": "stability", "machine": machine(), "scene": scene, "revs": revs, "table": table,
           "thresholds": {"energy_rise": ENERGY_RISE, "amplitude_growth": AMPLITUDE_GROWTH,
                          "bisection": BISECT_TOL}, "cases": {}}
    if "tail-rotor" in cases:
        out["cases"]["tail-rotor"] = tail_rotor_case(progress)
    if "stiff-damper" in cases:
        out["cases"]["stiff-damper"] = stiff_damper_case(progress=progress)
    if "tumbling" in cases:
        out["cases"]["tumbling"] = tumbling()
    return out


# -- human-readable lines --------------------------------------------------------------------

def _ms(h) -> str:
    if h is None:
        return "none"
    return "inf" if not math.isfinite(h) else f"{1e3 * h:.4g} ms"


def _method_line(name: str, row: dict) -> str:
    if row.get("growth"):
        g = row["growth"]
        worst = max(abs(r["ratio"] - 1) for r in g)
        reach = ", ".join(f"{r['reach']:g}" for r in g)
        factors = ", ".join(f"{r['measured_energy_factor']:.5f}" for r in g)
        return (f"  {name:9s} {'0 (none)':>12s} {'none':>12s} {'-':>7s}  the fastest mode's energy grows at every "
                f"step tested (hω = {reach}): by {factors} per step, 1+(hω)² predicted "
                f"(logs within {100 * worst:.2g} %)")
    lam = row["limiting_eigenvalue"]
    mode = "" if lam is None else f"λ = {lam[0]:.4g} {'+-'[lam[1] < 0]} {abs(lam[1]):.4g}i 1/s"
    ratio = f"{row['ratio']:.3f}" if row["ratio"] else "-"
    extra = ""
    if not math.isfinite(row["predicted_h"]):
        extra = f"stable up to {_ms(row['largest_stable_h'])}"
        if row.get("newton_failure_h"):
            extra += f"; Newton fails at {_ms(row['newton_failure_h'])} (not instability)"
    return f"  {name:9s} {_ms(row['predicted_h']):>12s} {_ms(row['measured_h']):>12s} {ratio:>7s}  {mode}{extra}"


def table_lines(title: str, table: dict) -> list[str]:
    lines = [f"{title}: span {table['span_s']:.3g} s, growth judged on the {table['criterion']}; "
             f"fastest mode {table['fastest_mode']}",
             f"  {'method':9s} {'predicted h':>12s} {'measured h':>12s} {'ratio':>7s}  limiting eigenvalue / notes"]
    return lines + [_method_line(n, r) for n, r in table["methods"].items()]


def lines_of(res: dict) -> list[str]:
    lines = table_lines(f"scene {res['scene']}", res["table"])
    c = res["cases"]
    for label, t in c.get("tail-rotor", {}).items():
        lines += table_lines(f"RK4 past the tail-rotor limit: clamped rig, driven rotors, {label}", t)
    if "stiff-damper" in c:
        lines += table_lines(f"stiff lead-lag damper ({c['stiff-damper']['damper_factor']:g}x the data)",
                             c["stiff-damper"])
    if "tumbling" in c:
        t = c["tumbling"]
        lines += [f"tumbling body (pitch {t['pitch_min_deg']:.2f} to {t['pitch_max_deg']:.2f} deg, nose within "
                  f"{t['nose_from_vertical_min_deg']:.3f} deg of the vertical), RK4 h = {_ms(t['h'])} "
                  f"over {t['span_s']:g} s:",
                  f"  quaternion: energy error {t['energy_error']['1']:.3g} (h), {t['energy_error']['2']:.3g} (h/2), "
                  f"{t['energy_error']['4']:.3g} (h/4): order {t['energy_order']:.2f}; attitude error "
                  f"{t['quaternion_attitude_error_rad']:.2g} rad",
                  f"  Euler angles (same RK4, same step): attitude error {t['euler_angle_attitude_error_rad']:.3g} rad"]
    return lines


def cmd_bench_stability(args) -> int:
    from mbs._progress import Progress

    cases = CASES if args.case == ["all"] or not args.case else tuple(c for c in args.case if c != "none")
    bar = Progress("stability sweeps", not args.json)
    expected = len(GRID) + math.ceil(math.log(2 / BISECT_TOL, 2))
    res = run(args.scene, args.revs, cases, progress=lambda k: bar(min(k, expected - 1), expected))
    emit(res, args.json, lines_of(res))
    return 0


def register(sub, bench) -> None:
    from mbs import arguments as A

    p = bench.add_parser("stability", help="measured against predicted step-size limits of the fixed-step methods")
    A.add_scene(p, "--scene", default="structural", what="scene of the main table (default structural)")
    p.add_argument("--revs", type=A.positive, default=20.0, help="span of each run in main-rotor revolutions")
    p.add_argument("--case", action="append", choices=("all", "none") + CASES,
                   help="failure case to run (repeatable; default all; 'none' for the table only)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_stability)
