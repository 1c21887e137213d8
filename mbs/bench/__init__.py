"""Benchmarks of the core (``heli bench ...``): speed against MuJoCo and Pinocchio, scaling with
model size, work-precision and stability of the integrators, the drive train, the swashplate's
loops and the modal blades; the timing helpers they share (:mod:`mbs.bench.timing`). The FMUs'
benchmarks are the fmu package's; the loads' is :mod:`mbs.loads.bench`."""
