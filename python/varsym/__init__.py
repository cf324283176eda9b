"""varsym: variational symplectic integrators for Lagrangian mechanics (Python interface).

    >>> import varsym
    >>> tr = varsym.simulate("kepler", eccentricity=0.6, scheme="gauss", degree=4, t_span=62.8,
    ...                      steps=2000)
    >>> tr.q.shape, abs(tr.q - tr.q_exact).max()

``simulate`` integrates a built-in model (``models()``; ``Model`` sets its parameters) or your
own Lagrangian (``Lagrangian``) and returns a ``Trajectory``; ``Stepper`` steps one, with its
tangent map and Poincaré sections; ``Model.ensemble`` runs many initial states on every core.
``Robot`` reads a robot from its URDF file (a Model with its joints, limits, mass matrix,
gravity and frame poses). ``optimize`` finds the controls of a model with inputs, a URDF robot
or a typed Lagrangian that reach a target state at least cost (an ``OptimalControl``). The
paper's Table 1 and figures: ``table1``, ``figure_data``. Everything is computed by the
compiled C++ library, in-process. Errors are varsym.Error subclasses carrying the tool's
one-line messages; Ctrl-C raises varsym.Interrupted (a KeyboardInterrupt) with the rows so far.
"""

from ._core import __version__
from .errors import EnergyError, Error, ExpressionError, Interrupted, StepFailure, UsageError
from ._lagrangian import Lagrangian
from ._trajectory import Trajectory
from ._simulate import Model, Stepper, simulate
from ._robot import Robot
from ._run import Table, call, figure_data, models, run, table1
from ._optimize import OptimalControl, SolverError, optimize

__all__ = ["simulate", "Model", "Robot", "Stepper", "Trajectory", "Lagrangian", "run", "table1",
           "figure_data", "models", "call", "Table", "Error", "UsageError", "ExpressionError",
           "StepFailure", "EnergyError", "Interrupted", "SolverError", "optimize", "OptimalControl",
           "__version__"]
