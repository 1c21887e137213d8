"""The native FMU: the heli rotor model as a shared library of C only (no Python at run time),
for FMI 2.0 and FMI 3.0, co-simulation and model exchange, with exact directional and adjoint
derivatives from CasADi's forward and reverse mode. One model core (``heli_core.c``) under thin
per-standard wrappers (``fmi2Functions.c``, ``fmi3Functions.c``), as the Modelica Reference-FMUs
are laid out. ``fmu.native.build.ensure_native_fmu`` builds and caches it.

Its modules: :mod:`~fmu.native.build` (generated C, model descriptions, libraries, cache) with
:mod:`~fmu.native.derivatives` (model exchange and exact derivatives), :mod:`~fmu.native.fmi3`
(the FMI 3.0 description), :mod:`~fmu.native.units`, :mod:`~fmu.native.c_literals` and
:mod:`~fmu.native.platforms` (the cross compilers); :mod:`~fmu.native.wasm` (WebAssembly for the
flight page); and the hosts of the benchmarks, :mod:`~fmu.native.run` (the C host ``host.c``) and
:mod:`~fmu.native.me_host` (model exchange in fmpy)."""
