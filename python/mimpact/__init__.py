"""mimpact: nonsmooth multibody dynamics with multiple impacts (the LZB model).

The chains of the command line from Python::

    import mimpact
    result = mimpact.run_chain("examples/scenes/c1.json")
    result.post_impact_velocities   # NumPy array, m/s

and the kernel: bodies, interactions and a simulation whose integrator and problems are
chosen by name (examples/python/bouncing_ball.py). Bad input raises ValueError with the
message the command line gives (the field, its value and what is allowed). See
docs/python.md.
"""

from ._mimpact import (
    ChainResult,
    ContactForces,
    DynamicalSystem,
    ImpactReport,
    Interaction,
    LagrangianDS,
    LagrangianLinearTIDS,
    LinearRelation,
    LzbLaw,
    NonSmoothDynamicalSystem,
    NonSmoothLaw,
    PackingResult,
    Relation,
    RunSummary,
    Simulation,
    SimulationState,
    StepReport,
    bead_mass,
    check_scene,
    converge,
    hertz_stiffness,
    hertz_stiffness_wall,
    read_scene,
    run_chain,
    run_packing,
)
from .fit import FitResult, fit
from .sweep import grid_points, sweep

__all__ = [
    "FitResult", "fit", "ChainResult", "ContactForces", "DynamicalSystem", "ImpactReport", "Interaction",
    "LagrangianDS", "LagrangianLinearTIDS", "LinearRelation", "LzbLaw",
    "NonSmoothDynamicalSystem", "NonSmoothLaw", "Relation", "RunSummary", "Simulation",
    "SimulationState", "StepReport", "bead_mass", "check_scene", "converge", "grid_points",
    "hertz_stiffness", "hertz_stiffness_wall", "read_scene", "run_chain", "sweep",
]
