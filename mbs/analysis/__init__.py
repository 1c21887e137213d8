"""Analysis of models and results.

* :mod:`mbs.analysis.signals`: signal analysis of recorded runs (spectra, envelopes, fitted
  modes) and closed-form blade frequencies; re-exported here (``from mbs import analysis;
  analysis.dominant_frequency(...)``);
* :mod:`mbs.analysis.period`: the common period of the rotors and its symmetry;
* :mod:`mbs.analysis.monodromy`: the Jacobian of the state after a number of fixed steps
  (one period) with respect to the initial state and the parameters, by forward-mode AD
  through the generated step;
* :mod:`mbs.analysis.trim`: periodic trim by shooting, Newton with that Jacobian;
* :mod:`mbs.analysis.floquet`: Floquet multipliers and characteristic exponents at a trim.

Only the signal functions (numpy) are imported here; the others need CasADi.
"""
from mbs.analysis.signals import (crossing_frequency, dominant_frequency, envelope, fit_damped_mode,
                                  flap_lag_frequencies, hinge_inertia, spectrum)

__all__ = ["crossing_frequency", "dominant_frequency", "envelope", "fit_damped_mode", "flap_lag_frequencies",
           "hinge_inertia", "spectrum"]
