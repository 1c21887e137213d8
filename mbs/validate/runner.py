"""A validation from end to end: read the published data, run the model at the published speeds,
pair every point, and judge it against the data's tolerances."""
from __future__ import annotations

from dataclasses import dataclass, field

from mbs.validate import compare, eigen, quantities
from mbs.validate.data import EigenTolerance, Validation, resolve_cg, resolve_speed
from mbs.validate.ours import Model, run, scene_of


@dataclass
class Result:
    """The comparison rows of every series, the eigenvalue pairs and the model's points."""

    validation: Validation
    model: Model
    blocks: list[tuple] = field(default_factory=list)  # (series, its rows)
    pairs: list[eigen.Pair] = field(default_factory=list)

    @property
    def rows(self) -> list[compare.Row]:
        return [r for _, rows in self.blocks for r in rows]

    def counts(self) -> dict:
        out = {kind: compare.counts([r for r in self.rows if r.kind == kind]) for kind in ("trim", "derivative")}
        out["eigenvalues"] = {"pairs": len(self.pairs), "within": sum(p.within for p in self.pairs),
                              "same_stability": sum(p.same_stability for p in self.pairs)}
        return out

    @property
    def all_within(self) -> bool:
        """Every checked row and every eigenvalue pair within its tolerance."""
        return all(r.within is not False for r in self.rows) and all(p.within for p in self.pairs)


def validate(validation: Validation, aircraft=None, aero: str | None = None, method: str = "rk4",
             steps_per_rev: int | None = None, backend: str = "compiled", progress=None) -> Result:
    """Compare the model (the scene of ``validation``, built with ``aircraft`` or the file's) with
    the published data of ``validation``."""
    scene = scene_of(validation, aircraft, aero)
    if scene.aircraft is not None:
        validation = resolve_speed(resolve_cg(validation, scene.aircraft.data), scene.aircraft.data)
    model = run(scene, validation.conditions("trim"), validation.conditions("derivative", "eigenvalues"), method,
                steps_per_rev, backend, progress, check=lambda info: quantities.check(validation, info, scene.aircraft))
    out = Result(validation, model)
    for s in validation.series:
        out.blocks.append((s, compare.rows(s, model)))
    tol = validation.eigen_tolerance or EigenTolerance()
    for e in validation.eigenvalues:
        out.pairs += eigen.pairs_at(e, model.at(e.speed, altitude=e.altitude), tol)
    return out
