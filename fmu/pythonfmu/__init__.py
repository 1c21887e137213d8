"""The pythonfmu FMU (FMI 2.0 co-simulation, Python at run time): its slave and its C front end.

- :mod:`fmu.pythonfmu.slave`: the ``Fmi2Slave`` (pythonfmu's entry module, shipped in the FMU
  under a name unique to the build), over its helpers :mod:`~fmu.pythonfmu.stepping` (the
  numerics), :mod:`~fmu.pythonfmu.errors` (entry points that never raise),
  :mod:`~fmu.pythonfmu.resources` (what it reads from the FMU), :mod:`~fmu.pythonfmu.fmu_state`
  and :mod:`~fmu.pythonfmu.units`, shipped with it;
- :mod:`fmu.pythonfmu.shim`: the FMI 2.0 front end in C in front of pythonfmu's binary.

The build that stages and packs them is :mod:`fmu.build`. Importing this package imports nothing.
"""
