"""The exceptions varsym raises. Each carries the one-line message the command-line tool prints."""


class Error(Exception):
    """Base class of varsym's errors."""


class UsageError(Error, ValueError):
    """Bad input: an unknown option, model or scheme, a value out of range (tool exit code 2)."""


class ExpressionError(Error, ValueError):
    """An expression that does not parse or names something unknown.

    ``position`` is the 0-based offset of the problem in the expression text."""

    def __init__(self, message, position=None):
        super().__init__(message)
        self.position = position


class StepFailure(Error, RuntimeError):
    """A step's Newton iteration did not converge (tool exit code 3).

    ``step`` and ``time`` say where; ``partial`` holds the rows computed before it: a
    Trajectory from varsym.run, the dict of arrays Stepper.run returns from Stepper.run."""

    def __init__(self, message, step=None, time=None, partial=None):
        super().__init__(message)
        self.step = step
        self.time = time
        self.partial = partial


class EnergyError(Error, RuntimeError):
    """The energy error passed the bound of the energy watch (tool exit code 4); ``partial``
    holds the rows before it (a Trajectory)."""

    def __init__(self, message, partial=None):
        super().__init__(message)
        self.partial = partial
