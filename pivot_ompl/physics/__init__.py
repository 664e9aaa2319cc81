"""Physics in the loop: a plan's whole-body motion simulated in MuJoCo (the ``physics`` extra).

* :mod:`.backend` -- MuJoCo imported on first use (a clear error when missing);
* :mod:`.model` -- the MuJoCo model of a scene: floor, obstacles, the free box, two hands;
* :mod:`.drive` -- what a motion drives: the hands' frames, the pivot rotations;
* :mod:`.loop` -- the simulation loop (:class:`Simulator`) and what it records;
* :mod:`.contacts` -- contact and grip forces, the friction a pivot corner needs;
* :mod:`.perturb` -- friction patches, a mass offset, slips at pivots;
* :mod:`.closed_loop` -- the run, replanned from the observed box when it drifted;
* :mod:`.report` -- :class:`SimulationReport`, the report JSON;
* :mod:`.simulate` -- :func:`simulate`, the entry point.

See docs/physics.md.
"""

from pivot_ompl.physics.closed_loop import LoopSettings
from pivot_ompl.physics.perturb import FrictionPatch, Perturbations, Slip, parse_perturbations
from pivot_ompl.physics.report import ReplanRecord, SimulationReport
from pivot_ompl.physics.simulate import simulate

__all__ = ["FrictionPatch", "LoopSettings", "Perturbations", "ReplanRecord",
           "SimulationReport", "Slip", "parse_perturbations", "simulate"]
