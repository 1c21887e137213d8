"""Flexible bodies: bodies whose sections move with modal coordinates (their own states) on
top of their frame, the paper's first next step.

* :mod:`~mbs.flexible.uniform_blade`: the uniform blade of the aircraft file and its continuous
  reference model (finite elements of the rotating beam, its frequencies, the stiffnesses that
  give the file's frequencies), on which the blades here and the segmented blade are built;
* :mod:`~mbs.flexible.shapes`: mode shapes of a blade (the continuous blade's finite elements,
  turning or at rest), with slopes, curvatures and the foreshortening integrals;
* :mod:`~mbs.flexible.beam`: :class:`~mbs.flexible.beam.ModalBlade`, the kinematics of a
  section written once (place, turn, their rates by AD), the curvature and strain energy;
* :mod:`~mbs.flexible.joints`: the flexible body's :class:`~mbs.flexible.joints.Modal`
  coordinates and its sections' :class:`~mbs.flexible.joints.Section` joints;
* :mod:`~mbs.flexible.elasticity`: the strain energy's forces and the structural damping;
* :mod:`~mbs.flexible.body`: :func:`~mbs.flexible.body.add_flexible_blade` puts one in a model;
* :mod:`~mbs.flexible.frequencies`: natural frequencies on a driven hub from the AD Jacobian.

The dynamics consume them in :mod:`mbs.dynamics._flexible` and the composite path; a rotor
blade of the aircraft file is :mod:`mbs.models.modal_blade`. A body hung on a flexible body
(other than its sections) moves with its frame, not with a deformed point.
"""
