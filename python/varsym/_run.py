"""varsym.run, table1, figure_data, models: the built-in models, schemes and the paper's results,
computed by the same code as the command-line tool (run in-process, not as a subprocess)."""

import os
import tempfile

import numpy as np

from . import _core
from ._lagrangian import Lagrangian, _expression_text
from ._members import _keyword_error
from ._simulate import _REGISTRY, Model, simulate
from ._trajectory import Trajectory
from .errors import EnergyError, Error, Interrupted, StepFailure, UsageError

_ERRORS = {2: UsageError, 3: StepFailure, 4: EnergyError, 130: Interrupted}


def _text(value):
    if isinstance(value, (float, np.floating)):
        return repr(float(value))  # shortest round-trip form: the tool reads the same double
    return str(value)


def _option(name, value):
    flag = "--" + name.replace("_", "-")
    if value is True:
        return [flag]
    if value is False or value is None:
        return []
    if isinstance(value, dict):  # parameters={"m": 1, "g": 9.81}
        return [flag, ",".join(f"{k}={_text(v)}" for k, v in value.items())]
    if isinstance(value, (list, tuple, np.ndarray)):
        return [flag, ",".join(_text(v) for v in value)]
    return [flag, _text(value)]


def _tool():
    try:
        from . import _tool as tool  # noqa: PLC0415 (optional: the tool's engine)
    except ImportError:
        raise Error("this installation of varsym has no command-line engine (varsym._tool): "
                    "the models outside the models layer and varsym.call need it; build the "
                    "package with `make python-tool`, or pip install with VARSYM_PIP_TOOL=1") from None
    return tool


def call(args):
    """Runs the command line ``varsym ARGS...`` in-process; raises the matching varsym.Error on
    failure (UsageError for exit code 2, StepFailure 3, EnergyError 4, Error otherwise). Ctrl-C
    stops the command as a first SIGINT stops the tool (within a step: what it wrote is kept, a
    run's rows in FILE.part with its checkpoint) and raises varsym.Interrupted."""
    code, message = _tool().run_cli([str(a) for a in args])
    if code != 0:
        raise _ERRORS.get(code, Error)(message)


def _read_csv(path):
    with open(path, encoding="ascii") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.size == 0:
        data = data.reshape(0, len(header))
    return {name: data[:, k] for k, name in enumerate(header)}


def _trajectory(path):
    return Trajectory.from_csv_columns(_read_csv(path))


# The options of varsym.run that a model of the models layer takes in-process (varsym.simulate);
# the others run the command line in-process, through a temporary CSV file.
_IN_PROCESS = {"scheme", "degree", "steps_per_period", "periods", "time", "steps", "every", "q0",
               "p0", "v0", "iteration", "predictor", "max_energy_error"}
_TOOL_ONLY = {"newton_tol", "newton_max_iter", "stats", "checkpoint_every", "checkpoint_seconds"}


def _parameters_of_options(model, options):
    """The tool's options of a model's parameters (``lengths=[1, 3, 1, 3]``, ``project=True``)
    as its parameters' names (crank_length=1, …); other keywords unchanged."""
    out = {}
    params = _REGISTRY[model]["parameters"] + _REGISTRY[model]["lists"]
    names = {p["name"] for p in params}
    for key, value in options.items():
        users = [p for p in params if p["option"].replace("-", "_") == key and key not in names]
        if not users:
            out[key] = value
        elif users[0].get("option_index", -1) < 0:
            out[users[0]["name"]] = value
        else:
            values = np.atleast_1d(np.asarray(value, dtype=float)).ravel()
            if len(values) != len(users):
                raise UsageError(f"{model}: {key} needs {len(users)} values, got {len(values)}")
            for p in users:
                out[p["name"]] = float(values[p["option_index"]])
    return out


def _run_in_process(model, options):
    names = {p["name"] for p in _REGISTRY[model]["parameters"] + _REGISTRY[model]["lists"]}
    parameters = {k: v for k, v in options.items() if k in names}
    rest = {k: v for k, v in options.items() if k not in names}
    m = Model(model, **parameters)
    if "predictor" in rest:  # the tool's --iteration and --predictor, as one solver name
        rest["iteration"] = f"{rest.get('iteration', 'automatic')}+{rest.pop('predictor')}"
    if "time" in rest or "steps" in rest:
        if "steps_per_period" in rest or "periods" in rest:
            raise UsageError("give --time and --steps, or --steps-per-period and --periods")
        t_span, steps = rest.pop("time", None), rest.pop("steps", None)
        if (t_span is None) != (steps is None):
            raise UsageError("--time and --steps go together")
    else:
        problem = m.problem(rest.get("q0"), rest.get("p0"), rest.get("v0"))
        spp = rest.pop("steps_per_period", None) or m.info["steps_per_period"]
        periods = float(rest.pop("periods", 1.0))
        if problem.period <= 0:
            if m.info["steps_per_period"] > 0:
                raise UsageError(f"{model}: {problem.no_period}")
            t_span, steps = m.info["time"], m.info["steps"]
        else:
            steps = spp * periods
            if abs(steps - round(steps)) > 1e-9 * steps:
                raise UsageError("--periods times --steps-per-period is not a whole number")
            t_span, steps = problem.period * periods, round(steps)
    return simulate(m, t_span=t_span, steps=steps, **rest)


def run(model=None, **options):
    """Integrates a built-in model, or your own Lagrangian, and returns its Trajectory.

    Every option of ``varsym run`` is a keyword, with '_' for '-': e.g.
    ``run("kepler", scheme="gauss", degree=4, steps_per_period=200, periods=10,
    eccentricity=0.5)``; lists for vectors (``q0=[1.0, 0.0]``), True for flags, a dict for
    ``parameters``. Your own system: ``run(lagrangian="0.5*q_dot**2 - 0.5*q**2", q0=[1])``, or
    ``run(lagrangian=varsym.Lagrangian(...))``, with ``force=[...]``. ``varsym.models()``
    lists the models; ``varsym.call(["run", "--help"])`` prints the options (to the process's
    standard output). Raises UsageError on bad input, StepFailure when a step does not
    converge (its ``partial`` holds the rows before it), EnergyError when the energy watch
    stops the run."""

    for key in ("output", "resume"):
        if key in options:
            raise UsageError(f"varsym.run chooses its own output file; '{key}' is for the tool")
    lag = options.get("lagrangian")
    if isinstance(lag, Lagrangian):
        options["lagrangian"] = lag.expression
        options.setdefault("coordinates", lag.coordinates)
        if lag.parameters:
            options.setdefault("parameters", lag.parameters)
    elif lag is not None and not isinstance(lag, str):
        options["lagrangian"] = Lagrangian(lag, options.get("coordinates", ("q",))).expression
    if "force" in options and not isinstance(options["force"], str):
        options["force"] = [_expression_text(f) for f in options["force"]]
    if model in _REGISTRY:
        options = _parameters_of_options(model, options)
        names = {p["name"] for p in _REGISTRY[model]["parameters"] + _REGISTRY[model]["lists"]}
        for key in options:
            if key not in _IN_PROCESS | names | _TOOL_ONLY:
                raise _keyword_error("run", key, sorted(_IN_PROCESS | names | _TOOL_ONLY))
        if set(options) <= _IN_PROCESS | names:
            return _run_in_process(model, options)
    args = ["run"] + (["--model", model] if model is not None else [])
    for key, value in options.items():
        args += _option(key, value)
    with tempfile.TemporaryDirectory(prefix="varsym-") as tmp:
        out = os.path.join(tmp, "run.csv")
        try:
            call(args + ["--output", out])
        except (StepFailure, EnergyError, Interrupted) as e:
            if os.path.exists(out + ".part"):  # the rows before the failure
                e.partial = _trajectory(out + ".part")
                e.args = (str(e).replace(out + ".part", "the exception's .partial"),)
            if isinstance(e, Interrupted):  # its checkpoint goes with the temporary directory
                e.args = ("run interrupted; the rows so far are in .partial",)
            raise
        return _trajectory(out)


class Table(np.ndarray):
    """A NumPy structured array that prints as a table (varsym.table1)."""

    def __new__(cls, array):
        return np.asarray(array).view(cls)

    def __repr__(self):
        if self.dtype.names is None or self.ndim != 1:
            return np.ndarray.__repr__(self.view(np.ndarray))
        names = self.dtype.names
        cells = [[f"{v:.3e}" if isinstance(v, (float, np.floating)) else str(v) for v in row]
                 for row in self.tolist()]
        widths = [max([len(n)] + [len(r[k]) for r in cells]) for k, n in enumerate(names)]
        line = lambda r: "  ".join(c.rjust(w) for c, w in zip(r, widths))  # noqa: E731
        return "\n".join([line(names)] + [line(r) for r in cells])

    __str__ = __repr__


def _pendulum_period():
    return Model("pendulum").problem().period


def table1(periods=1):
    """The paper's Table 1: Newmark and Simpson on the pendulum (m = 1, omega = 2 pi,
    q0 = pi/2, p0 = 0), N = 50, 100, 200 steps over ``periods`` nonlinear periods; errors in the
    maximum norm over all steps of the momentum, the state and the relative energy, against the
    exact solution. A NumPy structured array (fields scheme, quantity, steps, error; the rows of
    ``varsym paper table1 --format csv``) that prints as a table."""
    period = _pendulum_period()
    errors = {}
    for scheme in ("newmark", "simpson"):
        for n in (50, 100, 200):
            tr = simulate("pendulum", scheme=scheme, t_span=periods * period,
                          steps=n * periods)
            errors[scheme, "momentum", n] = np.abs(tr.p - tr.p_exact).max()
            errors[scheme, "state", n] = np.abs(tr.q - tr.q_exact).max()
            errors[scheme, "energy", n] = (np.abs(tr.energy - tr.energy[0]).max()
                                           / abs(tr.energy[0]))
    rows = [(scheme, what, n, errors[scheme, what, n]) for what in ("momentum", "state", "energy")
            for scheme in ("newmark", "simpson") for n in (50, 100, 200)]
    return Table(np.array(rows, dtype=[("scheme", "U7"), ("quantity", "U8"), ("steps", "i8"),
                                       ("error", "f8")]))


def figure_data(number, periods=5, steps_per_period=10):
    """The data of the paper's Figure 1 (the exact pendulum: t, q, p at 1001 points over
    ``periods`` periods) or Figure 2 (Newmark, Simpson and the exact solution at
    ``steps_per_period`` steps per period: step, t, q_newmark, p_newmark, q_simpson, p_simpson,
    q_exact, p_exact), as a dict of columns."""
    if number not in (1, 2):
        raise UsageError("the paper has Figures 1 and 2")
    period = _pendulum_period()
    if number == 1:
        tr = simulate("pendulum", t_span=periods * period, steps=1000)
        return {"t": tr.t, "q": tr.q_exact[:, 0], "p": tr.p_exact[:, 0]}
    out = {}
    for scheme in ("newmark", "simpson"):
        tr = simulate("pendulum", scheme=scheme, t_span=periods * period,
                      steps=periods * steps_per_period)
        out.update({"step": tr.step, "t": tr.t, f"q_{scheme}": tr.q[:, 0],
                    f"p_{scheme}": tr.p[:, 0]})
    out.update({"q_exact": tr.q_exact[:, 0], "p_exact": tr.p_exact[:, 0]})
    return out


def models():
    """The built-in models as a dict: name -> (one-line summary, description); without the
    command-line engine (varsym._tool), those of the models layer."""
    try:
        listed = _tool().models()
    except Error:
        listed = [(m["name"], m["summary"], m["description"]) for m in _core.registry()]
    return {name: (summary, text) for name, summary, text in listed}
