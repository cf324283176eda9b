"""Your own system: a Lagrangian from an expression (a string or a SymPy expression), compiled
once into C++ code with exact symbolic derivatives (varsym.Stepper and varsym.simulate step it)."""

import numpy as np

from . import _checks, _core
from ._members import _ensemble_result, _member_arrays
from .errors import UsageError


def _expression_text(expression):
    if isinstance(expression, str):
        return _checks.ascii_expression(expression)
    try:
        import sympy  # noqa: PLC0415 (optional: only for SymPy input)
    except ImportError as e:  # pragma: no cover
        raise UsageError("a Lagrangian is a string, or a SymPy expression (python3-sympy)") from e
    if not isinstance(expression, sympy.Basic):
        raise UsageError(
            f"a Lagrangian is a string or a SymPy expression, not {type(expression).__name__}"
            " (for a Python function, use Lagrangian.from_function)")
    return sympy.sstr(expression, full_prec=True)


def _force_list(force):
    """A generalized force as the list of its components' expressions (a single expression
    or SymPy object: d = 1; None: no force)."""
    if isinstance(force, (str, bytes)) or (force is not None and not np.iterable(force)):
        force = [force]
    return [_expression_text(f) for f in (force or [])]


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
        """Whether L depends on t (∂L/∂t is not identically zero): its energy E then changes
        by −∫∂L/∂t dt, which a run's ``work`` column holds (E − E0 − work is kept)."""
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

    def ensemble(self, q0=None, p0=None, *, parameters=None, force=None, constraints=None,
                 project=False, t_span=10.0, steps=1000, scheme=None, degree=None,
                 indicators=True, threads=0, event=None):
        """Runs one member per row on every CPU (``threads``: 0 = all it may use), as Model.ensemble
        does: ``q0`` and ``p0`` are (members × d) arrays of initial states (default: q = 0,
        q̇ = 0), ``parameters`` maps parameter names to one value per member (the others stay
        at this Lagrangian's), ``force`` a generalized force and ``constraints`` holonomic
        constraints as for varsym.simulate (``project``: move each start onto them). Each
        member runs ``steps`` steps over ``t_span``. Returns the same dict of arrays: status,
        t, q, p, lyapunov, mean_megno, max_energy_error, event_time, cause."""
        # The compiled Lagrangian holds its parameters sorted by name (a std::map).
        values, q0, p0 = _member_arrays("ensemble", parameters, self.parameters,
                                        sorted(self.parameters), q0, p0, self.dimension)
        if project is not False and constraints is None:
            raise UsageError("project=True moves each start onto the constraints: it needs "
                             "constraints=")
        if constraints is not None:  # the model's flag `project` follows L's parameters
            values = np.column_stack([values, np.full(len(values), float(bool(project)))])
        steps = _checks.count(steps, "steps")
        t_span = _checks.positive(t_span, "t_span")
        return _ensemble_result(_core.expression_ensemble(
            self._core, _force_list(force), _force_list(constraints), values, q0, p0,
            t_span / steps, steps, scheme or "simpson", _checks.degree(degree) or 0, indicators,
            _checks.count(threads, "threads", 0, 4096), event or ""))

    def __repr__(self):
        return (f"varsym.Lagrangian({self.expression!r}, {self.coordinates!r}, "
                f"{self.parameters!r})")
