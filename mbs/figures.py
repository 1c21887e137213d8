"""The paper's two figures, regenerated: Fig. 2 (hinge angles in forward flight) and Fig. 3
(relative total-energy error of the conservative structural case, float32 and float64), of
the Bo105 or another aircraft."""
from __future__ import annotations

import json
from pathlib import Path

from mbs import atomic, plots, scenes
from mbs.simulate import simulate


def fig2(out: Path, revs: float = 1.0, progress=None, aircraft=None) -> tuple[Path, dict]:
    """Forward flight at ~10 m/s: main-rotor flap and lag, tail-rotor seesaw over ``revs``."""
    scene = scenes.get("forward-flight", aircraft)
    sim = simulate(scene, revs=revs, steps_per_rev=100, progress=progress)
    name = "fig2_hinge_angles.png" if revs == 1 else f"fig2_hinge_angles_{revs:g}rev.png"
    path = plots.hinge_angles(sim, out / name, title=f"{_short(scene)}, forward flight at 10 m/s: hinge angles "
                                                     f"({revs:g} revolution{'s' if revs != 1 else ''}, RK4, 100 steps/rev)")
    return path, sim.summary()


def _short(scene) -> str:
    """The aircraft's name as the paper writes the Bo105's."""
    return "Bo105" if scene.aircraft.name == "MBB Bo105" else scene.aircraft.name


def fig3(out: Path, progress=None, aircraft=None) -> tuple[Path, dict]:
    """Structural case, RK4 at 100 steps/rev over 10 revolutions, float64 and float32."""
    scene = scenes.get("structural", aircraft)
    runs = [simulate(scene, 10, 100, "float64", progress=progress),
            simulate(scene, 10, 100, "float32", progress=progress),
            simulate(scene, 10, 100, "float32", compensated=False, progress=progress)]
    path = plots.energy_error(runs, out / "fig3_energy_error.png", log=True,
                              title=f"{_short(scene)} structural case: relative total-energy error, RK4, 100 steps/rev")
    return path, {f"{s.system.dtype}{'' if s.compensated else '_plain'}": s.summary() for s in runs}


def make_all(out: Path, progress=None, aircraft=None) -> dict:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    p2, s2 = fig2(out, 1.0, progress, aircraft)
    p2b, s2b = fig2(out, 10.0, progress, aircraft)
    p3, s3 = fig3(out, progress, aircraft)
    result = {"files": [str(p2), str(p2b), str(p3)], "fig2": s2, "fig2_10rev": s2b, "fig3": s3}
    atomic.write_text(out / "figures.json", json.dumps(result, indent=1))
    return result
