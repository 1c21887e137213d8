"""Rotor loads: what every joint carries, the hub loads the rotor puts into the airframe, their
harmonics per revolution, and power as an engine sees it.

* :mod:`mbs.loads.outputs`: joint reaction loads (:class:`mbs.dynamics.Reactions`, one backward
  Newton–Euler pass) declared as named model outputs;
* :mod:`mbs.loads.rotorcraft`: the loads outputs of a helicopter tree of any aircraft file (blade root and spanwise
  loads, hub loads in body axes, shaft torque and power, engine power);
* :mod:`mbs.loads.engine`: the engine power from the shaft powers, the transmission efficiency
  and the accessory power;
* :mod:`mbs.loads.analysis`: the loads over one period of the periodic trim and their exact
  harmonics per revolution; :mod:`mbs.loads.sweep`: the same over speeds;
* :mod:`mbs.loads.charts`, :mod:`mbs.loads.files`: charts and CSV files; :mod:`mbs.loads.commands`:
  ``heli loads`` and ``heli bench loads`` (:mod:`mbs.loads.bench`).
"""
