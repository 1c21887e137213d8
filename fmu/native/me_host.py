"""A model-exchange instance of an FMI 2.0 FMU in fmpy (this process), with its knowns (continuous
states, then inputs) and unknowns (derivatives, then outputs) as flat vectors: the exact
Jacobian from its directional derivatives and finite-difference ones from its values."""
from __future__ import annotations

import ctypes

import numpy as np


class MeHost:
    """One initialised FMI 2.0 ME instance of ``fmu`` with the String parameter ``scene`` set."""

    def __init__(self, fmu, scene: str):
        from fmpy import extract, instantiate_fmu, read_model_description

        self.md = read_model_description(str(fmu))
        self.inst = instantiate_fmu(extract(str(fmu)), self.md, fmi_type="ModelExchange")
        vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.inst.setupExperiment(startTime=0.0)
        self.inst.enterInitializationMode()
        self.inst.setString([vr["scene"]], [scene])
        self.inst.exitInitializationMode()
        self.inst.newDiscreteStates()
        self.inst.enterContinuousTimeMode()
        ders = [d.variable for d in self.md.derivatives]
        self.nx = len(ders)
        self.inputs = [v.valueReference for v in self.md.modelVariables if v.causality == "input"]
        self.outputs = [v.valueReference for v in self.md.modelVariables if v.causality == "output"]
        self.unknowns = [*(d.valueReference for d in ders), *self.outputs]
        self.knowns = [*(d.derivative.valueReference for d in ders), *self.inputs]
        self._x, self._dx = (ctypes.c_double * self.nx)(), (ctypes.c_double * self.nx)()

    def point(self) -> np.ndarray:
        self.inst.getContinuousStates(self._x, self.nx)
        return np.concatenate([np.array(self._x[:]), self.inst.getReal(self.inputs)])

    def set(self, z: np.ndarray) -> None:
        self._x[:] = [float(a) for a in z[:self.nx]]
        self.inst.setContinuousStates(self._x, self.nx)
        self.inst.setReal(self.inputs, [float(a) for a in z[self.nx:]])

    def values(self) -> np.ndarray:
        self.inst.getDerivatives(self._dx, self.nx)
        return np.concatenate([np.array(self._dx[:]), self.inst.getReal(self.outputs)])

    def jacobian_exact(self) -> np.ndarray:
        """One fmi2GetDirectionalDerivative per column (seed 1 on one known, every unknown)."""
        return np.array([self.inst.getDirectionalDerivative(self.unknowns, [k], [1.0]) for k in self.knowns]).T

    def _steps(self, z0: np.ndarray, rel: float) -> np.ndarray:
        return rel * np.maximum(1.0, np.abs(z0))

    def jacobian_forward(self, rel: float = 1e-7) -> np.ndarray:
        """(f(z + h e_j) - f(z)) / h, one evaluation per column and one at z."""
        z0 = self.point()
        f0, hs, cols = self.values(), self._steps(z0, rel), []
        for j, h in enumerate(hs):
            z = z0.copy()
            z[j] += h
            self.set(z)
            cols.append((self.values() - f0) / h)
        self.set(z0)
        return np.array(cols).T

    def jacobian_central(self, rel: float = 1e-5) -> np.ndarray:
        """(f(z + h e_j) - f(z - h e_j)) / 2h, two evaluations per column."""
        z0 = self.point()
        hs, cols = self._steps(z0, rel), []
        for j, h in enumerate(hs):
            z = z0.copy()
            z[j] += h
            self.set(z)
            plus = self.values()
            z[j] -= 2 * h
            self.set(z)
            cols.append((plus - self.values()) / (2 * h))
        self.set(z0)
        return np.array(cols).T

    def close(self) -> None:
        self.inst.terminate()
        self.inst.freeInstance()
