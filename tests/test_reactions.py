"""Joint reaction loads from the backward Newton–Euler pass: every body's force and moment
balance, zero at a free joint, equal to Pinocchio's inverse dynamics (``rnea``), a driven
hinge's drive torque, and clear errors."""
import numpy as np
import pytest

import mbs
from mbs import BodyTorque, DrivenHinge, Fixed, Hinge, Model, PointForce, Serial, scenes
from mbs.loads.outputs import COMPONENTS, add_hinge_torque, add_joint_loads
from trees import random_chain, random_state, random_tree

BALANCE = 1e-10  # relative, the bound (measured 1e-15 .. 1e-14)


def loaded_tree(seed: int, free_base: bool) -> Model:
    """A random tree with springs, dampers, gravity, and constant forces and torques on some
    bodies; every joint's loads declared as outputs ``<body>.joint.*``."""
    m = random_tree(seed, n_bodies=12, free_base=free_base)
    rng = np.random.default_rng(seed)
    for k, name in enumerate(list(m.bodies)[::3]):
        m.add_force(PointForce(f"push {name}", name, tuple(rng.normal(size=3) * 20), rng.normal(size=3) * 0.4, "world"))
        m.add_force(BodyTorque(f"twist {name}", name, tuple(rng.normal(size=3) * 5)))
    for name in list(m.bodies):
        add_joint_loads(m, name)
    return m


def joint_loads(system, x, t=0.0) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per body with outputs ``<body>.joint.*``: (force, moment about the joint), body axes."""
    y = dict(zip(system.info.output_names, system.outputs(x, t)))
    return {b: (np.array([y[f"{b}.joint.{c}"] for c in COMPONENTS[:3]]),
                np.array([y[f"{b}.joint.{c}"] for c in COMPONENTS[3:]]))
            for b in system.info.body_names if f"{b}.joint.force_x" in y}


def applied(model: Model, body: str, rot: np.ndarray, com: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The constant applied loads of ``body``: force (world) and moment about its centre of
    mass (body axes)."""
    f, n = np.zeros(3), np.zeros(3)
    for e in model.forces:
        if isinstance(e, PointForce) and e.body == body:
            f += np.asarray(e.force, float)
            n += np.cross(e.point - com, rot.T @ np.asarray(e.force, float))
        if isinstance(e, BodyTorque) and e.body == body:
            n += np.asarray(e.torque, float)
    return f, n


def balance(model: Model, system, x) -> float:
    """Largest relative miss of Newton's and Euler's equations over the bodies, each body's
    acceleration from ``V' = J_u u' + H`` (numpy, the composite path's ``u'``), its loads from
    its own and its children's joint reactions, gravity and the applied loads."""
    info, nq = system.info, system.info.nq
    V, ju, hh = system.kinematics(x)
    vdot = ju @ system.rhs(x)[nq:nq + info.nv] + hh
    pos, rot = system.poses(x)
    loads, worst = joint_loads(system, x), 0.0
    for i, b in enumerate(info.bodies):
        name, m, com, J = b["name"], b["mass"], np.array(b["com"]), np.array(b["inertia"])
        cg = pos[i] + rot[i] @ com
        f, n = rot[i] @ loads[name][0], rot[i] @ (loads[name][1] - np.cross(com, loads[name][0]))
        for k, c in enumerate(info.bodies):
            if c["parent"] == name:
                fc = rot[k] @ loads[c["name"]][0]
                f, n = f - fc, n - rot[k] @ loads[c["name"]][1] - np.cross(pos[k] - cg, fc)
        fa, na = applied(model, name, rot[i], com)
        w, wd = V[6 * i + 3:6 * i + 6], vdot[6 * i + 3:6 * i + 6]
        newton = m * vdot[6 * i:6 * i + 3] - (f + m * np.array(info.gravity) + fa)
        euler = J @ wd + np.cross(w, J @ w) - (rot[i].T @ n + na)
        scale = max(np.abs(m * vdot[6 * i:6 * i + 3]).max(), m * 9.81, np.abs(f).max(), np.abs(n).max(), 1.0)
        worst = max(worst, np.abs(newton).max() / scale, np.abs(euler).max() / scale)
    return worst


@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_every_body_balances_its_joint_loads_applied_loads_and_inertia(seed, free_base):
    model = loaded_tree(seed, free_base)
    system = mbs.build(model, "vm")
    for k in range(2):
        assert balance(model, system, random_state(system, 10 * seed + k)) <= BALANCE


def test_the_free_joint_carries_nothing():
    model = loaded_tree(4, free_base=True)
    system = mbs.build(model, "vm")
    weight = sum(b.mass for b in model.bodies.values()) * 9.81
    for k in range(3):
        force, moment = joint_loads(system, random_state(system, k))["b0"]
        assert np.abs(force).max() <= 1e-12 * weight and np.abs(moment).max() <= 1e-12 * weight


def test_the_bo105s_free_fuselage_joint_carries_nothing():
    """forward-flight at its start: aerodynamics on every blade, both rotors driven, the
    fuselage free: the whole chain of hub and blade loads leaves nothing for the free joint."""
    model = scenes.get("forward-flight").model()
    add_joint_loads(model, "fuselage")
    system = mbs.build(model, "vm")
    force, moment = joint_loads(system, system.x0(), 0.013)["fuselage"]
    weight = 2200 * 9.80665
    assert np.abs(force).max() <= 1e-11 * weight and np.abs(moment).max() <= 1e-11 * weight


# -- against Pinocchio's inverse dynamics ------------------------------------------------------

def pinocchio_joint_loads(model: Model, system, x) -> dict[str, np.ndarray]:
    """Per body: Pinocchio's ``rnea`` force transmitted by the body's (last) joint, local axes
    (force, moment), at our ``u'``."""
    pin = pytest.importorskip("pinocchio")
    from mbs.bench.pinocchio_ref import to_pinocchio

    pm, conv = to_pinocchio(model)
    data, nq, nv = pm.createData(), system.info.nq, system.info.nv
    pin.rnea(pm, data, conv(x[:nq]), x[nq:nq + nv], system.rhs(x)[nq:nq + nv])
    out = {}
    for b in model.order():
        joint = max(k for k, n in enumerate(pm.names) if n.split(".")[0] == b.name)
        out[b.name] = np.r_[data.f[joint].linear, data.f[joint].angular]
    return out


def assert_matches_pinocchio(model: Model, path: str, seeds) -> None:
    for b in list(model.bodies):
        add_joint_loads(model, b)
    system = mbs.build(model, "vm", path=path)
    for seed in seeds:
        x = random_state(system, seed)
        theirs, ours = pinocchio_joint_loads(model, system, x), joint_loads(system, x)
        scale = max(np.abs(v).max() for v in theirs.values())
        for name, ref in theirs.items():
            assert np.abs(np.r_[ours[name]] - ref).max() <= 1e-10 * scale, name


@pytest.mark.parametrize("path", ["composite", "articulated"])
@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_joint_loads_equal_pinocchios_rnea(seed, free_base, path):
    pytest.importorskip("pinocchio")
    assert_matches_pinocchio(random_tree(seed, n_bodies=12, free_base=free_base), path, [seed, seed + 50])


@pytest.mark.parametrize("path", ["composite", "articulated"])
def test_joint_loads_of_a_deep_chain_equal_pinocchios_rnea(path):
    pytest.importorskip("pinocchio")
    assert_matches_pinocchio(random_chain(40, 40, free_base=True), path, [7])


# -- hinge torques ---------------------------------------------------------------------------------

def test_a_driven_hinge_reports_its_drive_torque():
    """A hub spun up at α = 3 rad/s² carrying a blade fixed at an offset, with a torque of
    -40 N m about the shaft on the blade: the drive torque is ``J α + 40`` (J about the shaft)."""
    alpha, omega0, tau, mass, offset = 3.0, 20.0, 40.0, 12.0, 1.3
    m = Model("spin-up", gravity=(0, 0, -9.81))
    m.add_body("hub", "world", DrivenHinge((0, 0, 1), lambda t, p: omega0 * t + 0.5 * alpha * t**2, name="azimuth"),
               mass=30.0, inertia=np.diag([2.0, 2.0, 3.0]))
    inertia = np.diag([0.5, 4.0, 4.2])
    m.add_body("blade", "hub", Fixed(), mass=mass, com=(offset, 0, 0), inertia=inertia)
    m.add_force(BodyTorque("drag", "blade", (0.0, 0.0, -tau)))
    add_hinge_torque(m, "hub", "azimuth", "drive", "drive torque")
    system = mbs.build(m, "vm")
    for t in (0.0, 0.7):
        drive = system.outputs(system.x0(), t)[0]
        assert drive == pytest.approx((3.0 + inertia[2, 2] + mass * offset**2) * alpha + tau, rel=1e-12)


def test_a_spring_hinge_carries_its_spring_and_damper_torque():
    """About a hinge's axis inside a serial joint the reaction is the generalized force of its
    spring and damper (the constraint carries nothing there)."""
    k, c, rest = 300.0, 7.0, 0.1
    m = Model("hinges", gravity=(0, 0, 9.81))
    joint = Serial(Hinge((0, 1, 0), name="flap", stiffness=k, damping=c, rest_angle=rest),
                   Fixed(at=(0.2, 0, 0)), Hinge((0, 0, 1), name="lag"))
    m.add_body("blade", "world", joint, mass=3.0, com=(1.0, 0.1, 0), inertia=np.diag([0.1, 1.0, 1.0]))
    add_hinge_torque(m, "blade", "flap", "flap.torque", "flap hinge torque")
    add_hinge_torque(m, "blade", "lag", "lag.torque", "lag hinge torque")
    system = mbs.build(m, "vm")
    x = system.x0(**{"blade.flap": 0.4, "blade.lag": -0.3, "blade.flap_rate": 2.0, "blade.lag_rate": 1.5})
    flap, lag = system.outputs(x)
    assert flap == pytest.approx(-k * (0.4 - rest) - c * 2.0, rel=1e-12) and abs(lag) <= 1e-12 * abs(flap)


# -- errors ------------------------------------------------------------------------------------------

def test_bad_declarations_name_the_bad_value():
    m = random_tree(1, n_bodies=3)
    with pytest.raises(ValueError, match="joint loads of unknown body 'rotor'"):
        add_joint_loads(m, "rotor")
    with pytest.raises(ValueError, match="unknown frame 'hub'"):
        add_joint_loads(m, "b1", frame="hub")
    with pytest.raises(ValueError, match="on = 'both'"):
        add_joint_loads(m, "b1", on="both")
    with pytest.raises(ValueError, match="no hinge called 'pitch'; its hinges: angle"):
        add_hinge_torque(m, "b1", "pitch", "x", "")
