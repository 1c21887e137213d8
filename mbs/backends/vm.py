"""Evaluator 1: CasADi's own virtual machine (always available, float64 only)."""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.backends.info import info_of
from mbs.backends.system import Bound, System


def _flat(dm) -> np.ndarray:
    """Column-major flattening, the same layout the generated C writes."""
    return np.asarray(dm, dtype=float).ravel(order="F")


class VMSystem(System):
    """Runs the model's CasADi functions in CasADi's virtual machine."""

    backend = "vm"

    def __init__(self, symbolic, dtype: str = "float64"):
        # imported here: the FMU loads saved functions without this constructor, and needs
        # neither the integrators' tableaux nor what they import (scipy)
        from mbs.integrators import FIXED_STEP, symbolic_increment, symbolic_step

        if np.dtype(dtype) != np.float64:
            raise ValueError(f"the virtual machine computes in float64 only, not {dtype!r}; "
                             "use backend='compiled' for float32")
        self.functions = dict(symbolic.functions)
        for name, tab in FIXED_STEP.items():
            self.functions[f"step_{name}"] = symbolic_step(symbolic["rhs"], symbolic["project"], tab)
            self.functions[f"incr_{name}"] = symbolic_increment(symbolic["rhs"], tab)
        super().__init__(info_of(symbolic, {n: t.stages for n, t in FIXED_STEP.items()}), dtype)

    def _eval(self, name, *args):
        out = self.functions[name](*args)
        return [_flat(o) for o in (out if isinstance(out, (list, tuple)) else [out])]

    def bind(self, name):
        f = self.functions[name]
        ins = [np.zeros(f.nnz_in(i)) for i in range(f.n_in())]
        outs = [np.zeros(f.nnz_out(i)) for i in range(f.n_out())]

        def call() -> int:
            for o, v in zip(outs, self._eval(name, *ins)):
                o[:] = v
            return 0
        return Bound(name, ins, outs, call)

    def _run(self, method, x0, t0, h, k0, n, every, p, comp, compensated=True):
        incr, project = self.functions[f"incr_{method}"], self.functions["project"]
        rows, x = [], x0
        for i in range(n):
            try:
                x = _compensated_add(x, _flat(incr(x, t0 + (k0 + i) * h, h, p)), comp, project, compensated)
            except RuntimeError:
                return np.array(rows).reshape(-1, x0.size), 2, i
            if not np.all(np.isfinite(x)):
                return np.array(rows).reshape(-1, x0.size), 1, i
            if (i + 1) % every == 0 or i + 1 == n:
                rows.append(x)
        return np.array(rows).reshape(-1, x0.size), 0, n


def _compensated_add(x, dx, comp, project, compensated=True):
    """``project(x + dx)`` with Kahan compensation ``comp`` (updated in place), as the C driver does."""
    y = dx - comp
    s = x + y
    comp[:] = (s - x) - y if compensated else 0.0
    xp = _flat(project(s))
    comp[xp != s] = 0.0
    return xp
