"""The loads outputs of a helicopter tree built as :mod:`mbs.models.helicopter` builds it.

Bodies: ``main_hub`` (on the airframe or the world) with blades ``blade<k>`` (an elastic
blade's segments ``blade<k>_<j>``), ``tail_hub`` with ``seesaw`` and tail blades. Outputs
(forces N, moments N m, power W):

* ``blade<k>.root.force_x`` … ``moment_z``: the load the hub passes to the blade at its
  root joint, in blade axes (x along the span, y to the leading edge, z up at zero pitch;
  for a rotor turning against its thrust axis, a clockwise main rotor, the components are
  those of its mirror image, so that every sign below holds for either sense of rotation):
  ``force_x`` the centrifugal pull, with a minus sign (the hub pulls the blade in),
  ``moment_y`` the flap bending moment (positive when it bends the tip up; ``k β`` on a flap
  spring), ``moment_z`` the lag bending moment (positive when it bends the blade back against
  the rotation, ``k ζ`` on a lag spring), ``moment_x`` the torsion moment about the span
  axis (nose up); with a pitch bearing,
  ``blade<k>.root.pitch_torque``: its drive torque about the feathering axis (nose up), what
  a pitch link carries times its arm;
* on elastic blades, ``blade<k>.station<j>.*``: the same at segment ``j``'s joints (j >= 2);
  on modal blades the three moments at the 8-segment blade's joint radii, from the curvature;
* ``main_rotor.hub.*``, ``tail_rotor.hub.*``: what the rotor exerts on the airframe at its
  hub, in the airframe's body axes (world axes for a hub on the world);
* with driven rotors, ``<rotor>.shaft_torque`` (the drive's torque on the rotor) and
  ``<rotor>.shaft_power`` (times the rotor speed), and, when the rotors sit on an airframe
  (free or clamped), ``engine.power`` (:class:`mbs.loads.engine.Engine`).
"""
from __future__ import annotations

from mbs.loads.engine import Engine
from mbs.loads.outputs import COMPONENTS, add_hinge_torque, add_joint_loads
from mbs.tree import WORLD, Model

ROTORS = {"main_rotor": ("main_hub", 1.0), "tail_rotor": ("tail_hub", None)}
"""Rotor -> (hub body, speed per ``omega``; None: the data's tail-rotor gear ratio)."""


def add_load_outputs(m: Model, d, cfg) -> list[str]:
    """Declare the loads outputs of the model ``m`` built from the aircraft data ``d`` by the
    configuration ``cfg`` (:class:`mbs.models.helicopter.Config`); returns their names."""
    names = _blade_loads(m, d, cfg)
    for rotor, (hub, _) in ROTORS.items():
        if hub in m.bodies:
            parent = m.bodies[hub].parent
            names += add_joint_loads(m, hub, f"{rotor}.hub", frame=parent, on="parent",
                                     what=f"{rotor.replace('_', '-')} hub load on the "
                                     f"{'airframe' if parent != WORLD else 'ground'}")
    if cfg.rotors == "driven" and "omega" in m.parameters:
        names += _power(m, d)
    return names


def _blade_loads(m: Model, d, cfg) -> list[str]:
    from mbs.models.helicopter.frames import main_sense

    s = main_sense(d)
    signs = (1, s, 1, s, 1, s)  # y towards the leading edge, torsion nose up, lag moment as for a CCW rotor
    names = []
    for k in range(1, cfg.blade_count(d["main_rotor"]["n_blades"]) + 1):
        blade = f"blade{k}"
        names += add_joint_loads(m, blade, f"{blade}.root", what=f"blade {k} root load (hub on blade)", signs=signs)
        for j in range(2, cfg.blade_segments + 1):
            names += add_joint_loads(m, f"{blade}_{j}", f"{blade}.station{j}", signs=signs,
                                     what=f"blade {k} load at the joint of segment {j} (inboard on outboard)")
        if cfg.blade_modes:
            names += _modal_stations(m, d, blade, k, signs)
        if cfg.pitch_hinge and cfg.rotors == "driven":
            names.append(add_hinge_torque(m, blade, "pitch", f"{blade}.root.pitch_torque",
                                          f"blade {k} pitch-bearing drive torque about the feathering axis, nose up"))
    return names


def _modal_stations(m: Model, d, blade: str, k: int, signs) -> list[str]:
    """A modal blade's torsion, flap and lag bending moments at the 8-segment blade's joint
    radii: the section stiffnesses times the curvature of the bent blade (the modal blade's
    strain, as a segment joint's moment is its spring's)."""
    import casadi as ca

    from mbs.flexible.joints import Modal
    from mbs.models.modal_blade import station_radii

    beam = next(j for j in getattr(m.bodies[blade].joint, "parts", ()) if isinstance(j, Modal)).beam
    stiff = ca.DM([beam.blade.torsion_stiffness, beam.blade.flap_stiffness, beam.blade.lag_stiffness])
    names = []
    for j, radius in station_radii(d).items():
        x = radius - beam.blade.root
        for c, comp in enumerate(COMPONENTS[3:]):
            name = f"{blade}.station{j}.{comp}"
            m.add_output(name, lambda s, x=x, c=c: -signs[3 + c] * stiff[c] * beam.curvature(
                ca.vertcat(*[s.q(f"{blade}.{n}") for n in beam.names]), x)[c], "N m",
                f"blade {k} {('torsion', 'flap bending', 'lag bending')[c]} moment at {radius:.3f} m from the rotor "
                "axis (section stiffness times the bent blade's curvature), section axes")
            names.append(name)
    return names


def _power(m: Model, d) -> list[str]:
    """Shaft torque and power of each driven rotor, and the engine power."""
    from mbs.models.helicopter.frames import main_sense, tail_sense

    names, powers = [], []
    for rotor, (hub, ratio) in ROTORS.items():
        if hub not in m.bodies:
            continue
        ratio = d["tail_rotor"]["gear_ratio"] if ratio is None else ratio
        what = rotor.replace("_", "-")
        sense = main_sense(d) if rotor == "main_rotor" else tail_sense(d)
        torque = add_hinge_torque(m, hub, "azimuth", f"{rotor}.shaft_torque",
                                  f"{what} shaft torque: the drive's torque on the rotor (a joint reaction), "
                                  "positive in the sense of rotation", sign=sense)
        power = (lambda s, name=torque, r=ratio: _output(m, s, name) * r * s.p["omega"])
        m.add_output(f"{rotor}.shaft_power", power, "W", f"{what} shaft power: shaft torque times rotor speed")
        names += [torque, f"{rotor}.shaft_power"]
        powers.append(power)
    if m.bodies["main_hub"].parent == WORLD:  # a rotor on a test stand: no engine
        return names
    engine = Engine.of(d)
    total = lambda s: engine.power(*[p(s) for p in powers])  # noqa: E731
    m.add_output("engine.power", total, "W",
                 f"engine power: the rotors' shaft power over the transmission efficiency {engine.efficiency:g}, "
                 f"plus {engine.accessory_power:g} W accessory power")
    m.add_output("engine.torque", lambda s: total(s) / s.p["omega"], "N m",
                 "the engines' torque referred to the main-rotor shaft: engine power over the rotor speed")
    out = ["engine.power", "engine.torque"]
    reference, count = d["engine"].get("torque_reference", 0.0), d["engine"].get("count", 1)
    if reference:
        m.add_output("engine.torque_fraction", lambda s: total(s) / s.p["omega"] / (count * reference), "1",
                     f"each engine's torque over the gauge's 100 % ({reference:g} N m referred to the main-rotor "
                     f"shaft), the {count} engine(s) sharing the load")
        out.append("engine.torque_fraction")
    return names + out


def _output(m: Model, state, name: str):
    return m.outputs[name].fn(state)
