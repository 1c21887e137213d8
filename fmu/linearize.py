"""A, B, C, D of any FMU that provides directional derivatives, at its current point.

    x' = A dx + B du,   y = C dx + D du

``A = d der(x)/dx``, ``B = d der(x)/du``, ``C = dy/dx``, ``D = dy/du`` are read column by column
with ``fmiXGetDirectionalDerivative`` (one call per state and per input, every unknown at once)
from an FMI 2.0 or 3.0 FMU, through fmpy. Model exchange gives all four; an FMU with
co-simulation only gives ``D`` (``A``, ``B``, ``C`` empty: it has no continuous states to
linearise about). Array variables (FMI 3.0) count element by element (``blade.flap[2]``).

The point: the state after initialisation with ``start_values`` (names to values, as fmpy
takes them), at ``time`` (default the start time), or the continuous states ``states`` (in the
FMU's order) set afterwards.
"""
from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


@dataclass
class Linearization:
    """The matrices (``A`` (nx, nx), ``B`` (nx, nu), ``C`` (ny, nx), ``D`` (ny, nu); SI units of
    the FMU's variables) with the names of their rows and columns, the point (``time`` s,
    continuous states ``x``, inputs ``u``) and how they were read (FMI version, interface,
    number of directional-derivative calls)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: list[str]
    inputs: list[str]
    outputs: list[str]
    time: float
    x: np.ndarray
    u: np.ndarray
    fmi_version: str
    interface: str
    calls: int = 0
    notes: list[str] = field(default_factory=list)


def _size(v) -> int:
    n = 1
    for d in getattr(v, "dimensions", None) or []:
        if d.start is None:
            raise ValueError(f"variable {v.name!r} has a dimension set by another variable: not supported")
        n *= int(d.start)
    return n


def _elements(v) -> list[str]:
    n = _size(v)
    return [v.name] if n == 1 and not getattr(v, "dimensions", None) else [f"{v.name}[{k + 1}]" for k in range(n)]


def _pick(variables: list, names, what: str) -> list:
    if names is None:
        return variables
    by_name = {v.name: v for v in variables}
    bad = [n for n in names if n not in by_name]
    if bad:
        raise ValueError(f"{what} {bad[0]!r} is not one of the FMU's {what}s: {', '.join(by_name) or 'none'}")
    return [by_name[n] for n in names]


class _Session:
    """One instance of the FMU, initialised, in continuous-time mode (model exchange)."""

    def __init__(self, unzipdir: str, md, interface: str):
        from fmpy import instantiate_fmu

        self.md, self.v3, self.messages = md, md.fmiVersion.startswith("3"), []
        self.fmu = instantiate_fmu(unzipdir, md, fmi_type=interface, logger=self._log)
        self.me, self.calls, self.time = interface == "ModelExchange", 0, 0.0

    def initialise(self, start_values: dict, time: float | None) -> None:
        from fmpy.simulation import apply_start_values

        ex = self.md.defaultExperiment
        self.time = float(time if time is not None else (ex.startTime if ex and ex.startTime else 0.0))
        if self.v3:
            self.fmu.enterInitializationMode(startTime=self.time)
        else:
            self.fmu.setupExperiment(startTime=self.time)
            self.fmu.enterInitializationMode()
        apply_start_values(self.fmu, self.md, dict(start_values))
        self.fmu.exitInitializationMode()
        if self.me:
            (self.fmu.updateDiscreteStates if self.v3 else self.fmu.newDiscreteStates)()
            self.fmu.enterContinuousTimeMode()

    def _log(self, *args) -> None:
        message = args[-1]
        self.messages.append(message.decode(errors="replace") if isinstance(message, bytes) else str(message))

    def states(self, nx: int, x=None) -> np.ndarray:
        import ctypes

        buf = (ctypes.c_double * max(nx, 1))()
        if x is not None:
            buf[:nx] = [float(v) for v in x]
            self.fmu.setContinuousStates(buf, nx)
        self.fmu.getContinuousStates(buf, nx)
        return np.array(buf[:nx])

    def column(self, unknowns: list, n_unknown: int, known, element: int, n_known: int) -> np.ndarray:
        """d unknowns / d (element of known): one directional derivative."""
        self.calls += 1
        if self.v3:
            seed = [0.0] * n_known
            seed[element] = 1.0
            return np.array(self.fmu.getDirectionalDerivative([u.valueReference for u in unknowns],
                                                               [known.valueReference], seed, n_unknown))
        return np.array(self.fmu.getDirectionalDerivative([u.valueReference for u in unknowns],
                                                           [known.valueReference], [1.0]))

    def reals(self, variables: list) -> np.ndarray:
        vrs = [v.valueReference for v in variables]
        if self.v3:
            return np.array(self.fmu.getFloat64(vrs, sum(_size(v) for v in variables)))
        return np.array(self.fmu.getReal(vrs))

    def close(self) -> None:
        try:
            self.fmu.terminate()
        except Exception:  # noqa: BLE001 (an instance that failed to initialise: freed all the same)
            pass
        self.fmu.freeInstance()


def _interface(fmu, md, interface: str | None) -> str:
    kinds = [k for k, el in (("ModelExchange", md.modelExchange), ("CoSimulation", md.coSimulation)) if el]
    if interface is None:
        interface = kinds[0] if kinds else ""
    if interface not in kinds:
        raise ValueError(f"the FMU has no {interface or 'interface'}: it offers {', '.join(kinds) or 'none'}")
    flag = "providesDirectionalDerivatives" if md.fmiVersion.startswith("3") else "providesDirectionalDerivative"
    if _attribute(fmu, interface, flag) not in ("true", "1"):  # read from the XML: fmpy drops FMI 3.0's
        raise ValueError(f"the FMU's {interface} does not provide directional derivatives ({flag} is not true): "
                         "it cannot be linearised exactly")
    return interface


def _attribute(fmu, element: str, name: str) -> str | None:
    import zipfile
    from xml.etree import ElementTree as ET

    path = Path(fmu)
    xml = (path / "modelDescription.xml").read_bytes() if path.is_dir() else \
        zipfile.ZipFile(path).read("modelDescription.xml")
    el = ET.fromstring(xml).find(element)
    return None if el is None else el.get(name)


def linearize(fmu: str | Path, start_values: dict | None = None, time: float | None = None, states=None,
              inputs: list[str] | None = None, outputs: list[str] | None = None,
              interface: str | None = None) -> Linearization:
    """A, B, C, D of ``fmu`` (FMI 2.0 or 3.0, model exchange unless ``interface`` says
    ``"CoSimulation"``) by its directional derivatives; ``inputs``/``outputs`` name a subset
    (default all, in the FMU's order). Raises ValueError naming what is missing when the FMU
    provides no directional derivatives or has no such variable."""
    from fmpy import extract, read_model_description

    md = read_model_description(str(fmu))
    interface = _interface(fmu, md, interface)
    u_vars = _pick([v for v in md.modelVariables if v.causality == "input" and v.type in ("Real", "Float64")],
                   inputs, "input")
    y_vars = _pick([v for v in md.modelVariables if v.causality == "output" and v.type in ("Real", "Float64")],
                   outputs, "output")
    me = interface == "ModelExchange"
    ders = [d.variable for d in md.derivatives] if me else []
    x_vars = [d.derivative for d in ders]
    settable = {v.name for v in md.modelVariables if v.causality in ("parameter", "input")}
    unknown = [n for n in start_values or {} if n not in settable]
    if unknown:
        raise ValueError(f"{unknown[0]!r} is not a parameter or input of the FMU; those are: {', '.join(sorted(settable))}")
    unzipdir = extract(str(fmu), unzipdir=tempfile.mkdtemp(prefix="heli-linearize-"))
    s = None
    try:
        s = _Session(unzipdir, md, interface)
        s.initialise(start_values or {}, time)
        return _matrices(s, md, ders, x_vars, u_vars, y_vars, states, interface)
    except Exception as exc:
        from fmpy.fmi1 import FMICallException

        if not isinstance(exc, FMICallException):
            raise
        said = s.messages[-1] if s and s.messages else "no message"
        raise ValueError(f"the FMU refused: {exc} ({said})") from None
    finally:
        if s is not None:
            s.close()
        shutil.rmtree(unzipdir, ignore_errors=True)


def _matrices(s: _Session, md, ders, x_vars, u_vars, y_vars, states, interface) -> Linearization:
    nx = sum(_size(v) for v in ders)
    if states is not None and len(states) != nx:
        raise ValueError(f"states has {len(states)} values, the FMU has {nx} continuous states")
    x = s.states(nx, states) if nx else np.zeros(0)
    unknowns = [*ders, *y_vars]
    n_unknown = sum(_size(v) for v in unknowns)
    columns = []
    for known in [*x_vars, *u_vars]:
        for k in range(_size(known)):
            columns.append(s.column(unknowns, n_unknown, known, k, _size(known)))
    full = np.array(columns).T.reshape(n_unknown, len(columns))
    n_x = sum(_size(v) for v in x_vars)
    rows = lambda vs: [e for v in vs for e in _elements(v)]  # noqa: E731
    return Linearization(A=full[:nx, :n_x], B=full[:nx, n_x:], C=full[nx:, :n_x], D=full[nx:, n_x:],
                         states=rows(x_vars), inputs=rows(u_vars), outputs=rows(y_vars), time=s.time, x=x,
                         u=s.reals(u_vars) if u_vars else np.zeros(0),
                         fmi_version=md.fmiVersion, interface=interface, calls=s.calls)
