"""The native FMU: the same FMI 2.0 co-simulation model as the pythonfmu one, as a shared
library of C only (our FMI wrapper ``heli_fmi2.c`` over the generated models), no Python
at run time. ``fmu.native.build.ensure_native_fmu`` builds and caches it."""
