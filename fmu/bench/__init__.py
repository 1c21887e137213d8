"""Benchmarks of the FMUs (``heli bench fmu``, ``heli bench fmu-me``): :mod:`fmu.bench.speed`, the FMUs'
speed under fmpy, a C host and the core run directly; :mod:`fmu.bench.derivatives`, the native
FMU's Jacobian from its directional derivatives against finite differences, and model exchange
under fmpy's CVode. The core's benchmarks are in :mod:`mbs.bench`."""
