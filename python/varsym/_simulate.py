"""varsym.simulate, Model and Stepper: the models layer's simulations bound directly (no command
line, no temporary file). A run's rows go straight from the C++ loop into NumPy arrays allocated
once; Ctrl-C stops it within 0.2 s keeping them (varsym.Interrupted); ``progress=True`` shows a
tqdm bar."""

import difflib
import math
import os
import sys

import numpy as np

from . import _checks, _core
from ._lagrangian import Lagrangian, _force_list
from ._members import _ensemble_result, _keyword_error, _member_arrays
from ._trajectory import Trajectory
from .errors import EnergyError, Interrupted, StepFailure, UsageError

_REGISTRY = {m["name"]: m for m in _core.registry()}


def _vector(value, d, name, short=()):
    """value as a list of d floats ([] for None); `short`: other lengths the model completes
    (the four-bar's q0 = th1 alone)."""
    if value is None:
        return []
    v = np.atleast_1d(np.asarray(value, dtype=float)).ravel()
    if len(v) != d and len(v) not in short:
        others = "".join(f" or {k}" for k in short)
        raise UsageError(f"{name} needs {d}{others} value{'s' if d != 1 else ''}, got {len(v)}")
    return v.tolist()


class Model:
    """A built-in model with its parameters set, e.g. ``Model("kepler", eccentricity=0.6)``.
    ``varsym.models()`` lists the models; ``Model(name).parameters`` holds every parameter's
    value, and ``info`` its defaults, units, meaning and range. A parameter that is not the
    model's raises TypeError naming the closest ones."""

    def __init__(self, name, **parameters):
        if isinstance(name, Model):
            parameters = {**name.parameters, **parameters}
            name = name.name
        if name not in _REGISTRY:
            near = difflib.get_close_matches(str(name), list(_REGISTRY), n=1)
            hint = f"; did you mean {near[0]!r}?" if near else ""
            raise UsageError(f"no model {name!r}{hint} The models: {', '.join(_REGISTRY)}")
        self._set(name, _REGISTRY[name], parameters)

    def _set(self, name, info, parameters):
        """The model `name` of data `info` (as the registry's) at these parameters."""
        self.name = name
        self.info = info
        names = [p["name"] for p in self.info["parameters"]]
        list_names = [p["name"] for p in self.info["lists"]]
        for key in parameters:
            if key not in names + list_names:
                raise _keyword_error(f"Model({name!r})", key, names + list_names)
        self.parameters = {p["name"]: float(parameters.get(p["name"], p["default"]))
                           for p in self.info["parameters"]}
        # Parameters of several values (the arm's masses, one per link): None is the default.
        for p in self.info["lists"]:
            given = parameters.get(p["name"])
            self.parameters[p["name"]] = (None if given is None else
                                          np.atleast_1d(np.asarray(given, float)).ravel().tolist())
        # The ranges first: d follows from some (the chain's n), and a d out of range must be
        # refused before anything of that size is made (n = 2e7 took 2.8 GB, then refused).
        if name in _REGISTRY:
            _core.check_parameters(name, self._values(), self._lists())
        # d, where a parameter sets it (the chain's n, the arm's masses), follows from it.
        self.dim = self.info["dim"]
        for p in self.info["parameters"]:
            if p["sets_dimension"]:
                self.dim = int(self.parameters[p["name"]])
        for p in self.info["lists"]:
            if p["sets_dimension"] and self.parameters[p["name"]] is not None:
                self.dim = len(self.parameters[p["name"]])
        self.coordinates = [c.strip() for c in self.info["coordinates"].split(",")]
        if len(self.coordinates) != self.dim:  # "q_1 ... q_n"
            self.coordinates = [f"q_{i + 1}" for i in range(self.dim)]

    def problem(self, q0=None, p0=None, v0=None):
        """The model at its parameters from (q0, p0 or v0; each default: the model's): its
        complete initial state (``q0``, ``p0``) and ``period`` (0 where it has none)."""
        d, short = self.dim, self.info["short_start"]
        return self._prepare(self._values(), _vector(q0, d, "q0", short), _vector(p0, d, "p0"),
                             _vector(v0, d, "v0", short), self._lists())

    def _prepare(self, values, q0, p0, v0, lists):
        return _core.prepare(self.name, values, q0, p0, v0, lists)

    def _ensemble(self, *args):
        return _core.ensemble(self.name, *args)

    def _with(self, **parameters):
        """This model (of the same kind) with these parameters changed."""
        return type(self)(self, **parameters)

    def _values(self):
        return [self.parameters[p["name"]] for p in self.info["parameters"]]

    def _lists(self):
        return [self.parameters[p["name"]] or [] for p in self.info["lists"]]

    def animate(self, path, t, q, *, fps=60.0, title=None):
        """Writes the motion through rows ``q`` (len(t) × d coordinates, a rigid body's
        z-x-z Euler angles) at times ``t`` as a 3-D animation: one self-contained HTML page
        that any browser opens offline (docs/robots.md). The models drawn are those whose
        ``info["drawn"]`` is true (the heavy top, top, 3-D pendulum, rigid body, spherical and
        double pendulums, the arm). ``fps``: frames kept per second of the motion's time (0:
        every row). Returns a dict: frames, bytes, warnings."""
        if not self.info.get("drawn"):
            drawn = ", ".join(n for n, m in _REGISTRY.items() if m.get("drawn"))
            raise UsageError(f"{self.name} has no 3-D figure; the models drawn: {drawn}, and "
                             f"URDF robots (varsym.Robot)")
        q = np.asarray(q, dtype=float)
        if q.ndim == 1:
            q = q[:, None]
        try:
            return dict(_core.animate_model(self.name, self._values(), self._lists(),
                                            np.asarray(t, dtype=float).ravel().tolist(), q,
                                            os.fspath(path), float(fps), title or "",
                                            list(self.coordinates)))
        except ValueError as e:
            raise UsageError(str(e)) from None

    def stepper(self, h, scheme=None, degree=None, q0=None, p0=None, v0=None,
                iteration="automatic", max_energy_error=None):
        """A Stepper of this model with step h from (q0, p0 or v0)."""
        return Stepper(self, h, scheme=scheme, degree=degree, q0=q0, p0=p0, v0=v0,
                       iteration=iteration, max_energy_error=max_energy_error)

    def simulate(self, **options):
        """varsym.simulate(this model, **options)."""
        return simulate(self, **options)

    def ensemble(self, parameters=None, q0=None, p0=None, *, t_span=None, steps=None,
                 scheme=None, degree=None, indicators=True, threads=0, event=None):
        """Runs one member per row, on every CPU (``threads``: 0 = all it may use):
        ``parameters`` maps parameter names to arrays of one value per member (the others stay
        at this model's),
        ``q0`` and ``p0`` are (members × d) arrays of initial states (default: the model's).
        Returns a dict of arrays, one entry per member: status ("completed", "failed",
        "invalid"), t, q and p (the final state), lyapunov (maximal Lyapunov exponent),
        mean_megno (⟨Y⟩: 2 on a torus, growing in chaos; docs/ensembles.md), max_energy_error,
        event_time, cause (why a member failed or was invalid). ``event``: an expression in
        q1..qd, p1..pd and t (as the tool's ``--event``) whose change of sign stops a member
        (status "event", at ``event_time``, located to O(h²))."""
        contact = self.parameters.get("contact") or (
            parameters is not None and "contact" in parameters
            and bool(np.any(np.asarray(parameters["contact"], dtype=float) != 0)))
        if contact and indicators:
            raise UsageError("with contact a step has no tangent map for lyapunov and "
                             "mean_megno: give indicators=False")
        values, q0, p0 = _member_arrays("ensemble", parameters, self.parameters,
                                        [p["name"] for p in self.info["parameters"]], q0, p0,
                                        self.dim)
        time = (self.info["ensemble_time"] if t_span is None
                else _checks.positive(t_span, "t_span"))
        steps = self.info["ensemble_steps"] if steps is None else _checks.count(steps, "steps")
        self._refuse_scheme(scheme, degree)
        return _ensemble_result(self._ensemble(values, q0, p0, time / steps, steps,
                                               scheme or "simpson", _checks.degree(degree) or 0,
                                               indicators,
                                               _checks.count(threads, "threads", 0, 4096),
                                               event or "", self._lists()))

    def _refuse_scheme(self, scheme, degree):
        """Raises UsageError where a scheme or degree is given to a model with its own
        integrator (the rigid bodies')."""
        if self.info["integrator_note"] and (scheme is not None or degree is not None):
            raise UsageError(f"{self.name}: scheme and degree do not apply: "
                             f"{self.info['integrator_note']} (order=2|4|6)")

    def __repr__(self):
        par = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                        for k, v in self.parameters.items() if v is not None)
        return f"varsym.Model({self.name!r}{', ' if par else ''}{par})"


class Stepper:
    """A model or Lagrangian stepped by one scheme, with its state: ``step(n)`` advances,
    ``run(steps, every)`` records a Trajectory; ``q``, ``p``, ``t``, ``energy`` read the state;
    ``tangent_map()`` gives ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) at it; ``section(...)`` Poincaré
    crossings from it.

    ``system``: a built-in model's name, a Model, or a Lagrangian (or its expression). scheme:
    "simpson" (default, the paper's), "newmark", "lobatto" or "gauss" with ``degree`` (order
    2·degree). The rigid bodies (rigid-body, top, pendulum-3d) have their own integrator, the
    Lie group one of the parameter ``order`` (2, 4, 6), and refuse a scheme; their q is the
    z-x-z Euler angles, p the body angular momentum Π, and their rows also hold the attitude
    quaternion q_w..q_z and Ω. Start from q0 with p0 or v0 (defaults: the model's, or zero for a Lagrangian).
    ``force``: for a Lagrangian, a generalized force, one expression per coordinate, e.g.
    ``["-c*th_dot"]`` (``work`` then gives the forces' work: E − E0 − work is the scheme's
    energy balance error). ``constraints``: for a Lagrangian, holonomic constraints g(q) = 0,
    one expression per equation, e.g. ``["x**2 + y**2 - l**2"]``: the constrained engine then
    steps it (Newton on the saddle-point system), the rows adding constraint_residual,
    hidden_residual and the multipliers lambda_1..m; the start must lie on the constraints with
    a tangent velocity, or ``project=True`` moves it there (for a constrained model, ``project``
    is its parameter of that name). ``iteration``: "automatic" (the default; on URDF robots of
    about 10 joints and more with gauss-2 and Simpson, fewer at higher degrees, Newton or
    "articulated" step by step, whichever is cheaper),
    "newton", "simplified", "fixed-point" or "articulated" (URDF robots: O(n) per iterate),
    optionally followed by "+forces" (start each step from the previous step's forces, as
    Hairer's gni_irk2: fewer iterations, round-off adding up as √t) or "+previous" (the
    previous step's polynomial); the starts are the separable models' (docs/library.md).
    Raises StepFailure when a step does not converge, leaving the state at the last good step.

    The energy watch, as the tool's: a run stops with EnergyError (its ``partial`` holding the
    rows) once the relative error of E (E − W under forces) passes ``max_energy_error``;
    default 100 (h ω)^order at the start, between 0.01 and 0.5; 0 turns it off. It is off
    where the energy is not conserved; for a typed L that depends on t it follows E − W with
    W = −∫∂L/∂t dt (plus the forces' work)."""

    def __init__(self, system, h, scheme=None, degree=None, q0=None, v0=None, p0=None,
                 t0=0.0, force=None, iteration="automatic", max_energy_error=None,
                 constraints=None, project=False, **parameters):
        self.h = _checks.positive(h, "h")
        self._max_energy_error = max_energy_error
        chosen = (scheme, degree)  # as given: a model with its own integrator refuses them
        degree = _checks.degree(degree)
        scheme = scheme or "simpson"
        self._order = _core.scheme_order(scheme, degree or 0)
        if isinstance(system, (str, Model)) and not (isinstance(system, str)
                                                     and system not in _REGISTRY
                                                     and "_dot" in system):
            if project is not False:  # the constrained models' parameter of that name
                parameters = {**parameters, "project": project}
            if force is not None or constraints is not None:
                raise UsageError("force= and constraints= are for a Lagrangian; a model's forces "
                                 "and constraints are its own")
            if t0 != 0.0:
                raise UsageError("t0 is for a Lagrangian; a model starts at t = 0")
            self.model = (system._with(**parameters) if isinstance(system, Model)
                          else Model(system, **parameters))
            self.lagrangian = None
            self.coordinates = self.model.coordinates
            problem = self.model.problem(q0, p0, v0)
            self.model._refuse_scheme(*chosen)
            if problem.integrator is not None:  # the model's own (the rigid bodies')
                self._order = problem.integrator[1]
            self._sim = problem.simulate(self.h, scheme, degree or 0, iteration)
            self._watch(problem.period)
            return
        if parameters:
            raise _keyword_error("Stepper", next(iter(parameters)),
                                 ["scheme", "degree", "q0", "v0", "p0", "t0", "force",
                                  "iteration", "max_energy_error", "constraints", "project"])
        if not isinstance(system, Lagrangian):
            system = Lagrangian(system)
        self.model = None
        self.lagrangian = system
        self.coordinates = system.coordinates
        d = system.dimension
        q0 = np.zeros(d) if q0 is None else np.asarray(_vector(q0, d, "q0"))
        if p0 is not None and v0 is not None:
            raise UsageError("give v0 or p0, not both")
        if p0 is None:
            v0 = np.zeros(d) if v0 is None else np.asarray(_vector(v0, d, "v0"))
            system._core.check_regular(q0, v0, t0)
            p0 = system.momentum(q0, v0, t0)
        if project is not False and constraints is None:
            raise UsageError("project=True moves the start onto the constraints: it needs "
                             "constraints=")
        if constraints is not None:
            self._sim = _core.simulate_constrained_expression(
                system._core, _force_list(constraints), _force_list(force), list(q0),
                _vector(p0, d, "p0"), float(t0), self.h, scheme, degree or 0, iteration,
                bool(project))
        else:
            self._sim = _core.simulate_expression(system._core, _force_list(force), list(q0),
                                                  _vector(p0, d, "p0"), float(t0), self.h,
                                                  scheme, degree or 0, iteration)
        self._watch(0.0)

    def _watch(self, period):
        """The energy watch's reference (E at the start) and bound."""
        sim = self._sim
        self._e0 = sim.watched_energy
        if not sim.conserves_energy:
            self._bound = 0.0
        elif self._max_energy_error is not None:
            self._bound = float(self._max_energy_error)
            if not (math.isfinite(self._bound) and self._bound >= 0):
                raise UsageError("max_energy_error must be >= 0 (0 turns the watch off)")
        else:
            omega = sim.highest_frequency
            omega = omega if omega >= 0 else 0.0  # NaN: no estimate
            if period > 0:
                omega = max(omega, 2 * math.pi / period)
            self._bound = _core.default_energy_bound(self._order, self.h, omega)

    def step(self, n=1):
        """Takes n steps (Ctrl-C stops them within 0.2 s, raising Interrupted); returns self."""
        self.run(n, every=0)
        return self

    def run(self, steps, every=1, progress=False):
        """Takes ``steps`` steps and returns their rows as a Trajectory: the current state first,
        then every ``every`` steps and the last (every = 0: the last only). ``progress``: True
        for a progress bar (tqdm), or a function called as progress(steps_done, steps) about
        every 50 ms. Ctrl-C raises Interrupted, whose ``partial`` holds the rows so far."""
        steps = _checks.count(steps, "steps", 0)
        every = _checks.count(every, "every", 0)
        sim = self._sim
        first = sim.step
        last = first + steps
        # The rows: the current state, then the steps j with j % every == 0, and the last.
        start = -(-(first + 1) // every) * every if every else last + 1
        regular = max(0, (last - start) // every + 1) if every and start <= last else 0
        ends_off = steps > 0 and (regular == 0 or start + (regular - 1) * every != last)
        rows = 1 + regular + (1 if ends_off else 0)

        def index():
            out = np.empty(rows, dtype=np.int64)
            out[0] = first
            if regular:
                out[1:1 + regular] = np.arange(start, start + regular * every, every)
            if ends_off:
                out[-1] = last
            return out

        d, names = sim.dim, list(sim.columns)
        t, q, p = np.empty(rows), np.empty((rows, d)), np.empty((rows, d))
        cols = np.empty((rows, len(names)))
        t[0], q[0], p[0], cols[0] = sim.t, sim.q, sim.p, sim.values
        bar, callback = _progress(progress, steps, first)
        interrupted = False
        try:
            done, interrupted, energy, error = sim.record(last, every, t, q, p, cols, 1,
                                                          callback, self._e0, self._bound)
        except StepFailure as e:
            done = e.rows or 1
            e.partial = self._trajectory(t, q, p, cols, names, index, done)
            raise
        finally:
            if bar is not None:
                bar.update(sim.step - first - bar.n)
                bar.close()
        tr = self._trajectory(t, q, p, cols, names, index, done)
        if energy:
            raise EnergyError(
                f"the relative energy error reached {error:.3g} at step {sim.step} (t = "
                f"{sim.t:.6g}), above max_energy_error {self._bound:.3g}: the trajectory is no "
                f"longer meaningful; take a smaller h (0 turns this check off). The rows so far "
                f"are in .partial", tr)
        if interrupted:
            raise Interrupted(f"interrupted at step {sim.step} (t = {sim.t:.9g}); the rows so far "
                              f"are in .partial, the stepper in .stepper", tr, self)
        return tr

    def _trajectory(self, t, q, p, cols, names, index, n):
        tr = Trajectory(t[:n], q[:n], p[:n], {k: cols[:n, i] for i, k in enumerate(names)},
                        self.coordinates, lambda: index()[:n])
        tr.model = self.model  # the Model that made it (None for a bare Lagrangian)
        return tr

    def tangent_map(self):
        """The 2d × 2d Jacobian ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) of the next step (symplectic:
        JᵀΩJ = Ω); the state is not changed. The rigid bodies' integrator has none
        (UsageError)."""
        if not self._sim.has_tangent_map:
            raise UsageError("this model's integrator (the rigid bodies' Lie group one) has no "
                             "tangent map")
        return self._sim.tangent_map()

    def section(self, plane="q1=0", direction="+", steps=10000, crossings=100):
        """Where the orbit from the current state crosses ``plane`` ("qI=VALUE" or
        "pI=VALUE", I from 1) in ``direction`` ("+", "-" or "both") within ``steps`` steps:
        (times, states) with states (crossings × 2d, q then p). Needs a stepper with dense
        output (not the rigid bodies' or the constrained mechanisms'); the state is not
        changed."""
        try:
            lhs, value = plane.split("=")
            momentum = lhs[0] == "p"
            index = int(lhs[1:]) - 1
            value = float(value)
            if lhs[0] not in "qp" or not 0 <= index < self._sim.dim:
                raise ValueError
        except ValueError:
            raise UsageError(f"plane {plane!r}: give qI=VALUE or pI=VALUE, I from 1 to "
                             f"{self._sim.dim}") from None
        if direction not in ("+", "-", "both"):
            raise UsageError("direction: '+', '-' or 'both'")
        if not self._sim.has_dense_output():
            raise UsageError("this model's stepper has no dense output for sections")
        times, states, _, stopped = self._sim.section(momentum, index, value,
                                                      {"+": 1, "-": -1, "both": 0}[direction],
                                                      _checks.count(steps, "steps"),
                                                      _checks.count(crossings, "crossings"))
        if stopped:
            raise Interrupted(f"section interrupted after {len(times)} crossings; they are in "
                              ".partial (times, states)", partial=(times, states))
        return times, states

    q = property(lambda self: self._sim.q, doc="the coordinates q_j")
    p = property(lambda self: self._sim.p, doc="the momenta p_j")
    t = property(lambda self: self._sim.t, doc="the time t_j")
    steps = property(lambda self: self._sim.step, doc="steps taken")
    columns = property(lambda self: list(self._sim.columns), doc="the model's own columns")
    values = property(lambda self: dict(zip(self._sim.columns, self._sim.values)),
                      doc="the model's own columns at the current state")
    energy = property(lambda self: self.values["energy"], doc="E at (q_j, p_j, t_j)")
    work = property(lambda self: self.values.get("work", 0.0),
                    doc="the forces' work since the start (0 without a force)")
    mean_newton_iterations = property(lambda self: self._sim.mean_newton_iterations)

    def __repr__(self):
        what = repr(self.model) if self.model else repr(self.lagrangian)
        return f"<varsym.Stepper of {what}: h = {self.h:g}, step {self.steps}, t = {self.t:g}>"


def _progress(progress, total, first):
    """A tqdm bar and the callback that advances it, or the user's function; (None, None)."""
    if progress is None or progress is False:
        return None, None
    if callable(progress):
        return None, lambda j: progress(j - first, total)
    try:
        from tqdm import tqdm  # noqa: PLC0415 (Debian's python3-tqdm)
    except ImportError:
        def line(j):
            sys.stderr.write(f"\rvarsym: {j - first}/{total} steps")
        return None, line
    bar = tqdm(total=total, unit="step", unit_scale=True, desc="varsym", leave=False)
    return bar, lambda j: bar.update(j - first - bar.n)


_SIMULATE_KEYS = ["t_span", "steps", "h", "q0", "p0", "v0", "scheme", "degree", "every",
                  "progress", "iteration", "force", "t0", "max_energy_error", "constraints",
                  "project"]


def simulate(system, *, t_span=None, steps=None, h=None, q0=None, p0=None, v0=None,
             scheme=None, degree=None, every=1, progress=False, iteration="automatic",
             force=None, max_energy_error=None, constraints=None, project=False,
             **parameters):
    """Integrates a system and returns its Trajectory.

    ``system``: a built-in model's name (``varsym.models()``), a Model, or a Lagrangian (or its
    expression). ``parameters``: the model's parameters by name, e.g. ``eccentricity=0.6``.
    ``t_span``: the final time T, or (t0, T) for a Lagrangian; default: one period of a
    periodic model, else the model's default time (10 for a Lagrangian). ``steps`` or ``h``:
    default the model's steps per period (or its default steps). ``every``: a row every this
    many steps and the last. ``progress``: True for a progress bar, or a function
    progress(steps_done, steps). Ctrl-C stops the run within 0.2 s, raising
    varsym.Interrupted with the rows so far in ``.partial``; a failed step raises StepFailure
    (``step``, ``time``, ``cause``, ``q``, ``p``, ``partial``). ``max_energy_error``: the
    energy watch's bound (default 100 (h ω)^order, between 0.01 and 0.5; 0: off): past it the
    run stops with EnergyError and its rows in ``.partial``. An unknown keyword raises
    TypeError naming the closest valid ones. ``constraints`` and ``project``: holonomic
    constraints g(q) = 0 of a Lagrangian, as for Stepper."""
    model = None
    if isinstance(system, Model) or (isinstance(system, str) and system in _REGISTRY):
        if project is not False:  # the constrained models' parameter of that name
            parameters = {**parameters, "project": project}
        info = system.info if isinstance(system, Model) else _REGISTRY[system]
        names = [p["name"] for p in info["parameters"] + info["lists"]]
        for key in parameters:
            if key not in names:
                raise _keyword_error("simulate", key, _SIMULATE_KEYS + names)
        model = system._with(**parameters) if isinstance(system, Model) else Model(system,
                                                                                   **parameters)
    elif isinstance(system, str) and "_dot" not in system:
        near = difflib.get_close_matches(system, list(_REGISTRY), n=1)
        hint = f"; did you mean {near[0]!r}?" if near else ""
        raise UsageError(f"no model {system!r}{hint} (a Lagrangian names velocities NAME_dot)")
    elif parameters:
        raise _keyword_error("simulate", next(iter(parameters)), _SIMULATE_KEYS)
    t0, length = 0.0, None
    if t_span is not None:
        if np.ndim(t_span) == 0:
            length = float(t_span)
        else:
            t0, t1 = (float(x) for x in t_span)
            length = t1 - t0
        if not (math.isfinite(length) and length > 0):
            raise UsageError(f"t_span must end after it starts, got {t_span!r}")
    if steps is not None and h is not None:
        raise UsageError("give steps or h, not both")
    if model is not None:
        if t0 != 0.0:
            raise UsageError("a model starts at t = 0: give t_span=T")
        problem = model.problem(q0, p0, v0)
        periodic = model.info["steps_per_period"] > 0 and problem.period > 0
        if length is None:
            if model.info["steps_per_period"] > 0 and not periodic:
                raise UsageError(f"{model.name}: {problem.no_period}; give t_span")
            length = problem.period if periodic else model.info["time"]
            if steps is None and h is None:
                steps = model.info["steps_per_period"] if periodic else model.info["steps"]
        elif steps is None and h is None:
            steps = (math.ceil(length / problem.period * model.info["steps_per_period"])
                     if periodic else model.info["steps"])
    else:
        length = 10.0 if length is None else length
        if steps is None and h is None:
            steps = 10000
    if h is not None:
        h = _checks.positive(h, "h")
        steps = round(length / h)
        if steps < 1 or abs(steps * float(h) - length) > 1e-9 * length:
            raise UsageError(f"t_span {length:g} is not a whole number of steps h = {h:g}")
    steps = _checks.count(steps, "steps")
    if model is not None:
        stepper = Stepper(model, length / steps, scheme=scheme, degree=degree, q0=q0, p0=p0,
                          v0=v0, iteration=iteration, max_energy_error=max_energy_error,
                          force=force, constraints=constraints)
    else:
        stepper = Stepper(system, length / steps, scheme=scheme, degree=degree, q0=q0, p0=p0,
                          v0=v0, t0=t0, force=force, iteration=iteration,
                          max_energy_error=max_energy_error, constraints=constraints,
                          project=project)
    return stepper.run(steps, every=every, progress=progress)
