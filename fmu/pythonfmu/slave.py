"""FMI 2.0 co-simulation slave of the rotor multibody model (a ``pythonfmu`` ``Fmi2Slave``).

A thin adapter over the core: the variables, scenes and models come from the build
(``resources/heli_models/spec.json`` plus one folder per distinct model with the compiled
library ``model.so``, ``info.json`` and the CasADi functions for the virtual machine); the
numerics are the core's fixed-step driver (RK4, or rk8 by the parameter ``integrator``).
Inputs are held constant over a communication step, which is split into
``n = ceil(dt / max_step (1 - SUBSTEP_TOLERANCE))`` equal sub-steps (a master that counts time in
whole nanoseconds rounds the default step, which is ``max_step``, up by up to 0.5 ns).

Start values: every input and parameter has the primary scene's value as its XML start, and one
that the master does not set is that start, in every scene (FMI 2.0 section 2.2.7: no start
depends on another variable, so a master that writes every start value and one that writes
none run the same). When the scene in use is not the primary one, ``exitInitializationMode``
warns about each value in use equal to its start that differs from that scene's own value
(naming both), and a value the scene cannot take (a forward speed without a free fuselage)
fails it.
``initial_state`` selects the start: ``scene`` (the scene's initial state, the default) or
``periodic`` (the scene's periodic trim from the build, :mod:`fmu.periodic`), whose
controls are then the inputs' defaults.

Errors: pythonfmu's wrapper turns a Python exception into ``fmi2Fatal`` and then crashes on
the next call, so no exception ever leaves this slave. Every entry point (instantiate and
reset, the setters and getters, the life-cycle calls, ``doStep``, the FMU-state calls)
catches everything and logs a message with status error naming the call, the variable or
value reference and the value; the FMU's FMI front end (``fmu/pythonfmu/shim``) turns an error logged
during a call into that call's ``fmi2Error`` and forwards it whatever ``loggingOn`` says.
A getter answers NaN (Real), ``""`` (String), 0 or false for what it cannot give; setting
an output is an error and is ignored. A bad value of an input or parameter is stored and
refused at once (error); while it stands, ``doStep`` returns false (``fmi2Discard``, with a
message) without advancing, and a bad parameter makes ``exitInitializationMode`` fail
(error) with the instance left in initialisation mode, so the master can correct the value
and call it again. ``doStep`` before ``exitInitializationMode`` is an error. ``doStep``
refuses (Discard) a step needing more than ``limits.max_substeps`` sub-steps, and undoes
(Discard) a step after which a hinge angle is beyond ``limits.hinge_angle`` or the state or
the total energy is not finite. A corrupt or foreign FMU state is refused (error) and
nothing changes. Unexpected exceptions are logged with their traceback. Messages of status
warning and worse are also written to ``stderr``.

pythonfmu 0.7.0 executes this file again at every instantiate; :func:`_settle_rerun` at the
end keeps that from leaking memory.

In the shipped FMU this module is the entry module ``heli_rotor_slave_<digest>`` and imports
the core's run-time files from the package ``heli_rotor_<digest>`` and its own helpers
(:mod:`fmu.pythonfmu.stepping`, ``errors``, ``resources``, ``fmu_state``, ``units``) from its
subpackage ``heli_rotor_<digest>.slave`` (names unique to the build), never from an ``mbs`` or
``fmu`` that the host may have imported.
"""
from __future__ import annotations

import math
import sys
import traceback
from pathlib import Path

import numpy as np
from pythonfmu import Boolean, DefaultExperiment, Fmi2Slave, Integer, Real, String
from pythonfmu.enums import Fmi2Causality, Fmi2Initial, Fmi2Status, Fmi2Variability

from fmu.pythonfmu.errors import BadValue, entry_point
from fmu.pythonfmu.fmu_state import STATE_FORMAT, from_bytes, state_problem, to_bytes
from fmu.pythonfmu.resources import keep_one, load_vm, read_spec, repoint_package
from fmu.pythonfmu.stepping import BoundStepper, Stepper, closure_failure
from fmu.pythonfmu.units import unit_definitions
from mbs.backends.compiled import CompiledSystem
from mbs.backends.info import ModelInfo

MODELS = "heli_models"
TIME_TOLERANCE = 1e-9  # relative mismatch allowed between the master's time and ours
DIAGNOSTIC_ROWS = 1000  # rows recorded when a failed step is redone to find where it failed

KINDS = {"Real": Real, "String": String}
FALLBACK = {Real: math.nan, String: "", Integer: 0, Boolean: False}  # what a failed getter answers
SUBSTEP_TOLERANCE = 1e-6  # relative: a step this much longer than n max_step is n sub-steps


def _placeholder():
    """Accessor given to pythonfmu's variables: values go through :class:`HeliRotorSlave`'s
    own ``get_*``/``set_*``, so no variable holds a closure over the instance (a freed
    instance is then not kept alive by a reference cycle)."""
    return None


def _index(indices: list[int]):
    """``indices`` as a slice when they are consecutive (indexing then makes a view), else
    as an integer array."""
    if indices and list(indices) == list(range(indices[0], indices[-1] + 1)):
        return slice(indices[0], indices[-1] + 1)
    return np.array(indices, dtype=int)


def _nan_list(vrs):
    return [math.nan] * len(vrs)


class HeliRotorSlave(Fmi2Slave):
    """Rotor multibody model as an FMI 2.0 co-simulation slave; see the module docstring."""

    author = "rotor-mbs"
    license = "MIT"

    def __init__(self, **kwargs):
        """Runs at fmi2Instantiate and at fmi2Reset; never raises (a failure leaves an
        instance that answers every call with a logged error)."""
        self._broken = None
        self.log_queue, self.vars, self.modelName = [], {}, "HeliRotor"
        self.instance_name = str(kwargs.get("instance_name", ""))
        try:
            super().__init__(**kwargs)
            keep_one(self.resources)
            self._setup()
        except Exception as exc:
            self._broken = f"the FMU could not be set up: {type(exc).__name__}: {exc}"
            self._report(f"fmi2Instantiate: {self._broken}\n{traceback.format_exc()}")

    def _setup(self) -> None:
        root = Path(self.resources or Path(__file__).parent) / MODELS
        self._root, self._spec = root, read_spec(root / "spec.json")
        self.modelName, self.description = self._spec["model_identifier"], self._spec["description"]
        self.version = self._spec["version"]
        ex = self._spec["default_experiment"]
        self.default_experiment = DefaultExperiment(ex["start"], ex["stop"], ex["step"])
        repoint_package(self.resources)
        self._limits = {"max_substeps": 1_000_000, "hinge_angle": math.pi / 2, **self._spec.get("limits", {})}
        self._vars = {v["name"]: v for v in self._spec["variables"]}
        for v in self._spec["variables"]:
            self.register_variable(self._variable(v))
        self._positions = {vr: self._vars[var.name]["position"] for vr, var in self.vars.items()
                           if "position" in self._vars[var.name]}
        self._energy = self._vars.get("total_energy", {}).get("position")
        self._systems: dict = {}
        self._settings, self._errors, self._frozen = {}, {}, {}
        self._phase, self._start_time, self._t = "instantiated", 0.0, 0.0
        self._stepper = self._p = self._cache = None

    # -- variables ---------------------------------------------------------------------------
    def _variable(self, v: dict):
        """pythonfmu's variable of the spec entry ``v`` (accessors: :func:`_placeholder`)."""
        computed = v["causality"] not in ("input", "parameter")
        return KINDS[v["type"]](v["name"], causality=Fmi2Causality[v["causality"]],
                                variability=Fmi2Variability[v["variability"]], description=v["description"],
                                initial=Fmi2Initial.calculated if computed else None,
                                getter=_placeholder, setter=_placeholder)

    def _lookup(self, vr, kind, call: str):
        """The spec entry of value reference ``vr`` if it is a ``kind`` variable, else None
        (after logging an error naming the call and the value reference)."""
        var = self.vars.get(vr) if isinstance(vr, int) else None
        if var is None:
            self._report(f"{call}: unknown value reference {vr!r} (this FMU has 0 to {len(self.vars) - 1})")
            return None
        if not isinstance(var, kind):
            self._report(f"{call}: variable {var.name!r} (value reference {vr}) is a "
                         f"{type(var).__name__}, not a {kind.__name__}")
            return None
        return self._vars[var.name]

    def _get_one(self, vr, kind, call: str):
        """One value for ``call``; on any failure a logged error and ``FALLBACK[kind]``."""
        v = self._lookup(vr, kind, call)
        if v is None:
            return FALLBACK[kind]
        try:
            value = self._value(v["name"]) if v["causality"] in ("input", "parameter") else \
                self._computed()[v["position"]]
            return str(value) if kind is String else float(value)
        except Exception as exc:
            detail = str(exc) if isinstance(exc, BadValue) else f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}"
            self._report(f"{call}: variable {v['name']!r} (value reference {vr}) cannot be computed: {detail}")
            return FALLBACK[kind]

    def _set_one(self, vr, value, kind, call: str) -> None:
        """Set one value for ``call``; a refusal or failure is logged (status error)."""
        v = self._lookup(vr, kind, call)
        if v is None:
            return
        if v["causality"] not in ("input", "parameter"):
            self._report(f"{call}: {v['causality']} {v['name']!r} (value reference {vr}) cannot be set "
                         f"(attempted {value!r}); the value was ignored")
            return
        try:
            self._set(v["name"], value, call)
        except Exception as exc:
            self._report(f"{call}: setting {v['name']!r} (value reference {vr}) to {value!r} failed: "
                         f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}")

    @entry_point("getReal", _nan_list)
    def get_real(self, vrs: list[int]) -> list[float]:
        """Values of ``vrs``; outputs only: one evaluation of the outputs for all of them."""
        try:
            idx = [self._positions[vr] for vr in vrs]
        except (KeyError, TypeError):
            return [self._get_one(vr, Real, "getReal") for vr in vrs]
        values = self._computed()
        return [values[k] for k in idx]

    @entry_point("getString", lambda vrs: [""] * len(vrs))
    def get_string(self, vrs: list[int]) -> list[str]:
        return [self._get_one(vr, String, "getString") for vr in vrs]

    @entry_point("getInteger", lambda vrs: [0] * len(vrs))
    def get_integer(self, vrs: list[int]) -> list[int]:
        return [self._get_one(vr, Integer, "getInteger") for vr in vrs]

    @entry_point("getBoolean", lambda vrs: [False] * len(vrs))
    def get_boolean(self, vrs: list[int]) -> list[bool]:
        return [self._get_one(vr, Boolean, "getBoolean") for vr in vrs]

    @entry_point("setReal")
    def set_real(self, vrs: list[int], values: list[float]) -> None:
        for vr, value in zip(vrs, values):
            self._set_one(vr, value, Real, "setReal")

    @entry_point("setString")
    def set_string(self, vrs: list[int], values: list[str]) -> None:
        for vr, value in zip(vrs, values):
            self._set_one(vr, value, String, "setString")

    @entry_point("setInteger")
    def set_integer(self, vrs: list[int], values: list[int]) -> None:
        for vr, value in zip(vrs, values):
            self._set_one(vr, value, Integer, "setInteger")

    @entry_point("setBoolean")
    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        for vr, value in zip(vrs, values):
            self._set_one(vr, value, Boolean, "setBoolean")

    def to_xml(self, model_options=dict()):
        """pythonfmu's description plus start values, units, ranges (numbers written with
        ``repr``: shortest text that reads back bit for bit) and ``<UnitDefinitions>``; the
        build writes ``<ModelStructure>`` (``fmu.structure``: from the generated functions'
        sparsity)."""
        root = super().to_xml(model_options)
        if self._spec.get("guid"):
            root.set("guid", self._spec["guid"])  # from the FMU's content (fmu.build.content_guid); the shim checks it
        svs = list(root.find("ModelVariables"))
        units = {self._annotate(sv) for sv in svs}
        unit_definitions(root, units - {None})
        return root

    def _annotate(self, sv) -> str | None:
        """Write start, unit, min and max of one ``<ScalarVariable>``; returns its unit."""
        v = self._vars[sv.get("name")]
        element = sv.find("Real") if sv.find("Real") is not None else sv.find("String")
        for key in ("start", "unit", "min", "max"):
            if v.get(key) is not None and (key == "start" or element.tag == "Real"):
                element.set(key, v[key] if isinstance(v[key], str) else repr(float(v[key])))
        return v.get("unit")

    def _scene(self) -> dict:
        """The spec of the scene in use (the primary scene while ``scene`` holds a bad value)."""
        return self._spec["scenes"][self._use("scene")]

    def _value(self, name: str):
        """The value last set (what a getter returns), else the scene's default."""
        return self._settings[name] if name in self._settings else self._default(name)

    def _use(self, name: str):
        """The value in use: the one set, unless it was refused, else the scene's default."""
        return self._settings[name] if name in self._settings and name not in self._errors else self._default(name)

    def _start(self) -> dict:
        """The start in use: the scene's own (its ``x0``, ``defaults``, ``forward_speed``) or,
        with ``initial_state = "periodic"``, its periodic trim (the same entries)."""
        scene = self._scene()
        return scene["periodic"] if self._periodic() and scene.get("periodic") else scene

    def _periodic(self) -> bool:
        """True when ``initial_state = "periodic"`` is in use."""
        return "initial_state" in self._vars and self._use("initial_state") == "periodic"

    def _default(self, name: str):
        """The value of ``name`` when the master did not set it: its XML start, whatever the scene."""
        return self._vars[name]["start"]

    def _own(self, name: str):
        """The value of ``name`` in the scene and start in use by itself, the start of an FMU built for
        that scene alone (rad, rad/s, s, m/s as declared)."""
        scene = self._scene()
        if name == "max_step":
            return 2 * math.pi / abs(scene["omega"]) / scene["steps_per_rev"]
        start = self._start()
        if name == "initial_forward_speed":
            return self._own_speed(start)
        return start["defaults"][name]

    @staticmethod
    def _own_speed(start: dict) -> float:
        """The forward speed (m/s) of a start (the scene's or its periodic trim's): the trim's flight
        speed, the scene's initial speed, 0 without a free fuselage."""
        if not start["forward_speed"]:
            return 0.0
        return float(start["trim"]["speed"]) if "trim" in start else start["forward_speed"]["default"]

    def _set(self, name: str, value, call: str = "set") -> None:
        """Store ``value`` for the input or parameter ``name`` (set, whatever its value),
        check it (a refusal is stored, and logged as ``"<call>: <message>"``) and invalidate
        what depends on it."""
        v = self._vars[name]
        if v["causality"] == "input" and self._unchanged(name, value):
            return  # a master sets every input before each step; most are unchanged
        self._store(name, value)
        try:
            self._check(name, value)
        except BadValue as exc:
            self._p = self._cache = None
            self._errors[name] = str(exc)
            self._report(f"{call}: {exc}")
            return
        self._apply(name, v, call)

    def _unchanged(self, name: str, new) -> bool:
        """True when ``name`` was set to ``new`` already and accepted."""
        return name in self._settings and name not in self._errors and self._settings[name] == new

    def _store(self, name: str, new) -> None:
        """Record the setting ``new`` of ``name`` and clear its refusal."""
        self._settings[name] = new
        self._errors.pop(name, None)

    def _apply(self, name: str, v: dict, call: str) -> None:
        """Make the accepted setting of ``name`` take effect."""
        order = self._scene()["parameter_order"]
        if v["causality"] == "input" and self._p is not None and name in order:
            self._p[order.index(name)] = float(self._use(name))
            self._stepper.set_params(self._p)
            self._cache = None
            return
        self._p = self._cache = None
        if v["causality"] == "input" or v["variability"] == "tunable":
            return
        if self._phase not in ("stepping", "terminated") or name not in self._frozen:
            self._stepper = None
        elif self._use(name) != self._frozen[name]:
            self._errors[name] = (f"parameter {name!r} is fixed: it cannot change after initialisation (set to "
                                  f"{self._use(name)!r}, in use {self._frozen[name]!r}); the FMU refuses to step "
                                  "until it is set back")
            self._report(f"{call}: {self._errors[name]}")

    def _check(self, name: str, value) -> None:
        """Raise BadValue (naming the variable, the value and the unit) unless ``value`` is
        acceptable for ``name`` in the scene in use."""
        v = self._vars[name]
        if v["type"] == "String":
            if value not in v["allowed"]:
                raise BadValue(f"parameter {name!r} = {value!r} is not one of: {', '.join(v['allowed'])}")
            return
        what, unit = f"{v['causality']} {name!r}", v.get("unit") or ""
        if isinstance(value, bool) or not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise BadValue(f"{what} = {value!r} {unit} is not a finite number")
        low, high = self._scene()["ranges"].get(name, (None, None))
        low, high = -math.inf if low is None else low, math.inf if high is None else high
        if not low <= value <= high:
            raise BadValue(f"{what} = {value!r} {unit} is outside its range [{low!r}, {high!r}]")
        if name == "max_step" and value <= 0:
            raise BadValue(f"{what} = {value!r} s must be positive")

    # -- logging -----------------------------------------------------------------------------
    def _report(self, message: str, status: Fmi2Status = Fmi2Status.error) -> str:
        """Log ``message`` through FMI and, unless it is only information, on stderr; never raises."""
        try:
            self.log(message, status)
            if status > Fmi2Status.ok:
                print(f"{self.modelName} ({self.instance_name}) {status.name}: {message}", file=sys.stderr,
                      flush=True)
        except Exception:
            pass
        return message

    # -- FMI life cycle ------------------------------------------------------------------------
    @entry_point("setupExperiment")
    def setup_experiment(self, start_time: float = 0.0, stop_time=None, tolerance=None):
        start = float(start_time or 0.0)
        if not math.isfinite(start):
            raise BadValue(f"startTime = {start!r} s is not finite")
        self._start_time = self._t = start

    @entry_point("enterInitializationMode")
    def enter_initialization_mode(self):
        self._phase = "initialization"

    @entry_point("exitInitializationMode")
    def exit_initialization_mode(self):
        """Initialise; a refused parameter fails it (logged error) and the instance stays in
        initialisation mode, so the master can correct the value and call it again."""
        refused = [m for n, m in self._errors.items() if self._vars[n]["causality"] == "parameter"]
        if refused:
            raise BadValue("; ".join(refused))
        self._prepare()
        self._frozen = {n: self._use(n) for n, v in self._vars.items()
                        if v["causality"] == "parameter" and v["variability"] == "fixed"}
        self._phase = "stepping"
        self._warn_start_values()

    def _warn_start_values(self) -> None:
        """In a scene other than the primary one, warn about each Real input or parameter in use at
        its XML start (the primary scene's value), set or not, that differs from the scene's own."""
        scene, primary = self._use("scene"), self._spec["primary"]
        for name, v in self._vars.items():
            if scene == primary or v["type"] != "Real" or "start" not in v or self._use(name) != v["start"]:
                continue
            own = self._own(name)
            if own != v["start"]:
                unit = v.get("unit") or ""
                self._report(f"fmi2ExitInitializationMode: scene {scene!r} runs with {v['causality']} {name!r} = "
                             f"{v['start']!r} {unit}, its start value (that of scene {primary!r}); scene {scene!r} by "
                             f"itself has {own!r} {unit}: set it to that, or use the FMU built for scene {scene!r} "
                             f"(heli fmu build --scenes {scene})", Fmi2Status.warning)

    @entry_point("terminate")
    def terminate(self):
        self._phase = "terminated"

    def _prepare(self) -> None:
        """Load the scene's evaluator and set the initial state at the start time."""
        if self._periodic() and not self._scene().get("periodic"):
            raise BadValue(f"parameter 'initial_state' = 'periodic': the scene {self._use('scene')!r} has no "
                           "periodic start (it cannot be trimmed)")
        start = self._start()
        x0 = np.array(start["x0"], dtype=float)
        if "initial_forward_speed" in self._vars:
            x0 = self._with_forward_speed(start, x0, float(self._use("initial_forward_speed")))
        self._load(self._scene()["group"], self._use("evaluator"), x0, np.zeros(x0.size))
        self._t = self._start_time

    def _load(self, group: str, evaluator: str, x: np.ndarray, comp: np.ndarray) -> None:
        system = self._system(group, evaluator)
        if x.size != system.info.nx:
            raise BadValue(f"a state of {x.size} entries does not fit scene {self._use('scene')!r} "
                           f"({system.info.nx} states)")
        kind = BoundStepper if isinstance(system, CompiledSystem) and BoundStepper.usable else Stepper
        self._stepper = kind(system, x, comp, self._use("integrator"))
        self._stepper.hinges = _index(self._scene().get("hinge_states", []))
        self._p = self._cache = None

    def _with_forward_speed(self, start: dict, x0: np.ndarray, speed: float) -> np.ndarray:
        """Initial body velocity ``R(q0)^T (speed, 0, 0)`` (m/s): level flight north at the start's attitude
        (``R(q0)^T e_x`` computed at build time); the start's own state at its own speed."""
        fs = start["forward_speed"]
        if fs is None:
            if speed != 0.0:
                how = "" if "initial_forward_speed" in self._settings else " (its start value)"
                raise BadValue(f"parameter 'initial_forward_speed' = {speed!r} m/s{how}: the scene "
                               f"{self._use('scene')!r} has no free fuselage; set it to 0.0")
            return x0
        if speed == self._own_speed(start):
            return x0
        x0 = x0.copy()
        x0[fs["v"]] = speed * np.asarray(fs["direction"])
        return x0

    def _system(self, group: str, evaluator: str):
        key = (group, evaluator)
        if key not in self._systems:
            self._systems[key] = self._open(self._root / group, evaluator)
        return self._systems[key]

    def _open(self, folder: Path, evaluator: str):
        """The evaluator of the model in ``folder``: the compiled library, else the VM."""
        if evaluator == "compiled":
            try:
                return CompiledSystem(folder)
            except OSError as exc:
                self._report(f"the compiled model cannot be loaded on this host ({exc}); "
                             "falling back to the virtual machine (needs casadi)", Fmi2Status.warning)
        return load_vm(folder, ModelInfo.load(folder / "info.json"))

    def _params(self) -> np.ndarray:
        """Parameter vector of the scene's model (inputs included), handed to the stepper;
        also caches ``max_step`` (s)."""
        if self._p is None:
            self._p = np.array([float(self._use(n)) for n in self._scene()["parameter_order"]])
            self._h_max = float(self._use("max_step"))
            self._stepper.set_params(self._p)
        return self._p

    def _computed(self) -> list[float]:
        """Every output and local variable at the current time (cached until a change)."""
        if self._cache is None:
            if self._stepper is None:
                self._prepare()
            self._params()
            self._cache = self._stepper.outputs(self._t)
        return self._cache

    # -- stepping ------------------------------------------------------------------------------
    @entry_point("doStep", False)
    def do_step(self, current_time: float, step_size: float) -> bool:
        """One communication step; False (fmi2Discard, with a logged message) when refused
        or undone, the state then stays at ``current_time``."""
        t, dt = current_time, step_size
        if self._phase != "stepping":
            self._report(f"doStep at t = {t!r} s called while the instance is in {self._phase} "
                         "(call exitInitializationMode first)")
            return False
        problem = self._step_problem(t, dt)
        if problem:  # misuse: an error (a discard would make the master retry a smaller step)
            self._report(f"fmi2DoStep: {problem}")
            return False
        refusal = self._refusal(t, dt)
        if refusal:
            self._report(f"doStep at t = {t!r} s refused: {refusal}", Fmi2Status.discard)
            return False
        return self._advance(t, dt)

    def _refusal(self, t: float, dt: float) -> str | None:
        """Why the step from ``t`` (s) of ``dt`` (s) must not be taken, or None."""
        if self._errors:
            return "; ".join(self._errors.values())
        if self._stepper is None:
            self._prepare()
        self._params()
        limit = self._limits["max_substeps"]
        if not dt / self._h_max * (1 - SUBSTEP_TOLERANCE) <= limit:
            return (f"communicationStepSize = {dt!r} s needs {dt / self._h_max:.4g} sub-steps of max_step = "
                    f"{self._h_max!r} s, more than the limit of {limit} per doStep; use shorter "
                    "communication steps")
        return None

    def _advance(self, t: float, dt: float) -> bool:
        """Integrate ``[t, t + dt]`` (s) in ``n`` equal sub-steps, then check the result."""
        n = max(1, math.ceil(dt / self._h_max * (1 - SUBSTEP_TOLERANCE)))
        before = self._stepper.snapshot()
        status, _ = self._stepper.step(t, dt / n, n)
        if status:
            self._report(self._divergence(t, dt / n, n, status), Fmi2Status.discard)
            return False
        self._t, self._cache = t + dt, None
        problem = self._after_step_problem()
        if problem:
            self._stepper.restore(before)
            self._t, self._cache = t, None
            self._report(f"doStep at t = {t!r} s of {dt!r} s undone: {problem}; max_step = {self._h_max!r} s may "
                         f"be beyond {self._stepper.method}'s stability limit, or the inputs drove the model out of "
                         f"its range; the state stays at t = {t!r} s", Fmi2Status.discard)
            return False
        return True

    def _after_step_problem(self) -> str | None:
        """A non-finite state, a hinge angle beyond ``limits.hinge_angle`` (rad) or a
        non-finite total energy (J) after a step; None when all is well (the fast path:
        two dot products, enough to show all is well; the outputs evaluated here serve the
        next getReal)."""
        x, hinges, limit = self._stepper.x, self._stepper.hinges, self._limits["hinge_angle"]
        angles = x[hinges]
        if not (math.isfinite(x.dot(x)) and angles.dot(angles) <= limit * limit):
            fault = self._state_fault(x, hinges)
            if fault:
                return fault
        energy = self._computed()[self._energy] if self._energy is not None else 0.0
        return None if math.isfinite(energy) else f"total_energy = {energy!r} J is not finite"

    def _state_fault(self, x: np.ndarray, hinges) -> str | None:
        """The first non-finite state, else the first hinge angle beyond the limit (rad)."""
        names, limit = self._stepper.system.info.state_names, self._limits["hinge_angle"]
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            return f"state {names[bad[0]]!r} = {float(x[bad[0]])!r} is not finite"
        beyond = np.arange(x.size)[hinges][np.abs(x[hinges]) > limit]
        if beyond.size:
            i = int(beyond[0])
            return f"hinge angle {names[i]!r} = {float(x[i])!r} rad is beyond ±{limit!r} rad"
        return None

    def _step_problem(self, t: float, dt: float) -> str | None:
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            return f"communication step size communicationStepSize = {dt!r} s must be positive and finite"
        if not math.isfinite(t):
            return f"currentCommunicationPoint = {t!r} s is not finite"
        if abs(t - self._t) > TIME_TOLERANCE * max(1.0, abs(self._t)):
            return (f"currentCommunicationPoint = {t!r} s does not match the FMU's time {self._t!r} s "
                    "(restore a saved FMU state to go back in time)")
        return None

    def _last_finite(self, t: float, h: float, n: int) -> tuple[np.ndarray, int]:
        """Redo the failed step (from ``t``, ``n`` sub-steps of ``h`` s) recording at most
        about ``2 * DIAGNOSTIC_ROWS`` rows: (last finite state, sub-steps before it)."""
        st = self._stepper
        x, k = st.x.copy(), 0
        for every in sorted({max(1, -(-n // DIAGNOSTIC_ROWS)), 1}, reverse=True):
            count = n - k if every > 1 else min(n - k, 2 * DIAGNOSTIC_ROWS)
            rows, _, done = st.system._run(st.method, x, t + k * h, h, 0, count, every, st.p, st.comp.copy())
            whole = done // every
            if whole:
                x, k = rows[whole - 1].copy(), k + whole * every
        return x, k

    def _divergence(self, t, h, n, status) -> str:
        """Message for a failed step: where it failed and which state became non-finite."""
        st = self._stepper
        x, done = self._last_finite(t, h, n)
        tk = t + done * h
        where = f"at t = {tk!r} s (sub-step {done + 1} of {n}, h = {h!r} s)"
        if status != 1:
            return f"doStep at t = {t!r} s: the model evaluation failed {where}; the step was discarded"
        loop = closure_failure(st, x, tk, h)
        if loop:
            return (f"doStep at t = {t!r} s: {loop} ({where.partition('(')[2]}; the step was discarded (the state "
                    f"stays at t = {t!r} s)")
        bad = x + st.system._eval(f"incr_{st.method}", x, tk, h, st.p)[0]
        i = int(np.flatnonzero(~np.isfinite(bad))[0]) if not np.all(np.isfinite(bad)) else 0
        return (f"doStep at t = {t!r} s: the simulation diverged {where}: state "
                f"{st.system.info.state_names[i]!r} = {float(bad[i])!r}; max_step = {self._use('max_step')!r} s "
                f"may be beyond {st.method}'s stability limit, or the inputs drove the model out of its range; "
                f"the step was discarded (the state stays at t = {t!r} s)")

    # -- FMU state -----------------------------------------------------------------------------
    @entry_point("getFMUstate", {"format": "invalid", "error": "fmi2GetFMUstate failed"})
    def _get_fmu_state(self) -> dict:
        st = self._stepper
        return {"format": STATE_FORMAT, "phase": self._phase, "start_time": self._start_time, "t": self._t,
                "x": None if st is None else st.x.tolist(), "comp": None if st is None else st.comp.tolist(),
                "settings": dict(self._settings), "errors": dict(self._errors), "frozen": dict(self._frozen)}

    @entry_point("setFMUstate")
    def _set_fmu_state(self, state: dict) -> None:
        """Restore ``state``; a malformed one is refused (logged error) and nothing changes."""
        problem = state_problem(state)
        if problem:
            raise BadValue(f"not a state of this FMU: {problem}")
        before = dict(self.__dict__)
        try:
            self._restore(state)
        except Exception:
            self.__dict__.update(before)
            raise

    def _restore(self, state: dict) -> None:
        """Apply a checked ``state`` (the caller undoes everything if this raises)."""
        unknown = sorted((set(state["settings"]) | set(state["errors"])) - set(self._vars))
        if unknown or state["phase"] not in ("instantiated", "initialization", "stepping", "terminated"):
            raise BadValue(f"not a state of this FMU: unknown variables {unknown} or phase {state['phase']!r}")
        self._settings, self._errors = dict(state["settings"]), dict(state["errors"])
        for name in set(self._settings) - set(self._errors):
            self._check(name, self._settings[name])
        self._frozen = dict(state["frozen"])
        self._phase, self._start_time = state["phase"], float(state["start_time"])
        self._stepper = None
        if state["x"] is not None:
            x, comp = np.array(state["x"], dtype=float), np.array(state["comp"], dtype=float)
            self._load(self._scene()["group"], self._use("evaluator"), x, comp)
        self._t, self._p, self._cache = float(state["t"]), None, None

    _fmu_state_to_bytes = staticmethod(to_bytes)
    _fmu_state_from_bytes = staticmethod(from_bytes)


# -- pythonfmu re-runs this file ----------------------------------------------------------------

def _settle_rerun(scope: dict, module: dict) -> None:
    """Undo what pythonfmu 0.7.0 does to this module at every instantiate.

    Its ``findClass`` runs this file's source again with the module's dict as globals and
    a fresh dict ``scope`` as locals, keeps a list of the MRO of every class it finds in
    ``scope`` (so each run's classes and all their functions would stay alive: about
    150 kB per instantiate), and releases one reference to the module's dict that it never
    took. In such a run: hold that one reference (8 bytes per instantiate), and leave only
    the module's own slave class in ``scope`` so that this run's classes are collected."""
    if scope is module:
        return
    _PINNED.append(module)
    for name in [n for n, v in scope.items() if isinstance(v, type)]:
        del scope[name]
    scope["HeliRotorSlave"] = module["HeliRotorSlave"]


_PINNED: list = []  # the module's dict, once per re-run (pythonfmu releases one reference each time)
_settle_rerun(locals(), globals())

