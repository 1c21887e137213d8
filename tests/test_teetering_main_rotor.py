"""A teetering main rotor (``main_rotor.hub_type = "teetering"``: two blades on a yoke across the
shaft, no lag hinge, a Bell or Robinson rotor) as reports print it: the yoke on its teeter hinge
with the hub spring ``flap_stiffness``, the blades on it at their precone on their pitch bearings."""
import json
import math

import pytest

from mbs import aircraft
from mbs.analysis.derivatives import TEETERING, teetering_warning
from mbs.cli import main

PRECONE_DEG = 2.0


def _teetering(tmp_path, name: str = "teeter.toml", drop=("lag_frequency", "lag_stiffness", "lag_damping"),
               **lines) -> str:
    """The Bo105 as a two-bladed teetering rotor of the same solidity (chord doubled), a hub spring of
    40 kN m/rad and 2 deg of precone: test data, not an aircraft."""
    head, sep, rest = aircraft.resolve("bo105").read_text().partition("[main_rotor]\n")
    cut = rest.index("\n[") + 1
    keep = [x for x in rest[:cut].splitlines() if x.split(" = ")[0] not in drop]
    new = {"n_blades": '{ value = 2, unit = "-", source = "test" }',
           "chord": '{ value = 0.54, unit = "m", source = "test" }',
           "flap_stiffness": '{ value = 40000.0, unit = "N m/rad", source = "test" }', **lines}
    present = {x.split(" = ")[0] for x in keep}
    keep = [f"{x.split(' = ')[0]} = {new[x.split(' = ')[0]]}" if x.split(" = ")[0] in new else x for x in keep]
    keep += [f"{key} = {value}" for key, value in new.items() if key not in present]
    extra = ['hub_type = { value = "teetering", unit = "-", source = "test" }',
             'seesaw_mass = { value = 20.0, unit = "kg", source = "test" }',
             'seesaw_size = { value = [0.8, 0.2, 0.1], unit = "m", source = "test" }',
             f'precone = {{ value = {PRECONE_DEG}, unit = "deg", source = "test" }}']
    path = tmp_path / name
    path.write_text(head + sep + "\n".join(extra + keep) + "\n" + rest[cut:])
    return str(path)


def test_the_check_takes_a_teetering_rotor_without_lag_entries_and_names_what_it_cannot_be(tmp_path):
    report = aircraft.check(_teetering(tmp_path))
    assert report.ok, report.problems
    figures = {n: v for n, v, _ in report.figures}
    assert "lag frequency" not in figures
    cone = math.cos(math.radians(2 * PRECONE_DEG))  # the blades' points above the hinge plane (no undersling)
    assert figures["teeter frequency"] == pytest.approx((cone + 40000.0 / (2 * 231.7 * 44.4**2)) ** 0.5, rel=1e-12)
    for lines, words in (({"n_blades": '{ value = 3, unit = "-", source = "test" }'},
                          "a teetering main rotor has 2 blades, not 3"),
                         ({"flap_hinge_offset": '{ value = 0.1, unit = "m", source = "test" }'},
                          "whose blades start at the teeter hinge on the axis: give 0")):
        problems = aircraft.check(_teetering(tmp_path, "bad.toml", **lines)).problems
        assert any(words in p for p in problems), problems
    problems = aircraft.check(_teetering(tmp_path, "lag.toml", drop=("lag_stiffness", "lag_damping"))).problems
    assert any("main_rotor.lag_frequency: applies only when main_rotor.hub_type = 'flapping'" in p
               for p in problems), problems


def test_a_teetering_rotor_trims_with_its_coning_the_precone_and_warns_of_its_derivatives(tmp_path, capsys):
    """Hover and 30 m/s trims converge within 5 Newton iterations (measured 3 and 4); the blades'
    mean flapping is the precone to 1e-12 rad (rigid on the yoke); blade 1's flapping is blade 2's
    reversed about it, so the teeter is a first harmonic (|β1| > 0.005 rad); the derivatives of a
    teetering rotor carry their measured warning, a two-bladed rotor's on flapping hinges not
    (tests/test_two_bladed_derivatives.py)."""
    path = _teetering(tmp_path)
    for speed in (0.0, 30.0):
        assert main(["trim", "forward-flight", "--aircraft", path, "--speed", str(speed), "--json", "--quiet"]) == 0
        res = json.loads(capsys.readouterr().out)
        assert res["converged"] and res["iterations"] <= 5
        assert res["flapping"]["beta0"] == pytest.approx(PRECONE_DEG * 3.141592653589793 / 180, abs=1e-12)
        assert abs(complex(res["flapping"]["beta1c"], res["flapping"]["beta1s"])) > 0.005
    assert teetering_warning(aircraft.load(path).data) == [TEETERING]
    assert teetering_warning(aircraft.load("bo105").data) == []
    assert main(["derivatives", "forward-flight", "--aircraft", path, "--speed", "0", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["warnings"] == [TEETERING]


def test_an_undersling_puts_the_coned_blades_centre_of_mass_at_the_hinge(tmp_path):
    """With the undersling x_cg sin(precone) (x_cg = S/m from the hinge), the blades' centre of
    mass in the rotor's averaged mass properties lies at the teeter hinge's height, to 1e-12 m;
    without it, x_cg sin(precone) above."""
    import math

    import numpy as np

    from mbs.aircraft import mass

    d = aircraft.load(_teetering(tmp_path)).data
    mr = d["main_rotor"]
    rise = mr["first_moment"] / mr["blade_mass"] * math.sin(math.radians(PRECONE_DEG))
    under = aircraft.load(_teetering(tmp_path, "under.toml", undersling=f'{{ value = {rise!r}, unit = "m", '
                                                                         'source = "test" }')).data

    def blades_height(data):
        hub, yoke = mass.main_hub(data), mass.seesaw(data, "main_rotor")
        rotor = mass.main_rotor(data)
        return (rotor.mass * rotor.com[2] - hub.mass * hub.com[2] - yoke.mass * yoke.com[2]) / (
            rotor.mass - hub.mass - yoke.mass)

    assert blades_height(under) == pytest.approx(0.0, abs=1e-12)
    assert blades_height(d) == pytest.approx(rise, rel=1e-12)
    assert np.isclose(rise, 0.0857, atol=1e-4)


def test_an_undersling_far_below_the_balancing_one_is_warned_of(tmp_path):
    """1.5 m of undersling (the balancing one is 0.0857 m) is named with the blades' centre of mass
    1.41 m below the hinge; the balancing one, and twice it, pass without a word."""
    def notes(value):
        path = _teetering(tmp_path, f"u{value}.toml", undersling=f'{{ value = {value}, unit = "m", source = "test" }}')
        return [n for n in aircraft.check(path).warnings if n.startswith("main_rotor.undersling")]

    assert notes(0.0857) == [] and notes(0.17) == []
    (note,) = notes(1.5)
    assert "1.5 m puts the blades' centre of mass 1.41 m below the teeter hinge, where 0.0857 m" in note


def test_coning_hinges_cone_the_blades_until_the_lift_s_moment_is_balanced(tmp_path, capsys):
    """A Robinson's three-hinge rotor (a new user's R22 could not be written): each blade on a
    coning hinge ``coning_hinge_offset`` out along the yoke. In hover a blade cones to where the
    lift's moment about its hinge is balanced by the centrifugal moment of the coned blade, ``Ω²
    sin β (e S + cos β I)`` (``S``, ``I`` the blade's first and second moments about the hinge, its
    mass uniform from the axis), and the hinge's spring ``k (β − β_p)``: the lift's moment so
    found is the same within 1 % for free hinges (coning 3.2 deg past the 2 deg precone) and
    springs of 0.5 and 2 MN m/rad (measured 37.6, 37.4 and 37.4 kN m), although they cone the
    blades 1.4 and 0.5 deg past it."""
    import math

    e, cone = 0.3, math.radians(PRECONE_DEG)
    moments = {}
    d = aircraft.load(_teetering(tmp_path)).data["main_rotor"]
    big_r, line = d["radius"], d["blade_mass"] / d["radius"]
    first = line * ((big_r - e) ** 2 - e**2) / 2
    second = line * ((big_r - e) ** 3 + e**3) / 3
    for k in (0.0, 5.0e5, 2.0e6):
        path = _teetering(tmp_path, f"coning{k:g}.toml",
                          coning_hinge_offset=f'{{ value = {e}, unit = "m", source = "test" }}',
                          coning_stiffness=f'{{ value = {k}, unit = "N m/rad", source = "test" }}')
        assert main(["trim", "forward-flight", "--aircraft", path, "--speed", "0", "--json", "--quiet"]) == 0
        res = json.loads(capsys.readouterr().out)
        assert res["converged"], k
        beta = res["flapping"]["beta0"]
        moments[k] = d["omega"] ** 2 * math.sin(beta) * (e * first + math.cos(beta) * second) + k * (beta - cone)
        assert beta > cone + 0.008, k
    for k in (5.0e5, 2.0e6):
        assert moments[k] == pytest.approx(moments[0.0], rel=0.01), moments


def test_a_coning_spring_without_coning_hinges_is_refused(tmp_path):
    """coning_stiffness on a hub with no coning hinges would do nothing without a word."""
    problems = aircraft.check(_teetering(tmp_path, "spring.toml",
                                         coning_stiffness='{ value = 1e5, unit = "N m/rad", source = "test" }')).problems
    assert any(p.startswith("main_rotor.coning_stiffness: 100000 N m/rad does nothing without coning hinges")
               for p in problems), problems


def test_the_teeter_frequency_counts_the_blades_off_the_hinge_plane(tmp_path):
    """A new user's Bell 206 printed 'teeter frequency 1 1/rev' whatever its undersling (20 in moved
    its 80 kt flapping from -2.1 to -9.4 deg). The figure is the rigid seesaw's, (I_zz - I_xx)/I_yy
    about the hinge plus the spring's: summed over two point masses per blade with the file's
    blade mass, first moment and flap inertia, coned by the precone and hung the undersling below
    the hinge, to 1e-12."""
    import math

    from mbs.aircraft.derived import flap_frequency

    for undersling in (0.0, 0.0857, 0.508):
        mr = aircraft.load(_teetering(tmp_path, f"u{undersling}.toml", undersling=f'{{ value = {undersling}, '
                                      'unit = "m", source = "test" }')).data["main_rotor"]
        m, mean = mr["blade_mass"], mr["first_moment"] / mr["blade_mass"]
        spread = math.sqrt(mr["I_flap"] / m - mean**2)
        b = math.radians(PRECONE_DEG)
        points = [(m / 2, r * math.cos(b), r * math.sin(b) - undersling) for r in (mean - spread, mean + spread)]
        about_span = sum(dm * z**2 for dm, _, z in points)
        about_teeter = sum(dm * (x**2 + z**2) for dm, x, z in points)
        nu2 = (sum(dm * x**2 for dm, x, _ in points) - about_span) / about_teeter \
            + mr["flap_stiffness"] / (2 * about_teeter * mr["omega"] ** 2)
        assert flap_frequency(mr) == pytest.approx(math.sqrt(nu2), rel=1e-12), undersling
    assert flap_frequency(mr) < 0.99 * math.sqrt(1 + mr["flap_stiffness"] / (2 * mr["I_flap"] * mr["omega"] ** 2))
