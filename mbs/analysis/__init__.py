"""Analysis of models and results.

* :mod:`mbs.analysis.signals`: signal analysis of recorded runs (spectra, envelopes, fitted
  modes) and closed-form blade frequencies; re-exported here (``from mbs import analysis;
  analysis.dominant_frequency(...)``);
* :mod:`mbs.analysis.period`: the common period of the rotors and its symmetry;
* :mod:`mbs.analysis.monodromy`: the Jacobian of the state after a number of fixed steps
  (one period) with respect to the initial state and the parameters, by forward-mode AD
  through the generated step;
* :mod:`mbs.analysis.trim`: periodic trim by shooting, Newton with that Jacobian;
* :mod:`mbs.analysis.floquet`: Floquet multipliers and characteristic exponents at a trim;
* :mod:`mbs.analysis.multiblade`: multi-blade coordinates and fixed-frame rotor mode names;
* :mod:`mbs.analysis.fanplot`: Floquet sweeps over a run-time parameter (rotor speed), the fan
  plot and its unstable bands;
* :mod:`mbs.analysis.held`: the rotor's periodic response with the fuselage motion held (the
  quasi-static rotor) and its derivatives by the implicit-function theorem;
* :mod:`mbs.analysis.derivatives`: stability and control derivatives at trim, Padfield's A and B;
* :mod:`mbs.analysis.flight_modes`: the eigenvalues of A named as flight modes;
* :mod:`mbs.analysis.blade_modes`: an elastic blade's first frequencies on a driven hub from the
  model's AD Jacobian (segmented and modal blades).

Only the signal functions (numpy) are imported here; the others need CasADi.
"""
from mbs.analysis.signals import (crossing_frequency, dominant_frequency, envelope, fit_damped_mode,
                                  flap_lag_frequencies, hinge_inertia, spectrum)

__all__ = ["crossing_frequency", "dominant_frequency", "envelope", "fit_damped_mode", "flap_lag_frequencies",
           "hinge_inertia", "spectrum"]
