"""The packaged validations: the Puma against Padfield's Helisim derivatives and eigenvalues
(0-140 kn), the Bo105 against its DLR flight-test trims (0-105 kt) and against Helisim.

Each criterion of the flight model's sign-off is one test over every published speed, with the
tolerance the data file carries (Puma: main derivatives within 25 %, modes of the same stability,
frequencies within 25 %; Bo105: collective within 1 deg, cyclic 1.5 deg, tail collective 2.5 deg,
pitch attitude 1 deg, power 10 %). The criteria today's aircraft files miss are marked
``xfail(strict=True)`` with the measured figure: they turn into failures the day they pass, to be
unmarked then.
A run takes about 100 s (Puma, Bo105 Helisim) and 100-600 s (Bo105 flight test, 70 trims)
depending on the load of the machine.
"""
from __future__ import annotations

import json

import pytest

from mbs.validate import charts, load, report, validate
from test_cli_errors import run_main


@pytest.fixture(scope="module")
def puma():
    return validate(load("puma_helisim"))


@pytest.fixture(scope="module")
def flight_test():
    return validate(load("bo105_flight_test"))


@pytest.fixture(scope="module")
def bo105_helisim():
    return validate(load("bo105_helisim"))


def rows_of(res, quantity: str):
    rows = [r for r in res.rows if r.quantity == quantity and r.within is not None]
    show = (lambda r: f"{r.difference:+.2f} {r.unit}") if rows and rows[0].kind == "trim" else (lambda r: f"x{r.ratio:.2f}")
    print(f"{quantity}: " + ", ".join(f"{r.speed:g}: {r.ours:+.4g} vs {r.published:+.4g} ({show(r)})"
                                      + ("" if r.within else " OUT") for r in rows))
    return rows


def out_of(rows) -> list[str]:
    return [f"{r.speed:g}: ours {r.ours:+.4g}, published {r.published:+.4g}" for r in rows if not r.within]


MISSED = "today's Puma file misses it"
PUMA = {
    "Z_w": None, "M_θ1s": None, "L_θ1c": None,
    "X_u": "x1.29-1.67 from 60 kn (hub_drag, an estimate, adds about 40 % of the drag)",
    "M_u": "x2.6 in hover (the download panels, an estimate: x1.05 without, test_puma_helisim_causes.py), x0.29 and "
           "x0.15 at 20 and 80 kn, x1.36-1.68 elsewhere",
    "M_q": "x1.25-1.32 at 0-40 kn: in hover the download panels (x1.08 without); at 20-40 kn our rotor's damping "
           "grows with the Pitt-Peters skewed wake where Helisim's grows by the tailplane's alone "
           "(test_puma_helisim_causes.py)",
    "L_p": "x0.68, 0.56 at 120, 140 kn (within 25 % to 100 kn): compressibility, which Helisim lacks, takes 0.14 at "
           "140 kn and the hub-drag estimate's trim 0.07; with both off x0.77-1.05 (test_roll_damping.py)",
    "N_r": "x1.80-3.00, growing with speed: ours is momentum theory's tail rotor and strip theory's fin on the "
           "printed data (within 3 and 8 % at 80 and 140 kn); Helisim's is under half of that, less than the fin's "
           "strip damping alone at 140 kn (test_yaw_control.py)",
    "L_v": "opposite sign (the published "
    "curve's sign is uncertain)",
    "N_v": "x1.57-4.61 from 40 kn: ours is the printed tail rotor, fin and fuselage by textbook theory (within 6 % "
           "at 80 and 140 kn), Helisim's 0.38 and 0.22 of it (test_yaw_control.py)",
    "Z_θ0": "x1.26 in hover (compressibility, which Helisim lacks: x1.13 without, test_puma_helisim_causes.py)",
    "N_θ0T": "x1.50-1.97 at every speed: the model's tail rotor equals blade-element momentum theory on the "
             "file's tail data, Helisim's is 0.62 of it (test_yaw_control.py); the chord 0.1176 m of S1a's "
             "rigidPuma.m gives x1.21-1.41",
}


@pytest.mark.parametrize("quantity", [pytest.param(q, marks=pytest.mark.xfail(strict=True, reason=f"{MISSED}: {why}"))
                                      if why else q for q, why in PUMA.items()])
def test_puma_main_derivative_within_25_percent_of_helisim_at_every_speed(puma, quantity):
    rows = rows_of(puma, quantity)
    assert len(rows) == 8 and not [r for r in rows if r.problem]
    assert not out_of(rows), f"{quantity} outside 25 %: {out_of(rows)}"


@pytest.mark.xfail(strict=True, reason=f"{MISSED}: the spiral at 20-120 kn is stable where Helisim's diverges "
                                       "(the published spiral comes from P1's L_v, whose sign is uncertain)")
def test_puma_modes_have_helisims_stability_at_every_speed(puma):
    bad = [f"{p.speed:g} kn: {p.published:.3f} vs {p.ours:.3f} ({p.mode})" for p in puma.pairs if not p.same_stability]
    assert len({p.speed for p in puma.pairs}) == 8
    assert not bad, bad


@pytest.mark.xfail(strict=True, reason=f"{MISSED}: phugoid x0.25 at 80 kn, short period x1.32-2.12 to 80 kn "
                                       "(within 25 % with compressibility, hub drag and download off: "
                                       "test_puma_helisim_causes.py), Dutch roll x1.31-2.03 from 40 kn (the yaw group)")
def test_puma_frequencies_within_25_percent_of_helisim(puma):
    bad = [f"{p.speed:g} kn {p.mode}: x{p.ratio:.2f}" for p in puma.pairs if p.ratio is not None
           and p.measure == "frequency" and abs(p.ratio - 1) > 0.25]
    assert not bad, bad


FLIGHT = {"collective": "-1.01 deg at 100 kt (too little inflow through the disc at speed, at most a third of it "
                        "drag: test_bo105_trim_causes.py)", "lateral_cyclic": None, "longitudinal_cyclic": None,
          "tail_collective": "+2.7, +2.6 deg at 23, 31 kt (the flight test's 3.7 deg step from 15 to 23 kt, which the "
                             "model lacks: test_bo105_trim_causes.py)",
          "pitch": "-1.2 to +1.8 deg at 27-67 kt (the data's scatter at 27 and 39 kt, the tail-wake downwash +0.5 deg "
                   "from 39 kt: test_bo105_trim_causes.py)",
          "engine.power": "+13 to +17 % at 8-27 kt, where ours is momentum theory's and the flight test 11-17 % below "
                          "it; -16 and -24 % at 78 and 99 kt, with the collective's miss there: too little inflow "
                          "through the disc, not drag (test_bo105_trim_causes.py)"}


@pytest.mark.parametrize("quantity", [
    pytest.param(q, marks=pytest.mark.xfail(strict=True, reason=f"today's Bo105 file misses it: {why}")) if why else q
    for q, why in FLIGHT.items()])
def test_bo105_trim_within_tolerance_of_the_flight_test(flight_test, quantity):
    rows = rows_of(flight_test, quantity)
    assert rows and not [r for r in rows if r.problem]
    assert not out_of(rows), f"{quantity} outside {rows[0].unit} tolerance: {out_of(rows)}"


def test_every_published_speed_trims_and_linearises(puma, flight_test, bo105_helisim):
    for res in (puma, flight_test, bo105_helisim):
        assert all(p.ok for p in res.model.points.values()), [p.problem for p in res.model.points.values()]
        assert len(res.rows) == sum(len(s.value) for s in res.validation.series)
    assert len(bo105_helisim.pairs) == 64 and len(puma.pairs) == 64
    print("\n".join(report.verdict_lines(puma) + report.verdict_lines(flight_test) + report.verdict_lines(bo105_helisim)))


def test_bo105_helisim_figures_recorded(bo105_helisim, tmp_path):
    """Not a criterion of the sign-off (the Bo105's is its flight test): the comparison runs,
    Z_w and Z_θ0 (the rotor's thrust response, which the derivative charts read best) are within
    25 % at every speed, and the charts are written."""
    for q in ("Z_w", "Z_θ0"):
        assert not out_of(rows_of(bo105_helisim, q))
    files = charts.write_all(bo105_helisim, tmp_path)
    assert sorted(p.name for p in files) == ["derivatives.png", "root_locus.png"]
    assert all(p.stat().st_size > 20_000 for p in files)


CSV = """# title: two trims and a hover linearisation
# aircraft: bo105
# speed_unit: kt
# convention controls: blade angles, deg
# source P1: Padfield (1996), Fig. 4.10(c); a hover subsidence of the Bo105 root locus
kind,quantity,unit,speed,value,imaginary,uncertainty,tolerance,source,note
trim,collective,deg,0,14.26,,0.06,absolute TOL,P1,
trim,collective,deg,50.09,12.09,,0.06,absolute TOL,P1,
derivative,Z_w,1/s,0,-0.3164,,0.007,relative 0.25,P1,
eigenvalue,,1/s,0,-0.30,0,,,P1,
"""


@pytest.mark.parametrize("tol,code", [(0.01, 1), (2.0, 0)])
def test_check_sets_the_exit_status(tol, code, tmp_path, capsys):
    """``--check``: exit status 1 when a point is outside its tolerance (the model's hover
    collective is 0.4 deg above the flight test's), 0 when every point and pair is within."""
    data = tmp_path / "two.csv"
    data.write_text(CSV.replace("TOL", str(tol)))
    status, err = run_main(["validate", str(data), "--check", "--no-charts", "--quiet"], capsys)
    assert status == code, err


def test_command_json_is_one_object(tmp_path, capfd):
    from mbs import cli

    data = tmp_path / "two.csv"
    data.write_text(CSV.replace("TOL", "2.0"))
    assert cli.main(["validate", str(data), "--json", "--quiet", "--out", str(tmp_path / "o")]) == 0
    captured = capfd.readouterr()
    res = json.loads(captured.out)
    assert res["counts"]["trim"] == {"rows": 2, "checked": 2, "within": 2, "no_model_value": 0}
    assert res["counts"]["derivative"]["within"] == 1 and res["all_within"] is True
    pair, = res["eigenvalues"]
    assert pair["published"] == [-0.3, 0.0] and pair["measure"] == "rate" and pair["within"]
    assert sorted(p.split("/")[-1] for p in res["files"]) == ["derivatives.png", "root_locus.png", "trims.png"]
    assert res["conventions"] == {"controls": "blade angles, deg"}
    assert "collective [deg]: tolerance ±2 deg" in captured.err
