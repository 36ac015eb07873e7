"""mimpact: nonsmooth multibody dynamics with multiple impacts (the LZB model).

The chains of the command line from Python::

    import mimpact
    result = mimpact.run_chain("examples/scenes/c1.json")
    result.post_impact_velocities   # NumPy array, m/s

Bad input raises ValueError with the message the command line gives (the field, its value
and what is allowed). See docs/python.md.
"""

from ._mimpact import ChainResult, converge, run_chain

__all__ = ["ChainResult", "converge", "run_chain"]
