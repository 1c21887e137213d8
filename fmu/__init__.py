"""FMI 2.0 co-simulation FMU of the rotor multibody model (built with pythonfmu).

- :mod:`fmu.heli_bo105_slave`: the ``Fmi2Slave`` (shipped inside the FMU under a unique name);
- :mod:`fmu.build`: plan, stage, build and cache the ``.fmu`` (``heli fmu build``);
- :mod:`fmu.hosts`: run it under fmpy or OSP libcosim, and the equivalent direct core run;
- :mod:`fmu.demo`, :mod:`fmu.bench`: ``heli demo`` and ``heli bench fmu``.

Importing this package imports nothing heavy.
"""

DEFAULT_SCENES = ("forward-flight", "hover", "ground-run")
"""The scene family of an FMU built without ``--scenes``: the first one is its default scene."""
