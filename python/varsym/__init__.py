"""varsym: variational symplectic integrators for Lagrangian mechanics (Python interface).

    >>> import varsym
    >>> tr = varsym.run("kepler", scheme="gauss", degree=4, steps_per_period=200, periods=10)
    >>> tr.q.shape, tr.energy.max() - tr.energy.min()

Built-in models and schemes (``run``, ``models``), the paper's Table 1 and figures (``table1``,
``figure_data``), and your own system from an expression (``Lagrangian``, ``Stepper``, or
``run(lagrangian=...)``), computed by the compiled C++ library. Errors are varsym.Error
subclasses carrying the command-line tool's one-line messages.
"""

from .errors import EnergyError, Error, ExpressionError, StepFailure, UsageError
from ._lagrangian import Lagrangian, Stepper
from ._run import Trajectory, call, figure_data, models, run, table1

__all__ = ["run", "table1", "figure_data", "models", "call", "Trajectory", "Lagrangian",
           "Stepper", "Error", "UsageError", "ExpressionError", "StepFailure", "EnergyError"]
