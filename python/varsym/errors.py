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

    ``step`` (the index of the step that failed) and ``time`` (the time it started from) say
    where; ``cause`` names a cause where one was found (NaN from the Lagrangian or a force, a
    singular mass matrix; empty when the step was merely too large); ``q`` and ``p`` are the
    last good state (where the stepper reported it); ``partial`` holds the rows computed before
    the failure, a Trajectory."""

    def __init__(self, message, details=None, partial=None):
        super().__init__(message)
        details = details if isinstance(details, dict) else {}
        self.step = details.get("step")
        self.time = details.get("time")
        self.cause = details.get("cause", "")
        self.q = details.get("q")
        self.p = details.get("p")
        self.rows = details.get("rows")
        self.partial = partial


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) stopped a long call within 0.2 s. ``partial`` holds the rows computed
    before it (a Trajectory), and ``stepper`` the stepper, at the last step taken: continue it
    with ``stepper.run(...)``. A subclass of KeyboardInterrupt, so that an unhandled one ends a
    script as Ctrl-C always does."""

    def __init__(self, message="interrupted", partial=None, stepper=None):
        super().__init__(message)
        self.partial = partial
        self.stepper = stepper


class EnergyError(Error, RuntimeError):
    """The energy error passed the bound of the energy watch (tool exit code 4;
    ``max_energy_error`` in Python); ``partial`` holds the rows up to it (a Trajectory)."""

    def __init__(self, message, partial=None):
        super().__init__(message)
        self.partial = partial
