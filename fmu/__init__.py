"""The helicopter model as FMUs, and what runs them.

- :mod:`fmu.build`: the variables and scenes of an FMU family (shared by both FMUs: ``plan``),
  and the pythonfmu FMU's staging, build and cache (``heli fmu build``); :mod:`fmu.periodic`
  (stored periodic starts) and :mod:`fmu.structure` (``<ModelStructure>``) serve both;
- :mod:`fmu.pythonfmu`: the FMI 2.0 co-simulation FMU with Python at run time (the slave and its
  C front end, the shim);
- :mod:`fmu.native`: the native FMU (C only; FMI 2.0 and 3.0, co-simulation and model exchange;
  Linux, Windows, ARM and WebAssembly);
- :mod:`fmu.controller`: the hover-hold controller FMU;
- :mod:`fmu.cosim`: the closed-loop co-simulation (SSP file, OSP libcosim and an fmpy master);
- :mod:`fmu.linearize`: A, B, C, D of an FMU from its directional derivatives;
- :mod:`fmu.hosts`: run an FMU under fmpy or libcosim, and the equivalent direct core run;
- :mod:`fmu.demo`, :mod:`fmu.bench`: ``heli demo`` and the FMU benchmarks;
  :mod:`fmu.commands`, :mod:`fmu.derivative_commands`: the ``heli`` commands.

Importing this package imports nothing heavy.
"""

DEFAULT_SCENES = ("forward-flight", "hover", "ground-run")
"""The scene family of an FMU built without ``--scenes``: the first one is its default scene."""
