"""varsym.optimize: optimal control of a built-in model with inputs, a URDF robot (varsym.Robot) or
a typed Lagrangian with inputs on named coordinates (docs/optimal_control.md)."""

import math
import os

import numpy as np

from . import _checks, _core
from ._lagrangian import Lagrangian
from ._robot import Robot
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


class OptimalControl:
    """The optimal motion optimize returns (or the last iterate, in SolverError.partial).

    At the nodes t (N + 1): q, v, p and costate (λ_p, the discrete adjoint of the momenta), each
    an array (N + 1) × d. At the steps' quadrature points control_t (N r): u, (N r) × m.
    cost; status ("solved", "acceptable", "infeasible", "iteration_limit", "failed",
    "interrupted"); message (IPOPT's); iterations; constraint_violation (varsym's own max |g|);
    controls_at_bound (how many control values sit on their bound); closure (the general
    engine's replay of the controls against q) and trusted (the closure within 1e-6);
    reach_miss, with a reach target, (distance [m], angle [rad]) of the link from its target
    at T (else None); velocity_excess, how far the node velocities v exceed the velocity limits
    relative to them (0: within, as they always are without holonomic constraints).
    ``coordinates`` and ``inputs`` name the columns of q and u. ``result["q"]`` also works."""

    _FIELDS = ("t", "q", "v", "p", "costate", "control_t", "u", "cost", "status", "message",
               "iterations", "constraint_violation", "closure", "trusted", "controls_at_bound",
               "reach_miss", "velocity_excess")

    def __init__(self, raw, name, coordinates, inputs):
        for key in self._FIELDS:
            setattr(self, key, raw[key])
        self.model = name
        self.coordinates = list(coordinates)
        self.inputs = list(inputs)
        self._advice = raw["closure_advice"]

    def __getitem__(self, key):
        if key not in self._FIELDS:
            raise KeyError(key)
        return getattr(self, key)

    def keys(self):
        return list(self._FIELDS)

    def __repr__(self):
        return (f"<OptimalControl {self.model}: {self.status}, cost {self.cost:.10g}, "
                f"N = {len(self.t) - 1}, {self.iterations} iterations, closure {self.closure:.1e}>")

    def animate(self, path, *, mesh_path=(), title=None):
        """Writes the optimal motion of a Robot (Robot.animate) or of a built-in model with a
        figure (the arm; Model.animate) as a 3-D animation page, its nodes as frames (the page
        interpolates between them). Returns a dict: frames, bytes, warnings."""
        robot = getattr(self, "_robot", None)
        if isinstance(robot, Robot):
            return robot.animate(path, self.t, self.q, fps=0.0, mesh_path=mesh_path,
                                 title=title or f"{robot.robot_name}: optimal motion")
        if robot is None:
            raise UsageError(f"animate draws a URDF robot or a built-in model; {self.model} "
                             "is neither")
        if mesh_path:
            raise UsageError(f"mesh_path finds a URDF robot's meshes; {self.model} has none")
        return robot.animate(path, self.t, self.q, fps=0.0,
                             title=title or f"{self.model}: optimal motion")

    def plot(self, path=None):
        """A figure of the coordinates over time and the controls at the quadrature points
        (matplotlib); saved to ``path`` (.png, .svg, .pdf) if given. Returns the figure."""
        import matplotlib  # noqa: PLC0415 (optional: only for pictures)
        if path is not None:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: PLC0415

        fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        for i, name in enumerate(self.coordinates):
            top.plot(self.t, self.q[:, i], label=name)
        top.set_ylabel("q")
        top.set_title(f"{self.model}: optimal motion, cost {self.cost:.6g}")
        top.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize="small")
        for j, name in enumerate(self.inputs):
            bottom.plot(self.control_t, self.u[:, j], ".-", ms=2, label=name)
        bottom.set_ylabel("u")
        bottom.set_xlabel("t [s]")
        bottom.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize="small")
        fig.tight_layout()
        if path is not None:
            fig.savefig(os.fspath(path), dpi=120)
            plt.close(fig)
        return fig


def optimize(model, *, time, q_start, q_end=None, v_start=None, v_end=None, steps=50,
             scheme="simpson", degree=None, max_control=None, cost="effort", free_end=None,
             hessian="automatic", max_iterations=3000, refine=0, progress=False,
             ipopt_options=None, inputs=None, constraints=None, limits=True, reach=None,
             reach_position=None, reach_rpy=None, reach_weight=0.0, max_velocity=None,
             threads=0, **parameters):
    """The controls that take ``model`` from (q_start, v_start) at t = 0 to (q_end, v_end) at
    t = ``time`` at the least cost, by discrete mechanics and optimal control with ``steps``
    steps of ``scheme`` (velocities default to rest). ``model``: a name or Model with inputs
    ("acrobot", "arm", "cart-pole", "pendulum"); a varsym.Robot (the inputs: the torques of its
    actuated joints, those with URDF effort > 0, bounded by their efforts; the joints' position
    and velocity limits bound q and q̇; ``limits=False`` drops them); or a varsym.Lagrangian
    with ``inputs``, the names of the coordinates the controls act on (a generalized force
    each), and optionally ``constraints``, holonomic constraints g(q) = 0 as expressions over its
    coordinates and parameters (e.g. ["x**2 + y**2 - l**2"]; q_start and q_end must meet them).
    ``cost``: "effort" (∫ u²/2), "invariant" (∫ τᵀM⁻¹τ/2), "power" (∫ Σ|τ_i
    q̇_i|, smoothed), "time" (minimum time: ``time`` is then the first guess of a free horizon;
    needs ``max_control``, or a Robot's URDF efforts), or a dict of weights such as {"power": 1, "effort": 0.01}.
    ``max_control``: a bound |u| ≤ U on every input (over a robot's efforts); ``max_velocity``:
    |q̇| ≤ V on every coordinate at the nodes and the steps' quadrature points (over a robot's URDF
    velocity limits). ``free_end``:
    final coordinates left free, "q1", "v2", … (from 1) in a list or string, or a dict of them
    to terminal weights w, each adding w (x(T) − its q_end or v_end)²/2 to the cost.
    ``reach``: a varsym.Robot's link whose frame must be at ``reach_position`` (x, y, z [m],
    world frame) and, if given, at the orientation ``reach_rpy`` (URDF roll, pitch, yaw [rad])
    at T, instead of the joints at q_end (then optional, only the first guess of q(T)); with
    ``reach_weight`` w > 0 a terminal cost w/2 (|miss|² + (2 sin(angle/2))²) instead of exactly.
    ``refine``: K levels of mesh refinement (solve with steps/2^K first, then double up to
    ``steps``, each from the previous solution). ``progress``: True for a bar, or a function
    progress(iteration, cost, infeasibility). Returns an OptimalControl. Raises SolverError
    (``partial``: the last iterate) when it is not solved, or when the replay misses the
    optimal motion by more than 1e-6 (steps too coarse for the motion: the optimum rides on a
    spurious root of the step equations), and varsym.Interrupted (``partial``) on Ctrl-C.
    ``ipopt_options``: an IPOPT options file (its ipopt.opt format), read over varsym's
    options; IPOPT reads no other. Whatever it loosens, the answer must pass varsym's own check
    (the equations re-evaluated, the bounds, every boundary value and the replay), or
    SolverError. ``threads``: the threads for a Robot's step derivatives (0: one per CPU the
    process may use, fewer on small problems; 1: none); the same answer to the bit with any."""
    if isinstance(model, Lagrangian):
        if parameters:
            raise UsageError("optimize: a Lagrangian's parameters are given when it is made: "
                             "Lagrangian(expression, coordinates, {name: value})")
        if inputs is None:
            raise UsageError("optimize: a Lagrangian needs inputs, the coordinates the controls "
                             "act on, e.g. inputs=[\"th1\", \"th2\"]")
        inputs = [inputs] if isinstance(inputs, str) else [str(x) for x in inputs]
        constraints = [] if constraints is None else (
            [constraints] if isinstance(constraints, str) else [str(x) for x in constraints])
        source, values, lists = model._core, [], []
        name, d, coordinates, names = "lagrangian", len(model.coordinates), model.coordinates, \
            inputs
    else:
        if inputs is not None or constraints is not None:
            raise UsageError("optimize: inputs= and constraints= are a Lagrangian's; a model's "
                             "inputs and constraints are its own")
        if isinstance(model, Robot):
            m = Robot(model, **parameters) if parameters else model
            source = m._core
            effort = np.asarray(m.limits["effort"])
            names = [j for j, e in zip(m.joints, effort) if e > 0]  # the actuated joints
        else:
            m = model if isinstance(model, Model) else Model(model, **parameters)
            if isinstance(model, Model) and parameters:
                m = Model(model, **parameters)
            source = m.name
        values, lists = m._values(), m._lists()
        name, d = (m.robot_name if isinstance(m, Robot) else m.name), m.dim
        coordinates = list(getattr(m, "coordinates", None) or
                           [f"q{i + 1}" for i in range(d)])
        if not isinstance(model, Robot):
            names = None
    if reach is None:
        if reach_position is not None or reach_rpy is not None or reach_weight:
            raise UsageError("optimize: reach_position, reach_rpy and reach_weight need reach, "
                             "a robot's link")
        if q_end is None:
            raise UsageError(f"optimize: q_end is required ({d} values), or reach= a link")
    else:
        if not isinstance(model, Robot):
            raise UsageError("optimize: reach names a link of a robot: give a varsym.Robot")
        if reach_position is None:
            raise UsageError("optimize: reach needs reach_position, the link origin's target "
                             "(x, y, z) [m]")
        if q_end is None:
            q_end = q_start
    weights = _costs(cost)
    if weights["time"] > 0 and max_control is None and not (isinstance(model, Robot) and limits):
        raise UsageError("optimize: a cost on the time needs max_control, or a Robot's URDF "
                         "efforts with limits=True (with unbounded inputs the motion can be made "
                         "as fast as one likes)")
    bar, callback = None, progress if callable(progress) else None
    if progress is True:
        from tqdm import tqdm
        bar = tqdm(desc=f"optimize {name}", unit=" it")

        def callback(iteration, value, infeasibility):
            bar.update(1)
            bar.set_postfix(cost=f"{value:.6g}", infeasibility=f"{infeasibility:.1e}")
    try:
        raw = _core.optimize(source, names if isinstance(model, Lagrangian) else [],
                             constraints if isinstance(model, Lagrangian) else [], bool(limits),
                             values, lists, float(time),
                             int(steps), scheme, degree or 0,
                             _vector(q_start, d, "q_start"), _vector(v_start, d, "v_start", 0.0),
                             _vector(q_end, d, "q_end"), _vector(v_end, d, "v_end", 0.0),
                             math.inf if max_control is None else float(max_control),
                             *weights.values(), *_free_end(free_end, d), hessian,
                             int(max_iterations), int(refine), callback,
                             "" if ipopt_options is None else os.fspath(ipopt_options),
                             "" if reach is None else str(reach),
                             _vector(reach_position, 3, "reach_position", 0.0),
                             None if reach_rpy is None else _vector(reach_rpy, 3, "reach_rpy"),
                             float(reach_weight),
                             math.inf if max_velocity is None else float(max_velocity),
                             _checks.count(threads, "threads", 0, 4096))
    finally:
        if bar is not None:
            bar.close()
    m_inputs = raw["u"].shape[1] if raw["u"].ndim == 2 else 1
    out = OptimalControl(raw, name, coordinates,
                         names or [f"u{j + 1}" for j in range(m_inputs)])
    # What animate draws: the Robot or the built-in Model (at these parameters) that moved.
    out._robot = None if isinstance(model, Lagrangian) else m
    if raw["interrupted"]:
        raise Interrupted(f"optimize interrupted after {out.iterations} iterations; the last "
                          "iterate is in .partial", partial=out)
    if raw["verdict"] != "solved":  # not solved, not trusted, or a minimum time at its bound
        raise SolverError(f"optimize: {raw['verdict_message']}".replace("--steps", "steps"),
                          partial=out)
    return out
