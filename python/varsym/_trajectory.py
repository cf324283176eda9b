"""varsym.Trajectory: the one result type of a run, from whichever model or Lagrangian."""

import numpy as np


class Trajectory:
    """The rows of a run: ``t`` and ``step`` (1-D arrays), ``q`` and ``p`` (rows × d arrays,
    also for d = 1), and the model's own columns (``energy``; conserved quantities such as
    ``angular_momentum``; ``work`` and ``energy_balance`` under forces; ``q_exact`` and
    ``p_exact`` (rows × d) where the model has an exact solution, else None).

    Every column is also reached by name: ``tr["energy"]``; a coordinate by its name,
    ``tr["th1"]`` (q of that coordinate) and ``tr["p_th1"]`` (its momentum); the tool's CSV
    names ``q_1``, ``p_2`` as well. ``columns`` lists the model's own columns, ``coordinates``
    the coordinates' names."""

    def __init__(self, t, q, p, columns, coordinates, step=None):
        self.t = t
        self.q = q
        self.p = p
        self._step = step  # an array, a function that makes it, or None (0, 1, 2, ...)
        self._columns = dict(columns)
        self.coordinates = list(coordinates)
        self.energy = self._columns.get("energy")
        self.work = self._columns.get("work")
        self.energy_balance = self._columns.get("energy_balance")
        self.q_exact = self._stack("q", "_exact")
        self.p_exact = self._stack("p", "_exact")

    def animate(self, path, robot=None, *, fps=60.0, mesh_path=(), title=None):
        """Writes this motion as a 3-D animation page (Robot.animate, Model.animate): ``robot``
        is the Robot that made it (the default where this trajectory came from Robot.simulate
        or a Stepper of one); a built-in model's trajectory is drawn as the model's figure.
        Returns a dict: frames, bytes, warnings."""
        from ._robot import Robot  # noqa: PLC0415
        from ._simulate import Model  # noqa: PLC0415
        from .errors import UsageError  # noqa: PLC0415

        robot = robot if robot is not None else getattr(self, "model", None)
        if isinstance(robot, Robot):
            return robot.animate(path, self.t, self.q, fps=fps, mesh_path=mesh_path,
                                 title=title)
        if isinstance(robot, Model):
            if mesh_path:
                raise UsageError("mesh_path finds a URDF robot's meshes; "
                                 f"{robot.name} has none")
            return robot.animate(path, self.t, self.q, fps=fps, title=title)
        raise UsageError("animate draws a URDF robot or a built-in model: tr.animate(path, "
                         "robot=Robot(...)) for a trajectory that did not come from one")

    @property
    def step(self):
        """The step index j of each row (made when first asked for: it costs memory)."""
        if self._step is None:
            self._step = np.arange(len(self.t), dtype=np.int64)
        elif callable(self._step):
            self._step = self._step()
        return self._step

    @classmethod
    def from_csv_columns(cls, columns):
        """From the tool's CSV columns (step, t, q or q_1.., p or p_1.., the rest)."""
        def stack(name):
            if name in columns:
                return columns[name][:, None]
            parts = []
            while f"{name}_{len(parts) + 1}" in columns:
                parts.append(columns[f"{name}_{len(parts) + 1}"])
            return np.column_stack(parts) if parts else np.empty((len(columns["t"]), 0))
        q, p = stack("q"), stack("p")
        d = q.shape[1]
        state = {"step", "t", "q", "p"} | {f"{k}_{i}" for k in "qp" for i in range(1, d + 1)}
        rest = {k: v for k, v in columns.items() if k not in state}
        names = ["q"] if d == 1 else [f"q_{i}" for i in range(1, d + 1)]
        return cls(columns["t"], q, p, rest, names, columns["step"])

    def _stack(self, name, suffix):
        if name + suffix in self._columns:
            return self._columns[name + suffix][:, None]
        parts = []
        while f"{name}_{len(parts) + 1}{suffix}" in self._columns:
            parts.append(self._columns[f"{name}_{len(parts) + 1}{suffix}"])
        return np.column_stack(parts) if parts else None

    @property
    def columns(self):
        """Every column by name: step, t, q_1.., p_1.. (q, p for d = 1) and the model's own."""
        d = self.q.shape[1]
        out = {"step": self.step, "t": self.t}
        for k, a in (("q", self.q), ("p", self.p)):
            if d == 1:
                out[k] = a[:, 0]
            else:
                out.update({f"{k}_{i + 1}": a[:, i] for i in range(d)})
        out.update(self._columns)
        return out

    def __getitem__(self, name):
        if name in ("t", "q", "p", "step"):
            return getattr(self, name)
        if name in self._columns:
            return self._columns[name]
        if name in self.coordinates:
            return self.q[:, self.coordinates.index(name)]
        if name.startswith("p_") and name[2:] in self.coordinates:
            return self.p[:, self.coordinates.index(name[2:])]
        columns = self.columns
        if name in columns:
            return columns[name]
        raise KeyError(f"no column {name!r}; the columns: {', '.join(columns)}; the "
                       f"coordinates: {', '.join(self.coordinates)}")

    def __contains__(self, name):
        try:
            self[name]
        except KeyError:
            return False
        return True

    def keys(self):
        return self.columns.keys()

    def __len__(self):
        return len(self.t)

    def __repr__(self):
        d = self.q.shape[1]
        span = f"t = {self.t[0]:g} .. {self.t[-1]:g}" if len(self) else "no rows"
        return (f"<varsym.Trajectory: {len(self)} rows, {span}, d = {d} "
                f"({', '.join(self.coordinates)}), columns {', '.join(self._columns)}>")
