"""Your own system: a Lagrangian from an expression (a string or a SymPy expression), compiled
once into C++ code with exact symbolic derivatives, and a stepper of the general engine for it."""

import numpy as np

from . import _core
from .errors import UsageError


def _expression_text(expression):
    if isinstance(expression, str):
        return expression
    try:
        import sympy  # noqa: PLC0415 (optional: only for SymPy input)
    except ImportError as e:  # pragma: no cover
        raise UsageError("a Lagrangian is a string, or a SymPy expression (python3-sympy)") from e
    if not isinstance(expression, sympy.Basic):
        raise UsageError(
            f"a Lagrangian is a string or a SymPy expression, not {type(expression).__name__}"
            " (for a Python function, use Lagrangian.from_function)")
    return sympy.sstr(expression, full_prec=True)


class Lagrangian:
    """L(q, q̇, t) given as an expression over named coordinates (their velocities are
    NAME_dot), the time t and named parameters, e.g.::

        Lagrangian("0.5*m*l**2*th_dot**2 + m*g*l*cos(th)", ["th"], {"m": 1, "g": 9.81, "l": 1})

    The expression is a string in Python syntax (+ - * / **, parentheses, sin cos tan exp log
    sqrt sinh cosh tanh asin acos atan, pi, E) or a SymPy expression in Symbols of these names.
    Its first and second derivatives are taken symbolically once, here, and compiled: a step
    runs at C++ speed, without calling back into Python. Raises ExpressionError (with the
    offending ``position``) for an expression that does not parse or names something unknown."""

    def __init__(self, expression, coordinates=("q",), parameters=None):
        if isinstance(coordinates, str):
            coordinates = [c.strip() for c in coordinates.split(",")]
        self.coordinates = [str(c) for c in coordinates]
        self.parameters = {str(k): float(v) for k, v in (parameters or {}).items()}
        self.expression = _expression_text(expression)
        self._core = _core._Lagrangian(self.expression, self.coordinates, self.parameters)

    @classmethod
    def from_function(cls, function, coordinates=("q",), parameters=None):
        """A Lagrangian from a Python function ``function(q, v, t, **parameters)`` of SymPy-
        compatible operations (use sympy.sin etc., not math or numpy). The function is called
        once with SymPy symbols, and its result compiled as any expression: prototyping costs
        no speed. (A function that cannot take symbols cannot be used.)"""
        import sympy  # noqa: PLC0415

        if isinstance(coordinates, str):
            coordinates = [c.strip() for c in coordinates.split(",")]
        q = [sympy.Symbol(c) for c in coordinates]
        v = [sympy.Symbol(c + "_dot") for c in coordinates]
        par = {k: sympy.Symbol(k) for k in (parameters or {})}
        return cls(function(q, v, sympy.Symbol("t"), **par), coordinates, parameters)

    @property
    def dimension(self):
        return self._core.dimension

    @property
    def depends_on_time(self):
        """Whether L names t (its energy is then not conserved)."""
        return self._core.depends_on_time

    @property
    def instructions(self):
        """The length of the compiled code of L and all its derivatives."""
        return self._core.instructions

    def __call__(self, q, v, t=0.0):
        return self._core.value(np.atleast_1d(q), np.atleast_1d(v), t)

    def derivatives(self, q, v, t=0.0):
        """L and its derivatives at (q, v, t): a dict with value, L_q, L_v (arrays of d),
        L_qq, L_qv (L_qv[i, j] = ∂²L/∂q_i∂v_j), L_vv (d × d)."""
        return self._core.derivatives(np.atleast_1d(q), np.atleast_1d(v), t)

    def momentum(self, q, v, t=0.0):
        """p = ∂L/∂q̇."""
        return self._core.momentum(np.atleast_1d(q), np.atleast_1d(v), t)

    def velocity(self, q, p, t=0.0):
        """q̇ solving ∂L/∂q̇(q, q̇) = p (ValueError where ∂²L/∂q̇² is singular)."""
        return self._core.velocity(np.atleast_1d(q), np.atleast_1d(p), t)

    def energy(self, q, p, t=0.0):
        """E = q̇ᵀp − L at (q, p, t)."""
        v = self.velocity(q, p, t)
        return float(v @ np.atleast_1d(p) - self(q, v, t))

    def __repr__(self):
        return (f"varsym.Lagrangian({self.expression!r}, {self.coordinates!r}, "
                f"{self.parameters!r})")


class Stepper:
    """A stepper of the general engine (any member of the family) for a Lagrangian, with its
    state: ``step(n)`` advances, ``q``, ``p``, ``t``, ``energy`` read the state, ``run(steps,
    every)`` records a trajectory. Start from q0 with v0 (default 0) or p0.

    scheme: "simpson" (default, the paper's), "newmark", "lobatto" or "gauss" with ``degree``
    (order 2·degree). ``force``: a generalized force, one expression (string or SymPy) per
    coordinate over the Lagrangian's names, e.g. ``["-c*th_dot"]`` for damping (``work`` then
    gives the forces' work, so that E − E0 − work is the scheme's energy balance error).
    ``iteration``: "newton" (default), "simplified" or "fixed-point" (docs/library.md).
    Raises StepFailure (``step``, ``time``) when Newton does not converge, leaving the state at
    the last good step."""

    def __init__(self, lagrangian, h, scheme="simpson", degree=None, q0=None, v0=None, p0=None,
                 t0=0.0, force=None, iteration="newton"):
        if not isinstance(lagrangian, Lagrangian):
            lagrangian = Lagrangian(lagrangian)
        self.lagrangian = lagrangian
        d = lagrangian.dimension
        q0 = np.zeros(d) if q0 is None else np.atleast_1d(np.asarray(q0, dtype=float))
        if p0 is not None and v0 is not None:
            raise UsageError("give v0 or p0, not both")
        if p0 is None:
            v0 = np.zeros(d) if v0 is None else np.atleast_1d(np.asarray(v0, dtype=float))
            lagrangian._core.check_regular(q0, v0, t0)
            p0 = lagrangian.momentum(q0, v0, t0)
        force = [_expression_text(f) for f in (force or [])]
        self._core = _core._Stepper(lagrangian._core, force, float(h), scheme, degree or 0, q0,
                                    np.atleast_1d(np.asarray(p0, dtype=float)), float(t0),
                                    iteration)

    def step(self, n=1):
        """Takes n steps; returns self."""
        self._core.step(n)
        return self

    def run(self, steps, every=1):
        """Takes ``steps`` steps and returns the rows (the current state first, then every
        ``every`` steps and the last) as a dict of arrays: t, q and p (rows × d), energy."""
        return self._core.run(steps, every, True)

    q = property(lambda self: self._core.q, doc="the coordinates q_j")
    p = property(lambda self: self._core.p, doc="the momenta p_j")
    t = property(lambda self: self._core.t, doc="the time t_j")
    h = property(lambda self: self._core.h, doc="the time step")
    steps = property(lambda self: self._core.steps, doc="steps taken")
    energy = property(lambda self: self._core.energy, doc="E = q̇ᵀp − L at (q_j, p_j, t_j)")
    work = property(lambda self: self._core.work, doc="the forces' work since the start")
    mean_newton_iterations = property(lambda self: self._core.mean_newton_iterations)
