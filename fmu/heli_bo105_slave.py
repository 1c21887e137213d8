"""FMI 2.0 co-simulation slave of the rotor multibody model (a ``pythonfmu`` ``Fmi2Slave``).

A thin adapter over the core: the variables, scenes and models come from the build
(``resources/heli_models/spec.json`` plus one folder per distinct model with the compiled
library ``model.so``, ``info.json`` and the CasADi functions for the virtual machine); the
numerics are the core's fixed-step RK4 driver. Inputs are held constant over a
communication step, which is split into ``n = ceil(dt / max_step)`` equal RK4 sub-steps.

Errors: pythonfmu turns every Python exception into ``fmi2Fatal``. Bad input therefore
never raises: a bad value is stored, logged at once with status error (naming the variable
and the value) and the next ``fmi2DoStep`` returns ``fmi2Discard`` without advancing,
until the value is corrected. Unexpected exceptions are logged with their traceback and
re-raised (``fmi2Fatal``). Error messages are also written to ``stderr``, because most
importers drop FMU log messages unless debug logging is on.

In the shipped FMU this module is the entry module ``heli_bo105_slave_<digest>`` and imports
the core's run-time files from the package ``heli_bo105_<digest>`` (both names unique to the
build), never from an ``mbs`` that the host may have imported.
"""
from __future__ import annotations

import json
import math
import sys
import traceback
from pathlib import Path

import numpy as np
from pythonfmu import DefaultExperiment, Fmi2Slave, Real, String
from pythonfmu.enums import Fmi2Causality, Fmi2Initial, Fmi2Status, Fmi2Variability

from mbs.backends.compiled import CompiledSystem
from mbs.backends.info import ModelInfo

MODELS = "heli_models"
STATE_FORMAT = "heli-fmu-state-1"
TIME_TOLERANCE = 1e-9  # relative mismatch allowed between the master's time and ours

# SI base-unit exponents for <UnitDefinitions>; unknown units are declared by name only.
BASE_UNITS = {"rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1}, "m": {"m": 1}, "m/s": {"m": 1, "s": -1},
              "s": {"s": 1}, "J": {"kg": 1, "m": 2, "s": -2}, "N": {"kg": 1, "m": 1, "s": -2},
              "1": {}}


def quat_to_euler(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """Aerospace Euler angles (roll, pitch, yaw) in rad of the quaternion ``(w, x, y, z)``
    (same convention as :func:`mbs._rotation.quat_to_euler`, in scalar arithmetic)."""
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(min(1.0, max(-1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix (body -> world) of the quaternion ``q = (w, x, y, z)``."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


class BadValue(ValueError):
    """A value that the FMU refuses; the message names the variable and the value."""


class Recipe:
    """How one scene computes the output and local variables from ``(x, t, p)``."""

    def __init__(self, table: dict, n: int):
        self.n = n
        self.xpos, self.xidx = self._pairs(table["x"])
        self.ypos, self.yidx = self._pairs(table["y"])
        self.cpos, self.cval = self._pairs(table["const"], float)
        self.epos = np.array(table["energy"], dtype=int)
        self.euler = [(int(pos), int(axis), [int(i) for i in q]) for pos, axis, q in table["euler"]]

    @staticmethod
    def _pairs(rows, kind=int):
        rows = list(rows)
        return (np.array([r[0] for r in rows], dtype=int), np.array([r[1] for r in rows], dtype=kind))

    def evaluate(self, system, x: np.ndarray, t: float, p: np.ndarray) -> list[float]:
        v = np.empty(self.n)
        v[self.xpos] = x[self.xidx]
        if self.ypos.size:
            v[self.ypos] = system._eval("outputs", x, t, p)[0][self.yidx]
        if self.epos.size:
            v[self.epos] = system._eval("energy", x, t, p)[0][-1]
        v[self.cpos] = self.cval
        angles = {}
        for pos, axis, q in self.euler:
            key = tuple(q)
            if key not in angles:
                angles[key] = quat_to_euler(*(float(x[i]) for i in q))
            v[pos] = angles[key][axis]
        return v.tolist()


def load_vm(folder: Path, info: ModelInfo):
    """The virtual-machine evaluator from the CasADi functions saved at build time (needs
    casadi on the host)."""
    import casadi as ca

    from mbs.backends.system import System
    from mbs.backends.vm import VMSystem

    vm = VMSystem.__new__(VMSystem)
    vm.functions = {f.stem: ca.Function.load(str(f)) for f in sorted((folder / "vm").glob("*.casadi"))}
    System.__init__(vm, info, "float64")
    return vm


def _repoint_package(resources: str | None) -> None:
    """Point this package's modules at ``resources`` if the folder they were first imported
    from has gone (an importer deleted an earlier copy of this FMU; the code is identical,
    the package name carries its digest), so that later imports (e.g. the VM) still work."""
    top = CompiledSystem.__module__.split(".")[0]
    own = Path(resources or "") / top
    if not own.is_dir():
        return
    for name, module in list(sys.modules.items()):
        paths = getattr(module, "__path__", None) if name.split(".")[0] == top else None
        if paths and not all(Path(p).is_dir() for p in paths):
            module.__path__ = [str(own.joinpath(*name.split(".")[1:]))]


class HeliRotorSlave(Fmi2Slave):
    """Rotor multibody model as an FMI 2.0 co-simulation slave; see the module docstring."""

    author = "rotor-mbs"
    license = "MIT"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        root = Path(self.resources or Path(__file__).parent) / MODELS
        self._root = root
        self._spec = json.loads((root / "spec.json").read_text())
        self.modelName = self._spec["model_identifier"]
        self.description = self._spec["description"]
        self.version = self._spec["version"]
        ex = self._spec["default_experiment"]
        self.default_experiment = DefaultExperiment(ex["start"], ex["stop"], ex["step"])
        _repoint_package(self.resources)
        self._settings: dict = {}
        self._errors: dict[str, str] = {}
        self._frozen: dict = {}
        self._systems: dict = {}
        self._phase = "instantiated"
        self._start_time = 0.0
        self._sys = self._x = self._comp = self._p = self._cache = None
        self._t = 0.0
        self._vars = {v["name"]: v for v in self._spec["variables"]}
        for k, v in enumerate(self._spec["variables"]):
            self.register_variable(self._variable(v, k))
        self._positions = {vr: self._vars[var.name]["position"] for vr, var in self.vars.items()
                           if "position" in self._vars[var.name]}

    # -- variables ---------------------------------------------------------------------------
    def _variable(self, v: dict, k: int):
        kind = String if v["type"] == "String" else Real
        name = v["name"]
        args = dict(causality=Fmi2Causality[v["causality"]], variability=Fmi2Variability[v["variability"]],
                    description=v["description"])
        if v["causality"] in ("input", "parameter"):
            return kind(name, getter=lambda: self._value(name), setter=lambda value: self._set(name, value), **args)
        pos = v["position"]
        return kind(name, initial=Fmi2Initial.calculated, getter=lambda: self._computed()[pos],
                    setter=lambda value: self._refuse_output(name, value), **args)

    def get_real(self, vrs: list[int]) -> list[float]:
        """pythonfmu's ``get_real`` with one evaluation of the outputs for all of them."""
        values, out = None, []
        for vr in vrs:
            k = self._positions.get(vr)
            if k is None:
                out += super().get_real([vr])
            else:
                values = values or self._computed()
                out.append(values[k])
        return out

    def to_xml(self, model_options=dict()):
        """pythonfmu's description plus units, ranges, ``<UnitDefinitions>`` and ``<InitialUnknowns>``."""
        from xml.etree.ElementTree import Element, SubElement

        root = super().to_xml(model_options)
        svs = list(root.find("ModelVariables"))
        units = set()
        for sv in svs:
            v = self._vars[sv.get("name")]
            real = sv.find("Real")
            for key in ("unit", "min", "max"):
                if real is not None and v.get(key) is not None:
                    real.set(key, v[key] if key == "unit" else f"{v[key]:.16g}")
            units.add(v.get("unit"))
        defs = Element("UnitDefinitions")
        for u in sorted(units - {None}):
            unit = SubElement(defs, "Unit", name=u)
            if u in BASE_UNITS:
                SubElement(unit, "BaseUnit", {k: str(e) for k, e in BASE_UNITS[u].items()})
        root.insert(list(root).index(root.find("CoSimulation")) + 1, defs)
        structure = root.find("ModelStructure")
        initial = SubElement(structure, "InitialUnknowns")
        for i, sv in enumerate(svs, 1):
            if sv.get("causality") == "output":
                SubElement(initial, "Unknown", index=str(i))
        return root

    def _scene(self) -> dict:
        """The spec of the scene in use (the primary scene while ``scene`` holds a bad value)."""
        return self._spec["scenes"][self._use("scene")]

    def _value(self, name: str):
        """The value last set (what a getter returns), else the scene's default."""
        return self._settings[name] if name in self._settings else self._default(name)

    def _use(self, name: str):
        """The value in use: the one set, unless it was refused, else the scene's default."""
        return self._settings[name] if name in self._settings and name not in self._errors else self._default(name)

    def _default(self, name: str):
        if name == "scene":
            return self._spec["primary"]
        if name == "evaluator":
            return "compiled"
        scene = self._scene()
        if name == "max_step":
            omega = self._use("omega") if "omega" in self._vars else scene["omega"]
            return 2 * math.pi / abs(omega) / scene["steps_per_rev"]
        if name == "initial_forward_speed":
            return scene["forward_speed"]["default"] if scene["forward_speed"] else 0.0
        return scene["defaults"][name]

    def _set(self, name: str, value) -> None:
        self._settings[name] = value
        self._errors.pop(name, None)
        self._p = self._cache = None
        try:
            self._check(name, value)
        except BadValue as exc:
            self._errors[name] = self._report(str(exc))
            return
        v = self._vars[name]
        if v["causality"] == "input" or v["variability"] == "tunable":
            return
        if self._phase != "stepping":
            self._sys = self._x = None
        elif value != self._frozen[name]:
            self._errors[name] = self._report(
                f"parameter {name!r} is fixed: it cannot change after initialisation (set to {value!r}, "
                f"in use {self._frozen[name]!r}); the FMU refuses to step until it is set back")

    def _check(self, name: str, value) -> None:
        v = self._vars[name]
        if v["type"] == "String":
            if value not in v["allowed"]:
                raise BadValue(f"parameter {name!r} = {value!r} is not one of: {', '.join(v['allowed'])}")
            return
        what, unit = f"{v['causality']} {name!r}", v.get("unit") or ""
        if not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise BadValue(f"{what} = {value!r} {unit} is not a finite number")
        low, high = self._scene()["ranges"].get(name, (None, None))
        low, high = -math.inf if low is None else low, math.inf if high is None else high
        if not low <= value <= high:
            raise BadValue(f"{what} = {value!r} {unit} is outside its range [{low!r}, {high!r}]")
        if name == "max_step" and value <= 0:
            raise BadValue(f"{what} = {value!r} s must be positive")

    def _refuse_output(self, name: str, value) -> None:
        self._errors[name] = self._report(f"{self._vars[name]['causality']} {name!r} cannot be set "
                                          f"(attempted {value!r}); the FMU refuses to step until reset")

    # -- logging -----------------------------------------------------------------------------
    def _report(self, message: str, status: Fmi2Status = Fmi2Status.error) -> str:
        """Log ``message`` through FMI and, unless it is only information, on stderr."""
        self.log(message, status)
        if status > Fmi2Status.ok:
            print(f"{self.modelName} ({self.instance_name}) {status.name}: {message}", file=sys.stderr, flush=True)
        return message

    def _guard(self, what: str, fn, *args):
        """Run ``fn``; a refused value is logged plainly, anything else with its traceback,
        and re-raised (pythonfmu answers fmi2Fatal)."""
        try:
            return fn(*args)
        except BadValue as exc:
            self._report(f"{what} failed: {exc}", Fmi2Status.fatal)
            raise
        except Exception as exc:
            self._report(f"{what} failed: {type(exc).__name__}: {exc}\n{traceback.format_exc()}", Fmi2Status.fatal)
            raise

    # -- FMI life cycle ------------------------------------------------------------------------
    def setup_experiment(self, start_time: float = 0.0, stop_time=None, tolerance=None):
        self._start_time = float(start_time or 0.0)
        self._t = self._start_time

    def enter_initialization_mode(self):
        self._phase = "initialization"

    def exit_initialization_mode(self):
        self._guard("exitInitializationMode", self._initialise)

    def _initialise(self) -> None:
        refused = [m for n, m in self._errors.items() if self._vars[n]["causality"] == "parameter"]
        if refused:
            raise BadValue("; ".join(refused))
        self._prepare()
        self._frozen = {n: self._use(n) for n, v in self._vars.items()
                        if v["causality"] == "parameter" and v["variability"] == "fixed"}
        self._phase = "stepping"

    def _prepare(self) -> None:
        """Load the scene's evaluator and set the initial state at the start time."""
        scene = self._scene()
        self._sys = self._system(scene["group"], self._use("evaluator"))
        x0 = np.array(scene["x0"], dtype=float)
        if "initial_forward_speed" in self._settings and "initial_forward_speed" not in self._errors:
            x0 = self._with_forward_speed(scene, x0, float(self._settings["initial_forward_speed"]))
        self._x, self._t, self._comp = x0, self._start_time, np.zeros(x0.size)
        self._p = self._cache = None
        self._recipe = Recipe(scene["recipe"], self._spec["n_computed"])

    def _with_forward_speed(self, scene: dict, x0: np.ndarray, speed: float) -> np.ndarray:
        """Initial body velocity ``R(q0)^T (speed, 0, 0)``: level flight north at the scene's attitude."""
        fs = scene["forward_speed"]
        if fs is None:
            if speed != 0.0:
                raise BadValue(f"parameter 'initial_forward_speed' = {speed!r} m/s: the scene "
                               f"{self._use('scene')!r} has no free fuselage")
            return x0
        x0 = x0.copy()
        x0[fs["v"]] = quat_to_matrix(x0[fs["q"]]).T @ np.array([speed, 0.0, 0.0])
        return x0

    def _system(self, group: str, evaluator: str):
        key = (group, evaluator)
        if key not in self._systems:
            folder = self._root / group
            info = ModelInfo.load(folder / "info.json")
            if evaluator == "compiled":
                try:
                    self._systems[key] = CompiledSystem(folder)
                except OSError as exc:
                    self._report(f"the compiled model cannot be loaded on this host ({exc}); "
                                 "falling back to the virtual machine (needs casadi)", Fmi2Status.warning)
                    self._systems[key] = load_vm(folder, info)
            else:
                self._systems[key] = load_vm(folder, info)
        return self._systems[key]

    def _params(self) -> np.ndarray:
        if self._p is None:
            self._p = np.array([float(self._use(n)) for n in self._scene()["parameter_order"]])
        return self._p

    def _computed(self) -> list[float]:
        if self._cache is None:
            self._cache = self._guard("getReal", self._compute)
        return self._cache

    def _compute(self) -> list[float]:
        if self._x is None:
            self._prepare()
        return self._recipe.evaluate(self._sys, self._x, self._t, self._params())

    def do_step(self, current_time: float, step_size: float) -> bool:
        return self._guard("doStep", self._step, current_time, step_size)

    def _step(self, t: float, dt: float) -> bool:
        if self._errors:
            for msg in self._errors.values():
                self._report(f"step at t = {t!r} s refused: {msg}", Fmi2Status.discard)
            return False
        problem = self._step_problem(t, dt)
        if problem:
            self._report(problem, Fmi2Status.discard)
            return False
        h_max = float(self._use("max_step"))
        n = max(1, math.ceil(dt / h_max - 1e-12))
        h, comp, p = dt / n, self._comp.copy(), self._params()
        rows, status, done = self._sys._run("rk4", self._x, t, h, 0, n, n, p, comp)
        if status:
            self._report(self._divergence(t, h, n, p, status), Fmi2Status.discard)
            return False
        self._x, self._comp, self._t, self._cache = rows[-1].astype(float), comp, t + dt, None
        return True

    def _step_problem(self, t: float, dt: float) -> str | None:
        if not (math.isfinite(dt) and dt > 0):
            return f"communication step size communicationStepSize = {dt!r} s must be positive and finite"
        if not math.isfinite(t):
            return f"currentCommunicationPoint = {t!r} s is not finite"
        if abs(t - self._t) > TIME_TOLERANCE * max(1.0, abs(self._t)):
            return (f"currentCommunicationPoint = {t!r} s does not match the FMU's time {self._t!r} s "
                    "(restore a saved FMU state to go back in time)")
        return None

    def _divergence(self, t, h, n, p, status) -> str:
        """Redo the failed step recording every sub-step, and name the first state that
        became non-finite."""
        rows, _, done = self._sys._run("rk4", self._x, t, h, 0, n, 1, p, self._comp.copy())
        x = rows[done - 1] if done else self._x
        tk = t + done * h
        where = f"at t = {tk!r} s (sub-step {done + 1} of {n}, h = {h!r} s)"
        if status != 1:
            return f"the model evaluation failed {where}; the step was discarded"
        bad = x + self._sys._eval("incr_rk4", x, tk, h, p)[0]
        i = int(np.flatnonzero(~np.isfinite(bad))[0]) if not np.all(np.isfinite(bad)) else 0
        return (f"the simulation diverged {where}: state {self._sys.info.state_names[i]!r} = {float(bad[i])!r}; "
                f"max_step = {self._use('max_step')!r} s may be beyond RK4's stability limit, or the inputs "
                f"drove the model out of its range; the step was discarded (the state stays at t = {t!r} s)")

    # -- FMU state -----------------------------------------------------------------------------
    def _get_fmu_state(self) -> dict:
        return self._guard("getFMUstate", self._snapshot)

    def _snapshot(self) -> dict:
        return {"format": STATE_FORMAT, "phase": self._phase, "start_time": self._start_time, "t": self._t,
                "x": None if self._x is None else self._x.tolist(),
                "comp": None if self._comp is None else self._comp.tolist(),
                "settings": dict(self._settings), "errors": dict(self._errors), "frozen": dict(self._frozen)}

    def _set_fmu_state(self, state: dict) -> None:
        self._guard("setFMUstate", self._restore, state)

    def _restore(self, state: dict) -> None:
        if not isinstance(state, dict) or state.get("format") != STATE_FORMAT:
            raise BadValue(f"not a state of this FMU (expected format {STATE_FORMAT!r})")
        self._settings, self._errors = dict(state["settings"]), dict(state["errors"])
        self._frozen = dict(state["frozen"])
        self._phase, self._start_time = state["phase"], state["start_time"]
        self._sys = self._x = None
        if state["x"] is not None:
            self._prepare()
            if len(state["x"]) != self._x.size:
                raise BadValue(f"the saved state has {len(state['x'])} entries; scene "
                               f"{self._use('scene')!r} has {self._x.size}")
            self._x, self._comp = np.array(state["x"], dtype=float), np.array(state["comp"], dtype=float)
        self._t, self._p, self._cache = state["t"], None, None
