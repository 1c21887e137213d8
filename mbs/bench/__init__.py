"""Benchmarks: speed, FMU overhead, work-precision, stability, scaling."""
