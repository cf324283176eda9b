"""varsym.run, table1, figure_data, models: the built-in models, schemes and the paper's results,
computed by the same code as the command-line tool (run in-process, not as a subprocess)."""

import os
import tempfile

import numpy as np

from . import _core
from .errors import EnergyError, Error, StepFailure, UsageError

_ERRORS = {2: UsageError, 3: StepFailure, 4: EnergyError}


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


def call(args):
    """Runs the command line ``varsym ARGS...`` in-process; raises the matching varsym.Error on
    failure (UsageError for exit code 2, StepFailure 3, EnergyError 4, Error otherwise)."""
    code, message = _core.run_cli([str(a) for a in args])
    if code != 0:
        raise _ERRORS.get(code, Error)(message)


def _read_csv(path):
    with open(path, encoding="ascii") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.size == 0:
        data = data.reshape(0, len(header))
    return {name: data[:, k] for k, name in enumerate(header)}


class Trajectory:
    """The rows of a run. ``t``, ``step`` and ``energy`` are 1-D arrays; ``q`` and ``p`` are
    (rows, d) arrays, also for d = 1; ``q_exact`` and ``p_exact`` likewise where the model has an
    exact solution (else None). Every CSV column of the tool is in ``columns`` (by its name, e.g.
    ``angular_momentum``, ``p_phi``) and ``trajectory["name"]``."""

    def __init__(self, columns):
        self.columns = columns
        self.t = columns["t"]
        self.step = columns["step"].astype(np.int64)
        self.energy = columns.get("energy")
        self.q = self._stack("q")
        self.p = self._stack("p")
        self.q_exact = self._stack("q", "_exact")
        self.p_exact = self._stack("p", "_exact")

    def _stack(self, name, suffix=""):
        if name + suffix in self.columns:
            return self.columns[name + suffix][:, None]
        parts = []
        while f"{name}_{len(parts) + 1}{suffix}" in self.columns:
            parts.append(self.columns[f"{name}_{len(parts) + 1}{suffix}"])
        return np.column_stack(parts) if parts else None

    def __getitem__(self, name):
        return self.columns[name]

    def __len__(self):
        return len(self.t)

    def __repr__(self):
        d = self.q.shape[1] if self.q is not None else 0
        return f"<varsym.Trajectory: {len(self)} rows, d = {d}, columns {', '.join(self.columns)}>"


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
    from ._lagrangian import Lagrangian  # noqa: PLC0415 (a cycle otherwise)

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
        from ._lagrangian import _expression_text  # noqa: PLC0415

        options["force"] = [_expression_text(f) for f in options["force"]]
    args = ["run"] + (["--model", model] if model is not None else [])
    for key, value in options.items():
        args += _option(key, value)
    with tempfile.TemporaryDirectory(prefix="varsym-") as tmp:
        out = os.path.join(tmp, "run.csv")
        try:
            call(args + ["--output", out])
        except (StepFailure, EnergyError) as e:
            if os.path.exists(out + ".part"):  # the rows before the failure
                e.partial = Trajectory(_read_csv(out + ".part"))
                e.args = (str(e).replace(out + ".part", "the exception's .partial"),)
            raise
        return Trajectory(_read_csv(out))


def table1(h=None, periods=None):
    """The paper's Table 1 (Newmark and Simpson on the pendulum: errors and observed orders) as
    a NumPy structured array, one row per step size, its fields named as the tool's CSV
    columns (``varsym paper table1 --format csv``)."""
    args = ["paper", "table1", "--format", "csv"]
    if periods is not None:
        args += ["--periods", _text(periods)]
    with tempfile.TemporaryDirectory(prefix="varsym-") as tmp:
        out = os.path.join(tmp, "table1.csv")
        call(args + ["--output", out])
        return np.genfromtxt(out, delimiter=",", names=True, dtype=None, encoding="ascii")


def figure_data(number, **options):
    """The data of the paper's Figure 1 or 2 (``varsym paper figureN``): a dict of columns
    (time, exact solution, and for Figure 2 the Newmark and Simpson solutions)."""
    if number not in (1, 2):
        raise UsageError("the paper has Figures 1 and 2")
    args = ["paper", f"figure{number}"]
    for key, value in options.items():
        args += _option(key, value)
    with tempfile.TemporaryDirectory(prefix="varsym-") as tmp:
        call(args + ["--output", os.path.join(tmp, "figure.svg")])
        return _read_csv(os.path.join(tmp, "figure.csv"))


def models():
    """The built-in models as a dict: name -> (one-line summary, description)."""
    return {name: (summary, text) for name, summary, text in _core.models()}
