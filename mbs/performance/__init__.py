"""Power available against power required: the hover ceiling in and out of ground effect and the
largest level speed, against altitude, mass and temperature.

* :mod:`mbs.performance.available`: the engines' power available at the air's conditions (their
  ratings lapsing with the air, the gearbox limit, one engine inoperative);
* :mod:`mbs.performance.ceiling`: the power required, from periodic trims swept on Dask over
  altitude, temperature offset, payload and speed (:func:`mbs.sweep.trim_sweep`), and where it meets
  the power available: the hover ceiling (out of and in ground effect) and the largest level speed;
* :mod:`mbs.performance.commands`: ``heli performance ceiling`` and ``heli performance speed``.
"""
