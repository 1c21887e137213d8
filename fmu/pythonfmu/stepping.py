"""The slave's numerics: a communication step's sub-steps through the core's evaluator interface
(:class:`Stepper`), or straight into the compiled driver with its arguments bound once
(:class:`BoundStepper`), and the local loop that failed in a failed sub-step."""
from __future__ import annotations

import ctypes

import numpy as np

from mbs.backends import closure as _closure
from mbs.backends import compiled as _compiled


class Stepper:
    """One instance's numerics through the core's evaluator interface (``_run``, ``_eval``),
    for any evaluator: state ``x`` (nx,), summation compensation ``comp`` (nx,) and
    parameters ``p``, advanced in place."""

    def __init__(self, system, x: np.ndarray, comp: np.ndarray, method: str = "rk4"):
        self.system, self.method = system, method
        self.x, self.comp = np.array(x, dtype=float), np.array(comp, dtype=float)
        self.p = np.zeros(len(system.info.parameters))

    def set_params(self, p: np.ndarray) -> None:
        self.p[:] = p

    def step(self, t: float, h: float, n: int) -> tuple[int, int]:
        """``n`` steps of ``h`` from ``t``; on failure (status 1 non-finite, 2 evaluation
        error) the state is left as it was. Returns (status, sub-steps done)."""
        comp = self.comp.copy()
        rows, status, done = self.system._run(self.method, self.x, t, h, 0, n, n, self.p, comp)
        if not status:
            self.x[:], self.comp[:] = rows[-1], comp
        return status, done

    def snapshot(self) -> tuple[np.ndarray, np.ndarray]:
        """Copies of the state and the summation compensation (to undo a step)."""
        return self.x.copy(), self.comp.copy()

    def restore(self, snap: tuple[np.ndarray, np.ndarray]) -> None:
        """Undo to ``snap`` in place (the compiled driver holds pointers to these buffers)."""
        self.x[:], self.comp[:] = snap

    def outputs(self, t: float) -> list[float]:
        """Every output and local variable of the FMU (generated ``fmu_outputs``)."""
        return self.system._eval("fmu_outputs", self.x, t, self.p)[0].tolist()


# The driver signature that BoundStepper was written for; if the core's template differs,
# the generic Stepper is used.
DRIVER_SIGNATURE = ("int mbs_run_{m}(const casadi_real* x0, double t0, double h, long long k0,\n"
                    "    long long n, long long every, const casadi_real* p, casadi_real* out, casadi_real* comp,\n"
                    "    int compensated, long long* done)")


class BoundStepper(Stepper):
    """:class:`Stepper` for the compiled evaluator with every C argument bound once to fixed
    buffers: turning numpy arrays into pointers on each call costs about 25 µs, as much as
    the integrator step of the Bo105 itself, and an FMU calls twice per communication step."""

    usable = DRIVER_SIGNATURE in _compiled.DRIVER

    def __init__(self, system, x, comp, method: str = "rk4"):
        super().__init__(system, x, comp, method)
        lib = ctypes.CDLL(str(system.folder / "model.so"))
        self._trial, self._t, self._done = np.zeros(self.x.size), np.zeros(1), ctypes.c_longlong()
        ptr = lambda a: a.ctypes.data  # noqa: E731
        self._drive = getattr(lib, f"mbs_run_{method}")
        self._drive.restype = ctypes.c_int
        self._drive.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, *[ctypes.c_longlong] * 3,
                                *[ctypes.c_void_p] * 3, ctypes.c_int, ctypes.c_void_p]
        self._drive_args = (ptr(self.x), ptr(self.p), ptr(self.x), ptr(self._trial), ctypes.addressof(self._done))
        self._vals = np.zeros(self._outputs_size(lib))
        self._fn = lib.fmu_outputs
        self._fn.restype = ctypes.c_int
        self._fn.argtypes = [*[ctypes.c_void_p] * 4, ctypes.c_int]
        sizes = [ctypes.c_longlong() for _ in range(4)]
        lib.fmu_outputs_work(*[ctypes.byref(z) for z in sizes])
        self._arg = (ctypes.c_void_p * max(sizes[0].value, 3))(ptr(self.x), ptr(self._t), ptr(self.p))
        self._res = (ctypes.c_void_p * max(sizes[1].value, 1))(ptr(self._vals))
        self._iw = np.zeros(max(sizes[2].value, 1), np.int64)
        self._w = np.zeros(max(sizes[3].value, 1))
        self._fn_args = (ctypes.addressof(self._arg), ctypes.addressof(self._res), ptr(self._iw), ptr(self._w), 0)

    @staticmethod
    def _outputs_size(lib) -> int:
        f = lib.fmu_outputs_sparsity_out
        f.restype = ctypes.POINTER(ctypes.c_longlong)
        sp = f(0)
        return int(sp[0] * sp[1])

    def step(self, t, h, n):
        self._trial[:] = self.comp
        x, p, out, trial, done = self._drive_args  # out is x: the driver writes the last row only on success
        status = self._drive(x, t, h, 0, n, n, p, out, trial, 1, done)
        if not status:
            self.comp[:] = self._trial
        return (2 if status > 1 else status), self._done.value

    def outputs(self, t):
        self._t[0] = t
        if self._fn(*self._fn_args):
            raise FloatingPointError("the generated function fmu_outputs reported an error")
        return self._vals.tolist()


def closure_failure(stepper, x, t: float, h: float) -> str | None:
    """The local loop (mbs.loops) that could not close in the failed sub-step from ``(x, t)``, or
    None (no loop failed, or the evaluator has no generated right-hand side and outputs)."""
    try:
        return _closure.explain(stepper.system, stepper.method, x, t, h, 1, stepper.p)
    except Exception:
        return None
