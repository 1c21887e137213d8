"""Models built on the tree: the helicopter of any aircraft file, its elastic blades, and small
models for tests, checks and benchmarks.

* :mod:`mbs.models.helicopter`: a single-main-rotor helicopter from an aircraft file (every
  aircraft, the packaged Bo105, Puma and Lynx among them) and its scenes;
* :mod:`~mbs.models.elastic_blade`: main-rotor blades as chains of rigid segments;
  :mod:`~mbs.models.modal_blade`: as flexible bodies with modal coordinates;
* :mod:`~mbs.models.ground_resonance`: the fuselage on its landing gear and a lagging rotor;
* :mod:`~mbs.models.demo`: generic conservative trees (no helicopter data);
  :mod:`~mbs.models.fourbar`: a four-bar linkage as a local loop; :mod:`~mbs.models.mathieu`:
  the damped Mathieu equation; :mod:`~mbs.models.stability_cases`: the stability benchmark's cases.

The aircraft data (:mod:`mbs.aircraft`) and the uniform blade it calibrates
(:mod:`mbs.flexible.uniform_blade`) lie below; the analyses, loads and commands above.
"""
