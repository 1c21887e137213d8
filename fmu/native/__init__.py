"""The native FMU: the heli rotor model as a shared library of C only (no Python at run time),
for FMI 2.0 and FMI 3.0, co-simulation and model exchange, with exact directional and adjoint
derivatives from CasADi's forward and reverse mode. One model core (``heli_core.c``) under thin
per-standard wrappers (``fmi2Functions.c``, ``fmi3Functions.c``), as the Modelica Reference-FMUs
are laid out. ``fmu.native.build.ensure_native_fmu`` builds and caches it."""
