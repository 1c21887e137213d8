"""Benchmark of the native FMU's model exchange and exact derivatives (``heli bench fmu-me``).

1. The Jacobian of the FMI 2.0 ME FMU (every derivative and output with respect to every state
   and input, 126 x 39 for forward flight) in one host (fmpy, this process): from its
   directional derivatives (one ``fmi2GetDirectionalDerivative`` per column) against finite
   differences of its own values (forward: one evaluation per column, as CVode and most hosts
   do; central: two). Time (median) and accuracy: the largest difference from the exact
   Jacobian, relative to its largest entry.
2. One run of ``revs`` revolutions of forward flight under fmpy: the ME FMU with CVode (BDF,
   rtol 1e-8, dense Jacobian by CVode's own differences) against the CS FMU (RK4 at 1/100
   revolution per step): wall time (median) and steps (CVode's internal steps and right-hand
   sides; the CS FMU's communication steps and RK4 sub-steps).
"""
from __future__ import annotations

import ctypes
import statistics
import time

import numpy as np

FAMILY = ("forward-flight", "hover", "ground-run")
SCENE = "forward-flight"
CVODE_RTOL = 1e-8


class _Counted:
    """CVode's internal steps and right-hand sides in fmpy's solver (read after each output step)."""

    steps = rhs = 0

    @classmethod
    def install(cls):
        import fmpy.sundials as sundials
        from fmpy.sundials.libraries import sundials_cvode

        base = sundials.CVodeSolver
        get_steps, get_rhs = sundials_cvode.CVodeGetNumSteps, sundials_cvode.CVodeGetNumRhsEvals
        for fn in (get_steps, get_rhs):
            fn.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_long)]

        class Solver(base):
            def step(self, t, t_next):
                out = super().step(t, t_next)
                n, m = ctypes.c_long(), ctypes.c_long()
                get_steps(self.cvode_mem, ctypes.byref(n))
                get_rhs(self.cvode_mem, ctypes.byref(m))
                cls.steps, cls.rhs = n.value, m.value
                return out

        sundials.CVodeSolver = Solver
        return base

    @staticmethod
    def remove(base) -> None:
        import fmpy.sundials as sundials

        sundials.CVodeSolver = base


def jacobian_bench(fmu, repeats: int = 5) -> dict:
    """Exact (directional derivatives) against forward and central differences (h = 1e-7 and
    1e-5 of max(1, |z|)), in one fmpy host."""
    from fmu.native.me_host import MeHost

    h = MeHost(fmu, SCENE)
    try:
        z0 = h.point()
        n = z0.size
        exact = h.jacobian_exact()
        times = {"directional": [], "forward": [], "central": []}
        results = {}
        for _ in range(repeats):
            for kind, fn in (("directional", h.jacobian_exact), ("forward", h.jacobian_forward),
                             ("central", h.jacobian_central)):
                h.set(z0)
                t0 = time.perf_counter()
                results[kind] = fn()
                times[kind].append(time.perf_counter() - t0)
        scale = np.max(np.abs(exact))
        return {"shape": list(exact.shape), "columns": n,
                **{f"{k}_ms": 1e3 * statistics.median(v) for k, v in times.items()},
                "forward_error": float(np.max(np.abs(results["forward"] - exact)) / scale),
                "central_error": float(np.max(np.abs(results["central"] - exact)) / scale),
                "repeat_error": float(np.max(np.abs(results["directional"] - exact)) / scale),
                "evaluations": {"directional": n, "forward": n + 1, "central": 2 * n}}
    finally:
        h.close()


def run_bench(fmu, revs: float, repeats: int = 3) -> dict:
    """fmpy: the ME FMU with CVode against the CS FMU, ``revs`` revolutions of forward flight."""
    from fmpy import read_model_description, simulate_fmu

    from fmu.native.build import native_spec

    spec = native_spec(FAMILY)[0]
    rev = spec["scenes"][SCENE]["revolution"]
    steps_per_rev = spec["scenes"][SCENE]["steps_per_rev"]
    names = [v.name for v in read_model_description(str(fmu)).modelVariables if v.name.endswith(".flap")]
    common = dict(stop_time=revs * rev, output_interval=rev / steps_per_rev, output=names,
                  start_values={"scene": SCENE})
    walls = {"me": [], "cs": []}
    base = _Counted.install()
    try:
        for _ in range(repeats):
            t0 = time.perf_counter()
            me = simulate_fmu(str(fmu), fmi_type="ModelExchange", solver="CVode", relative_tolerance=CVODE_RTOL,
                              set_stop_time=False, **common)  # fmpy's CVode asks for derivatives past stopTime
            walls["me"].append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            cs = simulate_fmu(str(fmu), fmi_type="CoSimulation", **common)
            walls["cs"].append(time.perf_counter() - t0)
    finally:
        _Counted.remove(base)
    diff = max(float(np.max(np.abs(me[n] - cs[n]))) for n in names)
    n_cs = int(round(revs * steps_per_rev))
    return {"revs": revs, "me_wall_s": statistics.median(walls["me"]), "cs_wall_s": statistics.median(walls["cs"]),
            "cvode_steps": _Counted.steps, "cvode_rhs": _Counted.rhs, "cs_steps": n_cs, "cs_rhs": 4 * n_cs,
            "largest_flap_difference_rad": diff, "cvode_rtol": CVODE_RTOL}


def run(revs: float = 5.0, repeats: int = 3) -> dict:
    from fmu.native.build import ensure_native_fmu

    fmu = ensure_native_fmu(FAMILY)[0]
    return {"scene": SCENE, "jacobian": jacobian_bench(fmu, max(repeats, 5)), "simulation": run_bench(fmu, revs, repeats)}
