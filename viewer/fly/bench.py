"""``heli bench fly``: the flight page's model step in WebAssembly (headless Chromium, in the page's
own Web Worker) against the same C compiled natively, in one run on one machine; the page's size,
its time to the first frame and the real-time factor the page reaches flying as fast as it can.

Both sides run the same loop of the same entry points (``hw_run`` of ``fmu/native/heli_wasm.c``:
n co-simulation steps of the model core, each one RK4 step of ``heli simulate``'s size with the
FMU's checks) from the scene's periodic start, in alternation (native, then each page), so that a
change of the machine's load falls on all of them; wall time, and CPU time where the machine lets it be
read (the native thread's; the page's worker thread's from /proc), which a shared machine's load
does not inflate. The WebAssembly model is timed as the page ships
it (``-Os``) and compiled with other flags (``-O2``, ``-O3``, ``-O2 -msimd128``) for comparison.
"""
from __future__ import annotations

import ctypes
import os
import statistics
import tempfile
import time
from pathlib import Path

VARIANTS = {"-Os (shipped)": None, "-O2": ["-O2"], "-O3": ["-O3"], "-O2 -msimd128": ["-O2", "-msimd128"]}


class Native:
    """The native library's ``hw_run``, from the periodic start at each call."""

    def __init__(self, lib_path: Path, spec: dict, scene: str, h: float):
        self.lib = ctypes.CDLL(str(lib_path))
        self.lib.hw_run.argtypes, self.lib.hw_text.restype = [ctypes.c_int, ctypes.c_double], ctypes.c_void_p
        self.vr = {v["name"]: k for k, v in enumerate(spec["variables"])}
        self.scene, self.h = scene, h

    def us_per_step(self, steps: int) -> float:
        lib = self.lib
        assert lib.hw_open() == 0
        for name, value in (("scene", self.scene), ("initial_state", "periodic")):
            text = value.encode() + b"\0"
            ctypes.memmove(lib.hw_text(), text, len(text))
            assert lib.hw_set_string(self.vr[name]) == 0
        assert lib.hw_start() <= 1
        start, cpu = time.perf_counter(), time.thread_time()
        status = lib.hw_run(steps, self.h)
        elapsed, self.cpu_us = time.perf_counter() - start, (time.thread_time() - cpu) / steps * 1e6
        if status > 1:
            raise RuntimeError(f"the native run stopped (status {status})")
        return elapsed / steps * 1e6


def worker_cpu() -> dict[str, float]:
    """CPU seconds of every Web Worker thread of the running Chromium renderers (Linux: their
    /proc entries), by process and thread id; {} where /proc is not there."""
    out, tick = {}, os.sysconf("SC_CLK_TCK")
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            if b"--type=renderer" not in (proc / "cmdline").read_bytes():
                continue
            for task in (proc / "task").iterdir():
                if "Worker" in (task / "comm").read_text():
                    fields = (task / "stat").read_text().rsplit(")", 1)[1].split()
                    out[f"{proc.name}/{task.name}"] = (int(fields[11]) + int(fields[12])) / tick
        except OSError:
            continue
    return out


def _bench(page, steps: int) -> tuple[float, float | None]:
    """µs per step of ``hw_run`` in the page's worker: wall time (the page's clock) and CPU time (the
    worker thread's, None without /proc)."""
    before = worker_cpu()
    wall = page.evaluate(f"window.__fly.bench({steps})")["us_per_step"]
    after = worker_cpu()
    used = [after[k] - before[k] for k in after if k in before]
    return wall, max(used) / steps * 1e6 if used else None


def _measure(pages: dict, native: Native, steps: int, repeats: int) -> dict:
    """In headless Chromium: per page the time to the first frame (ms) and the real-time factor flying
    as fast as it can; then ``repeats`` rounds, each timing ``hw_run`` natively and in every page's
    worker in turn (µs per step), so that a change of the machine's load falls on all of them."""
    from playwright.sync_api import sync_playwright

    from viewer.fly.browser import ARGS, chromium

    out = {name: {"us_per_step": []} for name in pages}
    out["native"] = {"us_per_step": []}
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium(), headless=True, args=ARGS)
        opened = {}
        for name, path in pages.items():
            page = browser.new_page(viewport={"width": 1000, "height": 640})
            errors = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(Path(path).as_uri())
            try:
                page.wait_for_function("window.__fly && window.__fly.state.firstFrameMs", timeout=60000)
            except Exception:
                raise RuntimeError(f"the page {name} showed no first frame in 60 s (errors: {errors or 'none'}; "
                                   f"the model's: {page.evaluate('window.__fly && window.__fly.state.error')})") from None
            out[name]["first_frame_ms"] = page.evaluate("window.__fly.state.firstFrameMs")
            page.evaluate("window.__fly.scale('max'); window.__fly.run()")
            page.wait_for_timeout(3000)
            out[name]["max_factor"] = page.evaluate("window.__fly.state.frame.factor")
            page.evaluate("window.__fly.pause()")
            page.evaluate(f"window.__fly.bench({steps})")  # warm-up: the engine's optimising compiler
            opened[name] = page
        out["native"]["cpu_us_per_step"] = []
        for name in opened:
            out[name]["cpu_us_per_step"] = []
        for _ in range(repeats):
            out["native"]["us_per_step"].append(native.us_per_step(steps))
            out["native"]["cpu_us_per_step"].append(native.cpu_us)
            for name, page in opened.items():
                wall, cpu = _bench(page, steps)
                out[name]["us_per_step"].append(wall)
                out[name]["cpu_us_per_step"].append(cpu)
        browser.close()
    return out


def run(scene: str = "forward-flight", steps: int = 4000, repeats: int = 3, log=None) -> dict:
    """The benchmark (see the module docstring); figures by variant, medians of ``repeats``."""
    from fmu.native import wasm
    from mbs import scenes
    from viewer.fly import family, write_page

    sc = scenes.get(scene)
    names = family(scene)
    with tempfile.TemporaryDirectory(prefix="heli-bench-fly-") as tmp:
        shipped = write_page(scene, Path(tmp) / "fly.html", speeds=[], log=log)
        pages = {"-Os (shipped)": shipped.path}
        for label, flags in VARIANTS.items():
            if flags:
                pages[label] = write_page(scene, Path(tmp) / f"fly{len(pages)}.html", speeds=[], log=log,
                                          flags=[*flags, *wasm.FLAGS[1:]]).path
        spec = wasm.ensure_model(names).spec
        lib = wasm.native_library(names, Path(tmp) / "native" / "model.so")
        h = sc.revolution() / sc.steps_per_rev
        measured = _measure(pages, Native(lib, spec, scene, h), steps, repeats)
        sizes = {label: os.path.getsize(path) for label, path in pages.items()}
    load = list(os.getloadavg())
    native = measured.pop("native")
    native_us, native_best = statistics.median(native["us_per_step"]), min(native["us_per_step"])
    variants = {}
    native_cpu = statistics.median(native["cpu_us_per_step"])
    for label, r in measured.items():
        us, best = statistics.median(r["us_per_step"]), min(r["us_per_step"])
        cpu = statistics.median(r["cpu_us_per_step"]) if None not in r["cpu_us_per_step"] else None
        variants[label] = {"us_per_step": us, "best_us_per_step": best, "over_native": us / native_us,
                           "best_over_native": best / native_best, "cpu_us_per_step": cpu,
                           "cpu_over_native": None if cpu is None else cpu / native_cpu,
                           "realtime_factor": h / (us * 1e-6),
                           "page_bytes": sizes[label], "first_frame_ms": r["first_frame_ms"],
                           "page_max_factor": r["max_factor"], "runs_us": r["us_per_step"]}
    best = variants["-Os (shipped)"]
    return {"scene": scene, "steps": steps, "repeats": repeats, "step_s": h, "native_us_per_step": native_us,
            "native_best_us_per_step": native_best, "native_runs_us": native["us_per_step"],
            "native_cpu_us_per_step": native_cpu,
            "native_realtime_factor": h / (native_us * 1e-6), "variants": variants, "load_average": load,
            "meets": {"realtime_x10": best["realtime_factor"] >= 10,
                      "within_2x_native": (best["cpu_over_native"] or best["over_native"]) <= 2,
                      "page_under_5MB": best["page_bytes"] <= 5e6}}


def lines(res: dict) -> list[str]:
    """The human-readable report of :func:`run`."""
    out = [f"{res['scene']}: {res['steps']} RK4 steps of {res['step_s'] * 1e3:.4f} ms (the model core's doStep), median "
           f"(best) of {res['repeats']} alternating runs; load average {res['load_average'][0]:.1f}",
           f"  native (cc -O2, same C):      {res['native_us_per_step']:8.1f} ({res['native_best_us_per_step']:.1f}) µs/step, "
           f"CPU {res['native_cpu_us_per_step']:.1f} µs/step, {res['native_realtime_factor']:6.1f}x real time",
           f"  {'WebAssembly in Chromium':24s}{'µs/step (best)':>16s} {'/native (best)':>15s} {'CPU µs':>7s} "
           f"{'CPU /native':>12s} {'x real time':>12s} {'page MB':>8s} {'1st frame ms':>13s} {'page flying, x':>15s}"]
    for label, v in res["variants"].items():
        page = f"{v['page_max_factor']:15.1f}" if v["page_max_factor"] else f"{'-':>15s}"
        cpu = (f"{v['cpu_us_per_step']:7.1f} {v['cpu_over_native']:12.2f}" if v["cpu_us_per_step"] is not None
               else f"{'-':>7s} {'-':>12s}")
        out.append(f"  {label:24s}{v['us_per_step']:8.1f} ({v['best_us_per_step']:5.1f}) {v['over_native']:7.2f} "
                   f"({v['best_over_native']:5.2f}) {cpu} {v['realtime_factor']:12.1f} {v['page_bytes'] / 1e6:8.2f} "
                   f"{v['first_frame_ms']:13.0f} {page}")
    m = res["meets"]
    out.append("  goals (shipped page): real time x10 " + ("met" if m["realtime_x10"] else "NOT met") + "; <= 2x native "
               + ("met" if m["within_2x_native"] else "NOT met") + "; page <= 5 MB " + ("met" if m["page_under_5MB"] else
                                                                                    "NOT met"))
    return out
