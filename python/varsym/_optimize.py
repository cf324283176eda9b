"""varsym.optimize: optimal control of a built-in model with inputs (docs/optimal_control.md)."""

import math
import os

import numpy as np

from . import _core
from ._simulate import Model
from .errors import Error, Interrupted, UsageError


class SolverError(Error, RuntimeError):
    """The optimizer did not solve the problem (tool exit code 3): ``status`` is "infeasible"
    (no motion meets the boundary states within the bounds near the iterates), "iteration_limit"
    or "failed"; or it did, but the simulator's replay of the controls misses the optimal motion
    (``status`` "solved", ``partial["trusted"]`` False: take more steps). ``partial`` holds the
    last iterate, a dict as optimize returns."""

    def __init__(self, message, partial=None):
        super().__init__(message)
        self.partial = partial
        self.status = partial["status"] if partial else None


def _vector(x, d, name, default=None):
    if x is None:
        if default is None:
            raise UsageError(f"optimize: {name} is required ({d} values)")
        return np.full(d, default, dtype=float)
    v = np.atleast_1d(np.asarray(x, dtype=float)).ravel()
    if v.size != d:
        raise UsageError(f"optimize: {name} needs {d} values, got {v.size}")
    return v


def _costs(cost):
    """"effort", "invariant", "power", or a dict {term: weight}."""
    if isinstance(cost, str):
        cost = {term: 1.0 for term in cost.split(",")}
    weights = {"effort": 0.0, "invariant": 0.0, "power": 0.0, "time": 0.0}
    for term, weight in dict(cost).items():
        if term not in weights:
            raise UsageError(f"optimize: unknown cost term {term!r}; the terms are effort, "
                             "invariant, power and time")
        weights[term] = float(weight)
    return weights


def _free_end(free_end, d):
    """free_end as (free q flags, free v flags, q weights, v weights): names "q1", "v2", … (from
    1) in a list or a comma-separated string (weight 0), or a dict name -> terminal weight."""
    if free_end is None:
        free_end = {}
    if isinstance(free_end, str):
        free_end = [x for x in free_end.split(",") if x]
    if not isinstance(free_end, dict):
        free_end = {name: 0.0 for name in free_end}
    free = {"q": [False] * d, "v": [False] * d}
    weights = {"q": np.zeros(d), "v": np.zeros(d)}
    for name, weight in free_end.items():
        kind, index = str(name)[:1], str(name)[1:]
        if kind not in free or not index.isdigit() or not 1 <= int(index) <= d:
            raise UsageError(f"optimize: free_end: {name!r} is not a coordinate: give q1 … q{d} "
                             f"(positions) or v1 … v{d} (velocities)")
        if not (math.isfinite(float(weight)) and float(weight) >= 0):
            raise UsageError(f"optimize: free_end: the weight of {name} must be a number >= 0")
        free[kind][int(index) - 1] = True
        weights[kind][int(index) - 1] = float(weight)
    return free["q"], free["v"], weights["q"], weights["v"]


def optimize(model, *, time, q_start, q_end, v_start=None, v_end=None, steps=50,
             scheme="simpson", degree=None, max_control=None, cost="effort", free_end=None,
             hessian="automatic", max_iterations=3000, refine=0, progress=False,
             ipopt_options=None, **parameters):
    """The controls that take ``model`` (a name or a Model with inputs: "acrobot", "cart-pole",
    "pendulum")
    from (q_start, v_start) at t = 0 to (q_end, v_end) at t = ``time`` at the least cost, by
    discrete mechanics and optimal control with ``steps`` steps of ``scheme`` (velocities
    default to rest). ``cost``: "effort" (∫ u²/2), "invariant" (∫ τᵀM⁻¹τ/2), "power" (∫ Σ|τ_i
    q̇_i|, smoothed), "time" (minimum time: ``time`` is then the first guess of a free horizon;
    needs ``max_control``), or a dict of weights such as {"power": 1, "effort": 0.01}.
    ``max_control``: a bound |u| ≤ U on every input. ``free_end``: final coordinates left free,
    "q1", "v2", … (from 1) in a list or string, or a dict of them to terminal weights w, each
    adding w (x(T) − its q_end or v_end)²/2 to the cost. ``refine``: K levels of mesh refinement
    (solve with steps/2^K first, then double up to ``steps``, each from the previous
    solution). ``progress``: True for a bar, or a function progress(iteration, cost,
    infeasibility). Returns a dict of arrays: t, q, v, p and costate
    (λ_p) at the nodes; control_t and u at the quadrature points; cost, status, message,
    iterations, constraint_violation (varsym's max |g|), controls_at_bound (how many control
    values sit on max_control) and closure (the general engine's replay of the controls
    against the nodes). Raises SolverError (``partial``: the last iterate) when it is not
    solved, or when the replay misses the optimal motion by more than 1e-6 (steps too coarse
    for the motion: the optimum rides on a spurious root of the step equations), and
    varsym.Interrupted (``partial``) on Ctrl-C. ``ipopt_options``: an IPOPT options file (its
    ipopt.opt format), read over varsym's options; IPOPT reads no other. Whatever it loosens,
    the answer must pass varsym's own check (the equations re-evaluated, the bounds, every
    boundary value and the replay), or SolverError."""
    m = model if isinstance(model, Model) else Model(model, **parameters)
    if isinstance(model, Model) and parameters:
        m = Model(model, **parameters)
    d = m.dim
    weights = _costs(cost)
    if weights["time"] > 0 and max_control is None:
        raise UsageError("optimize: a cost on the time needs max_control (with unbounded inputs "
                         "the motion can be made as fast as one likes)")
    bar, callback = None, progress if callable(progress) else None
    if progress is True:
        from tqdm import tqdm
        bar = tqdm(desc=f"optimize {m.name}", unit=" it")

        def callback(iteration, value, infeasibility):
            bar.update(1)
            bar.set_postfix(cost=f"{value:.6g}", infeasibility=f"{infeasibility:.1e}")
    try:
        out = _core.optimize(m.name, m._values(), m._lists(), float(time), int(steps), scheme, degree or 0,
                             _vector(q_start, d, "q_start"), _vector(v_start, d, "v_start", 0.0),
                             _vector(q_end, d, "q_end"), _vector(v_end, d, "v_end", 0.0),
                             math.inf if max_control is None else float(max_control),
                             *weights.values(), *_free_end(free_end, d), hessian,
                             int(max_iterations), int(refine), callback,
                             "" if ipopt_options is None else os.fspath(ipopt_options))
    finally:
        if bar is not None:
            bar.close()
    if out["interrupted"]:
        raise Interrupted(f"optimize interrupted after {out['iterations']} iterations; the last "
                          "iterate is in .partial", partial=out)
    if out["status"] not in ("solved", "acceptable"):
        raise SolverError(f"optimize: {out['status']}: {out['message']}", partial=out)
    if not out["trusted"]:
        raise SolverError(f"optimize: not trusted: {out['closure_advice']}".replace("--steps",
                                                                                    "steps"),
                          partial=out)
    return out
