"""Plain-data description of a built model (JSON), so compiled code runs without CasADi."""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np


class StateSizes:
    """Sizes and names of the state ``x = (s, u, z)`` from ``q_names``, ``v_names``, ``z_names``."""

    q_names: list[str]
    v_names: list[str]
    z_names: list[str]

    @property
    def nq(self) -> int:
        return len(self.q_names)

    @property
    def nv(self) -> int:
        return len(self.v_names)

    @property
    def nz(self) -> int:
        return len(self.z_names)

    @property
    def nx(self) -> int:
        return self.nq + self.nv + self.nz

    @property
    def state_names(self) -> list[str]:
        return self.q_names + self.v_names + self.z_names


@dataclass
class ModelInfo(StateSizes):
    """Names, sizes, defaults and body data of a model; everything a run-time needs."""

    name: str
    q_names: list[str]
    v_names: list[str]
    parameters: list[dict]
    bodies: list[dict]
    x0: list[float]
    gravity: list[float]
    methods: dict[str, int] = field(default_factory=dict)  # fixed-step method -> rhs calls per step
    outputs: list[dict] = field(default_factory=list)
    z_names: list[str] = field(default_factory=list)
    extra: dict = field(default_factory=dict)

    @property
    def param_names(self) -> list[str]:
        return [p["name"] for p in self.parameters]

    @property
    def output_names(self) -> list[str]:
        return [o["name"] for o in self.outputs]

    @property
    def body_names(self) -> list[str]:
        return [b["name"] for b in self.bodies]

    def to_json(self) -> str:
        return json.dumps(asdict(self), indent=1)

    @classmethod
    def from_json(cls, text: str) -> "ModelInfo":
        return cls(**json.loads(text))

    @classmethod
    def load(cls, path: Path) -> "ModelInfo":
        return cls.from_json(Path(path).read_text())


def info_of(symbolic, methods: dict[str, int]) -> ModelInfo:
    """Describe ``symbolic`` (a :class:`mbs.dynamics.Symbolic`)."""
    model, lay = symbolic.model, symbolic.layout
    states = set(lay.q_names) | set(lay.v_names)  # a dependent coordinate is no state (mbs.dynamics._dependent)
    bodies = [dict(name=b.name, parent=b.parent, joint=type(b.joint).__name__, mass=b.mass,
                   com=b.com.tolist(), inertia=b.inertia.tolist(), at=b.at.tolist(),
                   frame=b.frame.tolist(), shape=b.shape,
                   q_names=[f"{b.name}.{n}" for n in b.joint.q_names if f"{b.name}.{n}" in states],
                   v_names=[f"{b.name}.{n}" for n in b.joint.v_names if f"{b.name}.{n}" in states])
              for b in lay.bodies]
    params = [dict(name=p.name, default=p.default, unit=p.unit, description=p.description,
                   control=p.control, low=p.low, high=p.high) for p in model.parameters.values()]
    outputs = [dict(name=o.name, unit=o.unit, description=o.description) for o in model.outputs.values()]
    return ModelInfo(model.name, lay.q_names, lay.v_names, params, bodies,
                     initial_state(symbolic).tolist(), model.gravity.tolist(), methods, outputs,
                     lay.z_names, {"dynamics": symbolic.path, "operations": dict(symbolic.operations)})


def initial_state(symbolic) -> np.ndarray:
    """Default state: joint defaults (unit quaternions, zero angles) plus ``model.initial``."""
    lay, model = symbolic.layout, symbolic.model
    full = getattr(lay, "full", lay)  # a model with dependent coordinates: its tree's layout
    s = np.concatenate([b.joint.q_default() for b in full.bodies] + [np.zeros(0)])
    z = np.array([model.states[n].initial for n in full.z_names])
    x = np.concatenate([s, np.zeros(full.nv), z])
    names = full.q_names + full.v_names + full.z_names
    dependent = set(getattr(model, "dependent", {}))
    for name, value in model.initial.items():
        if name not in names:
            raise ValueError(f"initial value for unknown coordinate {name!r}")
        if name in dependent or name.removesuffix("_rate") in dependent:
            raise ValueError(f"initial value for {name!r}, a dependent coordinate (a function of the others)")
        x[names.index(name)] = value
    return x[[names.index(n) for n in lay.state_names]] if full is not lay else x
