"""FMI 2.0 co-simulation slave of the rotor multibody model (a ``pythonfmu`` ``Fmi2Slave``).

A thin adapter over the core: the variables, scenes and models come from the build
(``resources/heli_models/spec.json`` plus one folder per distinct model with the compiled
library ``model.so``, ``info.json`` and the CasADi functions for the virtual machine); the
numerics are the core's fixed-step driver (RK4, or rk8 by the parameter ``integrator``).
Inputs are held constant over a communication step, which is split into
``n = ceil(dt / max_step)`` equal sub-steps.

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

import ctypes
import json
import math
import sys
import traceback
from pathlib import Path

import numpy as np
from pythonfmu import DefaultExperiment, Fmi2Slave, Real, String
from pythonfmu.enums import Fmi2Causality, Fmi2Initial, Fmi2Status, Fmi2Variability

from mbs.backends import compiled as _compiled
from mbs.backends.compiled import CompiledSystem
from mbs.backends.info import ModelInfo

MODELS = "heli_models"
STATE_FORMAT = "heli-fmu-state-1"
TIME_TOLERANCE = 1e-9  # relative mismatch allowed between the master's time and ours

# SI base-unit exponents for <UnitDefinitions>; unknown units are declared by name only.
BASE_UNITS = {"rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1}, "m": {"m": 1}, "m/s": {"m": 1, "s": -1},
              "s": {"s": 1}, "J": {"kg": 1, "m": 2, "s": -2}, "N": {"kg": 1, "m": 1, "s": -2},
              "1": {}}


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix (body -> world) of the quaternion ``q = (w, x, y, z)``."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


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


class BadValue(ValueError):
    """A value that the FMU refuses; the message names the variable and the value."""


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
        self._stepper = self._p = self._cache = None
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
        """pythonfmu's ``get_real``, with one evaluation of the outputs for all of them."""
        try:
            idx = [self._positions[vr] for vr in vrs]
        except KeyError:
            return super().get_real(vrs)
        values = self._computed()
        return [values[k] for k in idx]

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
        if name == "integrator":
            return "rk4"
        scene = self._scene()
        if name == "max_step":
            omega = self._use("omega") if "omega" in self._vars else scene["omega"]
            return 2 * math.pi / abs(omega) / scene["steps_per_rev"]
        if name == "initial_forward_speed":
            return scene["forward_speed"]["default"] if scene["forward_speed"] else 0.0
        return scene["defaults"][name]

    def _set(self, name: str, value) -> None:
        v = self._vars[name]
        if v["causality"] == "input" and name not in self._errors and self._settings.get(name) == value:
            return  # a master sets every input before each step; most are unchanged
        self._settings[name] = value
        self._errors.pop(name, None)
        try:
            self._check(name, value)
        except BadValue as exc:
            self._p = self._cache = None
            self._errors[name] = self._report(str(exc))
            return
        order = self._scene()["parameter_order"]
        if v["causality"] == "input" and self._p is not None and name in order:
            self._p[order.index(name)] = value
            self._stepper.set_params(self._p)
            self._cache = None
            return
        self._p = self._cache = None
        if v["causality"] == "input" or v["variability"] == "tunable":
            return
        if self._phase != "stepping":
            self._stepper = None
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
        x0 = np.array(scene["x0"], dtype=float)
        if "initial_forward_speed" in self._settings and "initial_forward_speed" not in self._errors:
            x0 = self._with_forward_speed(scene, x0, float(self._settings["initial_forward_speed"]))
        self._load(scene["group"], self._use("evaluator"), x0, np.zeros(x0.size))
        self._t = self._start_time

    def _load(self, group: str, evaluator: str, x: np.ndarray, comp: np.ndarray) -> None:
        system = self._system(group, evaluator)
        if x.size != system.info.nx:
            raise BadValue(f"a state of {x.size} entries does not fit scene {self._use('scene')!r} "
                           f"({system.info.nx} states)")
        kind = BoundStepper if isinstance(system, CompiledSystem) and BoundStepper.usable else Stepper
        self._stepper = kind(system, x, comp, self._use("integrator"))
        self._p = self._cache = None

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
        """Parameter vector of the scene's model (inputs included), handed to the stepper;
        also caches ``max_step``."""
        if self._p is None:
            self._p = np.array([float(self._use(n)) for n in self._scene()["parameter_order"]])
            self._h_max = float(self._use("max_step"))
            self._stepper.set_params(self._p)
        return self._p

    def _computed(self) -> list[float]:
        if self._cache is None:
            self._cache = self._guard("getReal", self._compute)
        return self._cache

    def _compute(self) -> list[float]:
        if self._stepper is None:
            self._prepare()
        self._params()
        return self._stepper.outputs(self._t)

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
        self._params()
        n = max(1, math.ceil(dt / self._h_max - 1e-12))
        status, _ = self._stepper.step(t, dt / n, n)
        if status:
            self._report(self._divergence(t, dt / n, n, status), Fmi2Status.discard)
            return False
        self._t, self._cache = t + dt, None
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

    def _divergence(self, t, h, n, status) -> str:
        """Redo the failed step recording every sub-step, and name the first state that
        became non-finite."""
        st = self._stepper
        rows, _, done = st.system._run(st.method, st.x, t, h, 0, n, 1, st.p, st.comp.copy())
        x = rows[done - 1] if done else st.x
        tk = t + done * h
        where = f"at t = {tk!r} s (sub-step {done + 1} of {n}, h = {h!r} s)"
        if status != 1:
            return f"the model evaluation failed {where}; the step was discarded"
        bad = x + st.system._eval(f"incr_{st.method}", x, tk, h, st.p)[0]
        i = int(np.flatnonzero(~np.isfinite(bad))[0]) if not np.all(np.isfinite(bad)) else 0
        return (f"the simulation diverged {where}: state {st.system.info.state_names[i]!r} = {float(bad[i])!r}; "
                f"max_step = {self._use('max_step')!r} s may be beyond {st.method}'s stability limit, or the inputs "
                f"drove the model out of its range; the step was discarded (the state stays at t = {t!r} s)")

    # -- FMU state -----------------------------------------------------------------------------
    def _get_fmu_state(self) -> dict:
        return self._guard("getFMUstate", self._snapshot)

    def _snapshot(self) -> dict:
        st = self._stepper
        return {"format": STATE_FORMAT, "phase": self._phase, "start_time": self._start_time, "t": self._t,
                "x": None if st is None else st.x.tolist(), "comp": None if st is None else st.comp.tolist(),
                "settings": dict(self._settings), "errors": dict(self._errors), "frozen": dict(self._frozen)}

    def _set_fmu_state(self, state: dict) -> None:
        self._guard("setFMUstate", self._restore, state)

    def _restore(self, state: dict) -> None:
        if not isinstance(state, dict) or state.get("format") != STATE_FORMAT:
            raise BadValue(f"not a state of this FMU (expected format {STATE_FORMAT!r})")
        self._settings, self._errors = dict(state["settings"]), dict(state["errors"])
        self._frozen = dict(state["frozen"])
        self._phase, self._start_time = state["phase"], state["start_time"]
        self._stepper = None
        if state["x"] is not None:
            x, comp = np.array(state["x"], dtype=float), np.array(state["comp"], dtype=float)
            self._load(self._scene()["group"], self._use("evaluator"), x, comp)
        self._t, self._p, self._cache = state["t"], None, None
