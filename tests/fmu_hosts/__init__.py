"""Test hosts of the FMUs, each run in a fresh process by the tests (``python -m fmu_hosts.MODULE``;
the tests put their folder on ``PYTHONPATH``): Python hosts over fmpy's and ctypes' calls
(:mod:`~fmu_hosts.modes`, :mod:`~fmu_hosts.probe`, :mod:`~fmu_hosts.probe_fmi`,
:mod:`~fmu_hosts.native_checks`), the scripted C host and its conformance cases
(:mod:`~fmu_hosts.script_host`, :mod:`~fmu_hosts.conformance`), and the exit check of C hosts
linked to libpython (:mod:`~fmu_hosts.exit_check`)."""
