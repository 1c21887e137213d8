"""``heli bench work-precision``: error against cost of every integrator on a Bo105 scene.

Protocol (after the usual work-precision diagrams, e.g. SciMLBenchmarks):

* **Span**: ``revs`` main-rotor revolutions from the scene's initial state (default one).
* **Error**: the hinge-angle error (rad), the largest absolute difference to the reference
  over every blade hinge angle (``*.flap``, ``*.lag``, ``*.pitch``, ``*.teeter``) and over
  :data:`SAMPLES_PER_REV` sample times per revolution (the end included). Fixed-step runs
  land on the samples; adaptive runs give them by their dense output (``t_eval``), which is
  what a user of them gets. The error at the end time alone is recorded too.
* **Reference**: scipy's DOP853 at ``rtol = atol =`` :data:`REFERENCE_TOL`, cross-checked
  with RK4 at :data:`CHECK_STEPS_PER_REV` steps per revolution; their difference (same
  measure) is reported as the reference's agreement and must stay far below the errors shown.
* **Sweeps**: fixed-step methods over steps per revolution (:data:`FIXED_SWEEP`),
  adaptive ones over tolerances (``rtol = atol``, :data:`TOLERANCES`).
* **Cost**: wall time of the integration alone, the median of up to ``repeats`` runs
  (one run when it takes longer than :data:`REPEAT_BELOW_S`); right-hand-side evaluations
  ``nfev`` and Jacobian evaluations ``njev`` from the solver interface (:mod:`mbs.solvers`).
* **Failures** (non-finite state, a solver that stops, a run over its wall-time budget)
  are kept in the table with their status and message and listed as omissions.

Fixed-step methods run in the generated C driver (one call per chunk of steps); scipy's
methods call the same compiled right-hand side from Python, with the AD Jacobian for the
implicit ones. :func:`time_at` interpolates each method's wall time at a given error, which
gives the speed ratio at equal accuracy.
"""
from __future__ import annotations

import csv
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from mbs import atomic
from mbs.cli import add_json, emit

SAMPLES_PER_REV = 10
REFERENCE_TOL = 1e-12
CHECK_STEPS_PER_REV = 20480
TARGET_ERROR = 1e-6
REPEATS = 5
REPEAT_BELOW_S = 1.0
FIXED_SWEEP = {
    "euler": (640, 1280, 2560, 5120, 10240, 20480, 40960, 81920),
    "rk4": (20, 40, 60, 80, 120, 160, 240, 320, 480, 640, 960, 1280, 1920, 2560),
    "rk8": (10, 20, 30, 40, 60, 80, 120, 160, 240, 320),
    "midpoint": (20, 40, 80, 160, 320, 640, 1280, 2560, 5120),
}
TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
QUICK = {"fixed_sweep": {"euler": (640, 2560), "rk4": (20, 80, 320), "rk8": (10, 40), "midpoint": (40, 160)},
         "tolerances": (1e-4, 1e-7), "check_steps_per_rev": 2560}
HINGE_SUFFIXES = (".flap", ".lag", ".pitch", ".teeter")
COLUMNS = ("scene", "method", "kind", "setting", "value", "status", "error_rad", "final_error_rad",
           "wall_s", "nfev", "njev", "steps", "message")


@dataclass
class Point:
    """One run of one method at one setting (``steps_per_rev`` or ``rtol``)."""

    method: str
    kind: str
    setting: str
    value: float
    status: str
    error_rad: float
    final_error_rad: float
    wall_s: float
    nfev: int
    njev: int
    steps: int
    message: str

    @property
    def ok(self) -> bool:
        return self.status == "success"


def hinge_indices(state_names: list[str]) -> list[int]:
    """Indices of the blade hinge angles among the states."""
    return [i for i, n in enumerate(state_names) if n.endswith(HINGE_SUFFIXES)]


def hinge_error(x: np.ndarray, ref: np.ndarray, idx: list[int]) -> tuple[float, float]:
    """(largest error over all rows, error in the last row) of the hinge angles (rad);
    inf when the rows do not all exist or are not finite."""
    if x.shape != ref.shape or not np.all(np.isfinite(x[:, idx])):
        return math.inf, math.inf
    d = np.abs(x[:, idx] - ref[:, idx])
    return float(d.max()), float(d[-1].max())


def run_point(problem, method: str, value: float, span: float, samples: int, ref: np.ndarray,
              idx: list[int], repeats: int = REPEATS, max_wall_s: float = 60.0) -> Point:
    """Run ``method`` once per repeat over ``span`` s (``value``: steps over the span for
    fixed-step methods, ``rtol`` for adaptive ones) and measure its error against ``ref``
    (``samples + 1`` rows)."""
    from mbs.solvers import METHODS, solve

    m = METHODS[method]
    if m.kind == "fixed":
        n = _whole_steps(int(value), samples)
        kwargs = {"h": span / n, "every": n // samples}
    else:
        kwargs = {"rtol": value, "atol": value, "t_eval": _sample_times(span, samples), "max_wall_s": max_wall_s}
    runs = []
    for _ in range(max(1, repeats)):
        with np.errstate(all="ignore"):
            sol = solve(problem, method, span, **kwargs)
        runs.append(sol)
        if not sol.ok or sol.wall_s > REPEAT_BELOW_S:
            break
    sol = runs[-1]
    err, final = hinge_error(sol.x, ref, idx) if sol.ok else (math.inf, math.inf)
    setting = "steps" if m.kind == "fixed" else "rtol"
    wall = float(np.median([r.wall_s for r in runs]))
    return Point(method, m.kind, setting, float(value), sol.status.name, err, final, wall, sol.nfev, sol.njev,
                 sol.nsteps, sol.message)


def _sample_times(span: float, samples: int) -> np.ndarray:
    return np.linspace(0.0, span, samples + 1)


def _whole_steps(n: int, samples: int) -> int:
    if n < samples or n % samples:
        raise ValueError(f"{n} steps do not land on the {samples} sample times: give a multiple of {samples}")
    return n


def reference(problem, span: float, samples: int, check_steps: int) -> tuple[np.ndarray, dict]:
    """DOP853 at :data:`REFERENCE_TOL` at the sample times, and its agreement with RK4 at
    ``check_steps`` steps over the span (hinge-angle measure, rad)."""
    from mbs.solvers import solve

    t_eval = _sample_times(span, samples)
    ref = solve(problem, "DOP853", span, rtol=REFERENCE_TOL, atol=REFERENCE_TOL, t_eval=t_eval)
    n = _whole_steps(check_steps, samples)
    chk = solve(problem, "rk4", span, h=span / n, every=n // samples)
    if not (ref.ok and chk.ok):
        raise RuntimeError(f"the reference run failed: DOP853: {ref.message}; RK4: {chk.message}")
    err, final = hinge_error(chk.x, ref.x, hinge_indices(problem.info.state_names))
    return ref.x, {"method": "DOP853", "rtol": REFERENCE_TOL, "atol": REFERENCE_TOL, "nfev": ref.nfev,
                   "wall_s": ref.wall_s, "check_method": "rk4", "check_steps": check_steps,
                   "check_wall_s": chk.wall_s, "agreement_rad": err, "final_agreement_rad": final}


def time_at(points: list[Point], error: float) -> float | None:
    """Wall time (s) at which a method reaches ``error`` (rad): log-log interpolation between
    the last successful point above it and the first below it in order of cost; the cheapest
    point already below it when the first one is; None when none reaches it."""
    ok = sorted((p for p in points if p.ok and math.isfinite(p.error_rad)), key=lambda p: p.wall_s)
    for i, p in enumerate(ok):
        if p.error_rad <= error:
            if i == 0 or ok[i - 1].error_rad <= p.error_rad:
                return p.wall_s
            a = ok[i - 1]
            f = math.log(a.error_rad / error) / math.log(a.error_rad / p.error_rad)
            return math.exp(math.log(a.wall_s) + f * math.log(p.wall_s / a.wall_s))
    return None


def _sweeps(methods, fixed_sweep: dict, tolerances) -> list[tuple[str, float]]:
    from mbs.solvers import METHODS

    out = []
    for name in methods:
        if name not in METHODS:
            raise ValueError(f"unknown method {name!r}; known: {', '.join(METHODS)}")
        values = fixed_sweep[name] if METHODS[name].kind == "fixed" else tolerances
        out += [(name, v) for v in values]
    return out


def run_scene(problem, scene: str, revs: float, span_per_rev: float, methods=None, fixed_sweep=None,
              tolerances=TOLERANCES, repeats: int = REPEATS, samples_per_rev: int = SAMPLES_PER_REV,
              check_steps_per_rev: int = CHECK_STEPS_PER_REV, max_wall_s: float = 60.0,
              progress=None) -> dict:
    """Every method's sweep on ``problem`` over ``revs`` revolutions of ``span_per_rev`` s."""
    from mbs.solvers import METHODS

    if not (revs > 0 and abs(revs * samples_per_rev - round(revs * samples_per_rev)) < 1e-9):
        raise ValueError(f"revs = {revs} must be a positive multiple of 1/{samples_per_rev} revolution")
    if repeats < 1:
        raise ValueError(f"repeats = {repeats} must be >= 1")
    fixed_sweep = fixed_sweep or FIXED_SWEEP
    methods = list(methods or METHODS)
    samples, span = max(1, round(revs * samples_per_rev)), revs * span_per_rev
    ref, ref_info = reference(problem, span, samples, round(revs * check_steps_per_rev))
    idx = hinge_indices(problem.info.state_names)
    todo = _sweeps(methods, fixed_sweep, tolerances)
    points = []
    for k, (name, v) in enumerate(todo):
        value = round(v * revs) if METHODS[name].kind == "fixed" else v
        points.append(run_point(problem, name, value, span, samples, ref, idx, repeats, max_wall_s))
        if progress:
            progress(k + 1, len(todo))
    return _summary(scene, revs, span, samples, ref_info, points, idx, problem.info.state_names)


def _summary(scene, revs, span, samples, ref_info, points, idx, names) -> dict:
    from mbs.solvers import ADAPTIVE, FIXED

    methods = dict.fromkeys(p.method for p in points)
    at = {m: time_at([p for p in points if p.method == m], TARGET_ERROR) for m in methods}
    ours = {m: t for m, t in at.items() if m in FIXED and t is not None}
    scipy = {m: t for m, t in at.items() if m in ADAPTIVE and t is not None}
    best_ours, best_scipy = min(ours, key=ours.get, default=None), min(scipy, key=scipy.get, default=None)
    ratio = scipy[best_scipy] / ours[best_ours] if best_ours and best_scipy else None
    return {"scene": scene, "revs": revs, "span_s": span, "samples": samples, "hinge_angles": [names[i] for i in idx],
            "reference": ref_info, "points": [asdict(p) for p in points],
            "omissions": [asdict(p) for p in points if not p.ok],
            "target_error_rad": TARGET_ERROR, "wall_s_at_target": at, "fastest_ours": best_ours,
            "fastest_scipy": best_scipy, "speedup_at_target": ratio}


# -- files ---------------------------------------------------------------------------------

def write_csv(res: dict, path: Path) -> Path:
    with atomic.replacing(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, COLUMNS)
        w.writeheader()
        for p in res["points"]:
            w.writerow({"scene": res["scene"], **{k: p[k] for k in COLUMNS if k != "scene"}})
    return path


def _curves(res: dict) -> dict[str, list[dict]]:
    curves: dict[str, list[dict]] = {}
    for p in res["points"]:
        curves.setdefault(p["method"], []).append(p)
    return curves


def write_chart(res: dict, path: Path) -> Path:
    """Two log-log panels: hinge-angle error against wall time and against evaluations;
    one curve per method; failed runs listed under the chart."""
    from mbs.plots import _pyplot

    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.4), sharey=True)
    for k, (method, pts) in enumerate(_curves(res).items()):
        ok = sorted((p for p in pts if p["status"] == "success" and math.isfinite(p["error_rad"])),
                    key=lambda p: p["wall_s"])
        style = {"marker": "osD^v<>p"[k % 8], "ls": "-" if pts[0]["kind"] == "fixed" else "--",
                 "label": f"{method} ({'steps/rev' if pts[0]['kind'] == 'fixed' else 'rtol'} sweep)"}
        axes[0].loglog([p["wall_s"] for p in ok], [p["error_rad"] for p in ok], **style)
        axes[1].loglog([max(p["nfev"], 1) for p in ok], [p["error_rad"] for p in ok], **style)
    for ax, label in zip(axes, ("wall time of the run (s)", "right-hand-side evaluations")):
        ax.axhline(res["target_error_rad"], color="k", lw=0.8, ls=":")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("hinge-angle error (rad)")
    axes[1].legend(fontsize=8, loc="lower left")
    ref = res["reference"]
    fig.suptitle(f"work-precision, {res['scene']}, {res['revs']:g} rev; reference DOP853 at {ref['rtol']:g}, "
                 f"RK4 at {ref['check_steps']} steps agrees to {ref['agreement_rad']:.1e} rad")
    fig.text(0.01, 0.01, _omission_text(res), fontsize=7, va="bottom", wrap=True)
    fig.tight_layout(rect=(0, 0.08, 1, 0.95))
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return path


def _omission_text(res: dict) -> str:
    om = res["omissions"]
    if not om:
        return "omissions: none (every run succeeded)"
    items = [f"{p['method']} {p['setting']}={p['value']:g}: {p['status']}" for p in om]
    return "omissions (failed runs, not plotted): " + "; ".join(items)


def write_outputs(res: dict, out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    stem = f"work_precision_{res['scene']}"
    return {"csv": str(write_csv(res, out / f"{stem}.csv")), "png": str(write_chart(res, out / f"{stem}.png"))}


# -- the command ---------------------------------------------------------------------------

SCENES = ("structural", "forward-flight")


def run(scenes=SCENES, revs: float = 1.0, methods=None, repeats: int = REPEATS, out: Path | None = None,
        progress=None, **sweeps) -> dict:
    """The work-precision study of each scene; with ``out``, its CSV and PNG per scene."""
    from mbs import scenes as registry
    from mbs.bench.timing import machine
    from mbs.solvers import Problem

    results = {}
    for name in scenes:
        sc = registry.get(name)
        problem = Problem(sc.model())
        bar = (lambda d, t, name=name: progress(name, d, t)) if progress else None
        res = run_scene(problem, name, revs, sc.revolution(problem.system), methods, repeats=repeats,
                        progress=bar, **sweeps)
        if out is not None:
            res["files"] = write_outputs(res, Path(out))
        results[name] = res
    return {"benchmark": "work-precision", "machine": machine(), "scenes": results}


def _fmt_t(t: float | None) -> str:
    return "not reached" if t is None else f"{1e3 * t:.3g} ms"


def scene_lines(res: dict) -> list[str]:
    ref = res["reference"]
    lines = [f"scene {res['scene']}, {res['revs']:g} rev ({res['span_s']:.4g} s), error over "
             f"{len(res['hinge_angles'])} hinge angles at {res['samples']} samples",
             f"  reference DOP853 at rtol = atol = {ref['rtol']:g} ({ref['nfev']} evaluations); RK4 at "
             f"{ref['check_steps']} steps agrees to {ref['agreement_rad']:.2e} rad",
             f"  wall time at a hinge-angle error of {res['target_error_rad']:g} rad:"]
    for m, t in res["wall_s_at_target"].items():
        lines.append(f"    {m:9s} {_fmt_t(t)}")
    if res["speedup_at_target"]:
        lines.append(f"  fastest ours: {res['fastest_ours']}, fastest scipy: {res['fastest_scipy']}; "
                     f"speed-up {res['speedup_at_target']:.1f}x")
    lines.append(f"  omissions: {len(res['omissions'])} failed runs" if res["omissions"] else "  omissions: none")
    for p in res["omissions"]:
        lines.append(f"    {p['method']} {p['setting']} = {p['value']:g}: {p['message']}")
    if "files" in res:
        lines.append(f"  wrote {res['files']['png']} and {res['files']['csv']}")
    return lines


def cmd_bench_work_precision(args) -> int:
    from mbs._progress import Progress

    bars: dict = {}

    def progress(scene, done, total):
        bars.setdefault(scene, Progress(f"work-precision {scene}", not args.json))(done, total)

    res = run(args.scene or SCENES, args.revs, args.method, args.repeats, Path(args.out), progress,
              **(QUICK if args.quick else {}))
    m = res["machine"]
    lines = [f"machine: {m['cpu']}, {m['cores']} cores; python {m['python']}, numpy {m['numpy']}, "
             f"scipy {m['scipy']}, casadi {m['casadi']}"]
    for r in res["scenes"].values():
        lines += scene_lines(r)
    emit(res, args.json, lines)
    return 0


def register(sub, bench) -> None:
    from mbs import arguments as A
    from mbs.solvers import METHODS

    p = bench.add_parser("work-precision", help="hinge-angle error against wall time and evaluations, every method")
    p.add_argument("--scene", action="append", choices=SCENES, help="scene (repeatable; default both)")
    p.add_argument("--revs", type=A.positive, default=1.0, help="span in main-rotor revolutions (default 1)")
    p.add_argument("--method", action="append", choices=list(METHODS), help="method (repeatable; default all)")
    p.add_argument("--repeats", type=A.positive_int, default=REPEATS,
                   help=f"timed runs per point, median reported (default {REPEATS})")
    p.add_argument("--quick", action="store_true", help="short sweeps (a few points per method), for a first look")
    p.add_argument("--out", type=A.output_folder, default="out/work-precision",
                   help="folder for the PNG and CSV files")
    add_json(p)
    p.set_defaults(fn=cmd_bench_work_precision)
