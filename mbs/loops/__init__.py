"""Local closed loops inside the open tree, in almost minimal coordinates.

A loop lives inside one joint (:class:`LoopJoint`, a joint assembly between a parent and a
child body with massless links inside): its *dependent* coordinates are solved from closure
equations as functions of the joint's own independent coordinates, the time and the
parameters, inside the generated code. The states stay the tree's coordinates; the tree, the
forward-mode AD and both dynamics paths see an ordinary joint.

* :class:`LinkLoop`: a rigid link over one revolute part (a pitch link on its horn, a four-bar's
  coupler), solved in closed form (``A cos θ + B sin θ = K``);
* :class:`Newton`: any loop's closure equations by a fixed number of Newton steps from a
  predictor, with the AD Jacobian;
* :func:`add_loop_outputs`: each loop's closure margin and link-length error as outputs.

Derivatives: the dependent rates are one forward directional derivative of the solution
along ``(q', 1)``; accelerations and every Jacobian follow from the tree's AD through the same
expression. For the closed form that is the AD of the formula; for Newton, the AD of the
converged iterates, which is the implicit-function theorem's (:mod:`mbs.loops.newton`).
Nothing is differentiated by hand.

Convergence and failure: the closed form needs no iteration; it exists exactly where the
loop can close (margin ``1 - |K|/ρ >= 0``) and keeps the branch of the loop's assembly, which is
checked when the model is built. Where a loop cannot close (a link too short for the inputs,
a Newton solve that left a residual above its tolerance) its coordinates are NaN: the run
stops with the generated code's non-finite status, and the message names the loop and the
time (:mod:`mbs.backends.closure`). Limits: a loop may read only its own joint's coordinates,
the time and the parameters (the tree's recursions then hold unchanged); a loop across
bodies would need the dense ``J_u``.
"""
from mbs.loops.joint import LoopJoint
from mbs.loops.link import LinkLoop
from mbs.loops.loop import Assembly, Loop
from mbs.loops.newton import Newton
from mbs.loops.outputs import MARGIN, add_loop_outputs, loops_of

__all__ = ["Assembly", "LinkLoop", "Loop", "LoopJoint", "MARGIN", "Newton", "add_loop_outputs", "loops_of"]
