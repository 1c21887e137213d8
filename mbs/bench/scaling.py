"""``heli bench scaling``: cost of a right-hand side and of code generation against model size.

Two families of conservative trees:

* ``rotor``: free fuselage, free hub and ``n`` blades on flap and lag hinges
  (:func:`mbs.models.demo.spinning_rotor`), 7 + 2 n degrees of freedom: wide and shallow;
* ``chain``: ``n`` links on hinges with random axes, one after the other: ``n`` degrees of
  freedom, as deep as a tree gets (every rate moves every later body).

Per size: the forward-dynamics path the builder takes and the operations of one
right-hand side by each path, symbolic build and C generation time (together, "code
generation"), C compile time (separately; on a cache hit, the time measured when the
library was first built), and medians of one raw right-hand side and one RK4 step, for the
compiled C and for CasADi's virtual machine. Sizes whose right-hand side has more than
``max_instructions`` operations are timed with the virtual machine only; its cost is
proportional to the number of operations, so it measures the same growth. The growth
exponent is the least-squares slope in log-log, over all sizes and over the upper half.
"""
from __future__ import annotations

import csv
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from mbs import atomic
from mbs.bench.timing import machine, median_time, toolchain
from mbs.joints import Hinge
from mbs.tree import Model

ROTOR_BLADES = (2, 3, 4, 6, 8, 12, 16)
CHAIN_DOF = (5, 10, 20, 40, 70, 100)
QUICK_ROTOR_BLADES = (2, 4, 8, 16)
QUICK_CHAIN_DOF = (5, 10, 20, 40)
MAX_INSTRUCTIONS = 100_000  # right-hand-side operations above which a size is not compiled
COLUMNS = ("family", "size", "dof", "path", "instructions", "ops_composite", "ops_articulated", "build_s",
           "generate_s", "codegen_s", "compile_s", "compile_cached", "rhs_us", "rk4_us", "vm_rhs_us", "vm_rk4_us")


def chain(n: int, seed: int = 0) -> Model:
    """``n`` links in series on hinges with random axes (``n`` DOF), gravity along world z.

    Each link: 1 kg, centre of mass 0.1 m along its x axis, a random full inertia tensor
    about it (principal moments 0.01..0.02 kg m^2), the next hinge 0.2 m along x.
    """
    from scipy.spatial.transform import Rotation

    if n < 1:
        raise ValueError(f"a chain needs at least one link, got n = {n}")
    rng = np.random.default_rng(seed)
    m = Model(f"scaling-chain{n}", gravity=(0.0, 0.0, 9.81))
    parent = "world"
    for i in range(n):
        r = Rotation.random(random_state=rng).as_matrix()
        m.add_body(f"link{i}", parent, Hinge(rng.normal(size=3), name="angle"), mass=1.0,
                   com=(0.1, 0.0, 0.0), inertia=r @ np.diag(rng.uniform(0.01, 0.02, 3)) @ r.T,
                   at=(0.2, 0.0, 0.0) if i else (0.0, 0.0, 0.0))
        parent = f"link{i}"
    return m


def rotor(n_blades: int) -> Model:
    """The demo rotor tree with ``n_blades`` blades: 7 + 2 ``n_blades`` DOF."""
    from mbs.models.demo import spinning_rotor

    if n_blades < 1:
        raise ValueError(f"a rotor needs at least one blade, got n_blades = {n_blades}")
    return spinning_rotor(n_blades=n_blades, free_fuselage=True, name=f"scaling-rotor{n_blades}")


FAMILIES = {"rotor": rotor, "chain": chain}


def fit_exponent(n: ArrayLike, t: ArrayLike) -> float:
    """Least-squares slope ``k`` of ``log t = k log n + c``; ``n``, ``t`` positive, >= 2 points."""
    n, t = np.asarray(n, float), np.asarray(t, float)
    if n.size < 2 or np.any(n <= 0) or np.any(t <= 0) or np.unique(n).size < 2:
        raise ValueError(f"need >= 2 distinct positive sizes and positive values, got n={n}, t={t}")
    return float(np.polyfit(np.log(n), np.log(t), 1)[0])


def upper_half(n: ArrayLike, t: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The points of the larger half of the sizes (at least two)."""
    order = np.argsort(n)
    keep = order[min(len(order) // 2, len(order) - 2):]
    return np.asarray(n, float)[keep], np.asarray(t, float)[keep]


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def _state(system, seed: int = 1) -> np.ndarray:
    """A state with small random angles and rates (the model's defaults plus noise)."""
    rng = np.random.default_rng(seed)
    x, nq = system.x0(), system.info.nq
    x[:nq] += 0.1 * rng.normal(size=nq)
    x[nq:nq + system.info.nv] += 0.5 * rng.normal(size=system.info.nv)
    return system.project(x)


def _compile(vm, source: str, cache: bool) -> tuple[object, float, bool]:
    """Compiled system, compile time in s and whether it came from the cache."""
    from mbs.backends.compiled import CompiledSystem, compile_source
    from mbs.backends.info import ModelInfo

    tmp = None if cache else Path(tempfile.mkdtemp(prefix="mbs-scaling-"))
    try:
        folder = compile_source(source, vm.info, tmp)
        system = CompiledSystem(folder)
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    fresh = "compile_s" in vm.info.extra
    compile_s = vm.info.extra.get("compile_s") if fresh else ModelInfo.load(folder / "info.json").extra.get("compile_s")
    return system, compile_s, not fresh


def _times(step, rhs, x, t, h, p, batches: int) -> tuple[float, float]:
    return (1e6 * median_time(lambda: rhs(x, t, p), batches=batches),
            1e6 * median_time(lambda: step(x, t, h, p), batches=batches))


def measure(family: str, size: int, max_instructions: int = MAX_INSTRUCTIONS, cache: bool = True,
            batches: int = 5) -> dict:
    """One row: sizes, generation/compile times (s) and medians (µs) of rhs and RK4 step."""
    from mbs.backends.compiled import generate
    from mbs.backends.vm import VMSystem
    from mbs.dynamics import symbolic

    model = FAMILIES[family](size)
    vm, build_s = _timed(lambda: VMSystem(symbolic(model)))
    source, generate_s = _timed(lambda: generate(vm.functions, vm.info, "float64"))
    path, counts = vm.info.extra["dynamics"], vm.info.extra["operations"]
    ops = counts[path]
    row = dict(family=family, size=size, dof=vm.info.nv, path=path, instructions=ops,
               ops_composite=counts["composite"], ops_articulated=counts["articulated"], build_s=build_s,
               generate_s=generate_s, codegen_s=build_s + generate_s, compile_s=None, compile_cached=None,
               rhs_us=None, rk4_us=None)
    x, t, h, p = _state(vm), 0.0, 1e-3, vm.params()
    row["vm_rhs_us"], row["vm_rk4_us"] = _times(vm.functions["step_rk4"], vm.functions["rhs"], x, t, h, p, batches)
    if ops <= max_instructions:
        compiled, row["compile_s"], row["compile_cached"] = _compile(vm, source, cache)
        row["rhs_us"], row["rk4_us"] = _times(compiled.function("step_rk4"), compiled.function("rhs"),
                                              x, np.zeros(1), h, p, batches)
    return row


def _fit_pair(rows, key) -> dict | None:
    pts = [(r["dof"], r[key]) for r in rows if r.get(key)]
    if len(pts) < 2:
        return None
    n, t = map(np.array, zip(*pts))
    return {"all": fit_exponent(n, t), "upper_half": fit_exponent(*upper_half(n, t)),
            "dof_range": [int(n.min()), int(n.max())]}


def fits(rows: list[dict]) -> dict:
    """Growth exponents per family and measure (over all sizes and the upper half)."""
    keys = ("rhs_us", "rk4_us", "vm_rhs_us", "instructions", "codegen_s", "compile_s")
    out = {}
    for family in dict.fromkeys(r["family"] for r in rows):
        mine = [r for r in rows if r["family"] == family]
        out[family] = {k: f for k in keys if (f := _fit_pair(mine, k)) is not None}
    return out


def verdict(fit: dict, limit: float = 2.0) -> dict:
    """The right-hand-side growth against the n^``limit`` target, from the widest-ranging timing."""
    key = max(("rhs_us", "vm_rhs_us"), key=lambda k: fit[k]["dof_range"][1] if k in fit else -1)
    exponent = fit[key]["upper_half"]
    return {"measure": key, "dof_range": fit[key]["dof_range"], "upper_half_exponent": exponent,
            "target_exponent": limit, "met": bool(exponent <= limit)}


def write_csv(rows: list[dict], path: Path) -> None:
    with atomic.replacing(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r[k]) for k in COLUMNS})


def write_chart(rows: list[dict], path: Path) -> None:
    """Two log-log panels: rhs time against DOF, and generation/compile time against DOF."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.3))
    styles = {"rotor": ("C0", "o"), "chain": ("C3", "s")}
    for family, (color, marker) in styles.items():
        mine = [r for r in rows if r["family"] == family]
        if not mine:
            continue
        _series(a, mine, "rhs_us", f"{family}, compiled C", color, marker, "-")
        _series(a, mine, "vm_rhs_us", f"{family}, virtual machine", color, marker, ":", hollow=True)
        _series(b, mine, "codegen_s", f"{family}, build + C generation", color, marker, "-")
        _series(b, mine, "compile_s", f"{family}, C compile", color, marker, "--", hollow=True)
    _slopes(a, rows, "vm_rhs_us")
    a.set(xlabel="degrees of freedom", ylabel="one right-hand side (µs)", xscale="log", yscale="log",
          title="right-hand side cost")
    b.set(xlabel="degrees of freedom", ylabel="time (s)", xscale="log", yscale="log", title="code generation")
    for ax in (a, b):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    atomic.savefig(fig, path, dpi=120)
    plt.close(fig)


def _series(ax, rows, key, label, color, marker, ls, hollow=False) -> None:
    pts = [(r["dof"], r[key]) for r in rows if r.get(key)]
    if pts:
        n, t = zip(*pts)
        ax.plot(n, t, ls=ls, marker=marker, color=color, label=label, mfc="none" if hollow else color)


def _slopes(ax, rows, key) -> None:
    """Grey reference lines n^1, n^2, n^3 through the largest chain point."""
    pts = sorted((r["dof"], r[key]) for r in rows if r.get(key))
    if not pts:
        return
    n1, t1 = pts[-1]
    n = np.geomspace(min(p[0] for p in pts), n1, 20)
    for k in (1, 2, 3):
        ax.plot(n, t1 * (n / n1) ** k, color="0.6", lw=0.8, ls="-.")
        ax.annotate(f"n^{k}", (n[0], t1 * (n[0] / n1) ** k), fontsize=7, color="0.4")


def run(rotor_blades=ROTOR_BLADES, chain_dof=CHAIN_DOF, max_instructions: int = MAX_INSTRUCTIONS,
        cache: bool = True, out: Path | None = None, progress=None, batches: int = 5) -> dict:
    """Measure every size; write ``scaling.csv`` and ``scaling.png`` into ``out`` if given."""
    plan = [("rotor", n) for n in rotor_blades] + [("chain", n) for n in chain_dof]
    rows = []
    for i, (family, size) in enumerate(plan):
        rows.append(measure(family, size, max_instructions, cache, batches))
        if progress:
            progress(i + 1, len(plan))
    res = {"benchmark": "scaling", "machine": {**machine(), **toolchain()}, "max_instructions": max_instructions,
           "cache": cache, "rows": rows, "fits": fits(rows)}
    res["target"] = {f: verdict(fit) for f, fit in res["fits"].items() if "vm_rhs_us" in fit}
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(rows, out / "scaling.csv")
        write_chart(rows, out / "scaling.png")
        res["files"] = [str(out / "scaling.csv"), str(out / "scaling.png")]
    return res


# -- command line ---------------------------------------------------------------------------------

def _fmt(v, spec: str) -> str:
    return "-" if v is None else format(v, spec)


def table(res: dict) -> list[str]:
    """Human-readable rows, exponents and the target verdict."""
    lines = [f"{'family':6} {'size':>4} {'DOF':>4} {'path':>11} {'ops':>9} {'codegen s':>9} {'compile s':>10} "
             f"{'rhs µs':>9} {'RK4 µs':>9} {'VM rhs µs':>10}"]
    for r in res["rows"]:
        comp = _fmt(r["compile_s"], ".1f") + ("*" if r["compile_cached"] else " ")
        lines.append(f"{r['family']:6} {r['size']:4d} {r['dof']:4d} {r['path']:>11} {r['instructions']:9d} "
                     f"{r['codegen_s']:9.2f} "
                     f"{comp:>10} {_fmt(r['rhs_us'], '.2f'):>9} {_fmt(r['rk4_us'], '.2f'):>9} "
                     f"{r['vm_rhs_us']:10.1f}")
    lines.append("* compile time measured when the library was first built (cache hit now); "
                 "'-': not compiled (more than {} operations)".format(res["max_instructions"]))
    for family, fit in res["fits"].items():
        parts = [f"{k} {v['all']:.2f} (upper half {v['upper_half']:.2f}, DOF {v['dof_range'][0]}-{v['dof_range'][1]})"
                 for k, v in fit.items()]
        lines.append(f"growth exponents, {family}: " + "; ".join(parts))
    for family, v in res.get("target", {}).items():
        lines.append(f"target rhs <= n^2 up to {v['dof_range'][1]} DOF, {family}: exponent {v['upper_half_exponent']:.2f} "
                     f"({v['measure']}, upper half) -> {'met' if v['met'] else 'MISSED'}")
    lines += [f"wrote {f}" for f in res.get("files", [])]
    return lines


def cmd_bench_scaling(args) -> int:
    from mbs._progress import Progress
    from mbs.cli import emit

    quick = args.quick
    res = run(QUICK_ROTOR_BLADES if quick else ROTOR_BLADES, QUICK_CHAIN_DOF if quick else CHAIN_DOF,
              args.max_instructions, not args.no_cache, Path(args.out), Progress("scaling"),
              batches=3 if quick else 5)
    emit(res, args.json, table(res))
    return 0


def register(sub, bench) -> None:
    from mbs import arguments as A
    from mbs.cli import add_json

    p = bench.add_parser("scaling", help="right-hand side and code generation cost against model size")
    p.add_argument("--quick", action="store_true", help="fewer sizes (rotor 2-16 blades, chain up to 40 DOF)")
    p.add_argument("--out", type=A.output_folder, default="bench-results/scaling",
                   help="folder for scaling.csv and scaling.png")
    p.add_argument("--no-cache", action="store_true",
                   help="compile every size afresh in a temporary folder (honest compile times, slower)")
    p.add_argument("--max-instructions", type=A.positive_int, default=MAX_INSTRUCTIONS,
                   help="compile only models whose right-hand side has at most this many operations")
    add_json(p)
    p.set_defaults(fn=cmd_bench_scaling)
