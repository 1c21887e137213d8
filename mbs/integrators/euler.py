"""Explicit (forward) Euler method."""
from mbs.integrators._tableau import ButcherTableau

EULER = ButcherTableau(name="euler", a=((0,),), b=(1.0,), c=(0,), order=1)
