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

import functools

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
    "StepReport", "bead_mass", "check_scene", "converge", "grid_points",
    "hertz_stiffness", "hertz_stiffness_wall", "read_scene", "run_chain", "run_packing",
    "PackingResult", "sweep",
]


def _without_arguments_echoed(function):
    """pybind11's TypeError for arguments of the wrong type repeats every argument given, a
    scene of megabytes included: keep the signatures, drop the echo."""
    @functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as error:
            text = str(error)
            cut = text.find("\n\nInvoked with")
            if cut < 0:
                raise
            raise TypeError(text[:cut] + "\nThe arguments given have other types.") from None
    return call


def _shorten_type_errors():
    module = globals()
    for name in __all__:
        item = module[name]
        if isinstance(item, type) and item.__module__ == "mimpact._mimpact":
            for attribute, value in list(vars(item).items()):
                if callable(value) and (attribute == "__init__" or not attribute.startswith("_")):
                    setattr(item, attribute, _without_arguments_echoed(value))
        elif callable(item) and getattr(item, "__module__", "") == "mimpact._mimpact":
            module[name] = _without_arguments_echoed(item)


_shorten_type_errors()
