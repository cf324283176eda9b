"""varsym.Robot: a robot read from its URDF file, a Model like the built-in ones (simulate,
Stepper, ensemble), with its dynamics at a state: M(q), g(q), the bias C(q, q̇)q̇ + g(q), the
energy and the links' poses, by the recursive multibody algorithms of the C++ library."""

import os

import numpy as np

from . import _core
from ._simulate import Model
from .errors import UsageError


class Robot(Model):
    """A robot from a URDF file: ``Robot("ur5.urdf")``, or from its XML text with
    ``Robot(text=...)``. Its coordinates are the revolute, continuous and prismatic joints
    (``joints``, depth first from the root link; fixed joints merge their links). Parameters,
    as for a Model: ``gravity`` (9.81 m/s², along −z), ``no_damping`` (1: leave the URDF's
    joint damping out), a PD controller on every joint with ``kp``, ``kd`` (one gain per
    joint), ``target`` (joint positions; default the start) reached by a minimum-jerk move over
    ``move_time`` s with gravity compensation unless ``no_gravity_compensation`` = 1, and
    constant joint torques ``torque``, or ``torques``: one expression per joint in t, the
    joints' names and their velocities NAME_dot (e.g. ``["5*sin(t)", "0", ...]``). ``limits`` holds the URDF's lower, upper, effort,
    velocity and damping per coordinate. ``base="free"`` sets the root link free in space (its
    coordinates base_x, base_y, base_z [m, world] and the unit quaternion base_qw, base_qx,
    base_qy, base_qz come first; a one-link file without joints is then a free rigid body),
    ``base="planar"`` free in the x–z plane (base_x, base_z, base_ry); the per-joint lists and
    ``torques`` then cover the joints after the base, and the results gain the columns
    base_vx…, base_wx…, momentum_x…, angular_momentum_x…, com_x… (and quaternion_residual)
    (docs/robots.md). ``optimize`` takes fixed bases only.
    A file that cannot be read, or a robot varsym refuses
    (floating, planar or mimic joints, closed loops, a moving link without inertia, an inertia
    that is not positive definite or breaks the triangle inequality), raises UsageError naming
    the file, line and element (docs/robots.md)."""

    def __init__(self, source=None, *, text=None, torques=None, base=None, **parameters):
        if isinstance(source, Robot):
            if torques is not None or base is not None:
                raise UsageError("torques and base are fixed when the Robot is read: "
                                 "Robot(path, torques=[...], base=...)")
            self._core, parameters = source._core, {**source.parameters, **parameters}
            self._urdf = source._urdf
            parameters = {k: v for k, v in parameters.items() if v is not None}
        elif (source is None) == (text is None):
            raise TypeError("Robot(path) or Robot(text=URDF_XML)")
        else:
            typed = [] if torques is None else [str(x) for x in torques]
            held = "fixed" if base is None else str(base)
            if held not in ("fixed", "free", "planar"):
                raise UsageError(f"base is 'fixed', 'free' or 'planar', not {base!r}")
            self._core = (_core._Robot(text, True, typed, held) if text is not None
                          else _core._Robot(os.fspath(source), False, typed, held))
            self._urdf = None if text is not None else os.fspath(source)
        self._set("urdf", self._core.info, parameters)
        self.joints = list(self._core.joints)
        self.coordinates = self.joints
        self.dim = len(self.joints)

    @property
    def base(self):
        """How the root link is held: 'fixed', 'free' or 'planar'."""
        return self._core.base

    @property
    def robot_name(self):
        """The URDF's <robot name>."""
        return self._core.name

    @property
    def limits(self):
        """The joints' URDF limits: a dict of arrays lower, upper [rad or m], effort [N m or N],
        velocity, damping (±inf where the URDF gives none)."""
        return dict(self._core.limits)

    @property
    def frames(self):
        """Every link's name (the merged ones too), for ``pose``."""
        return list(self._core.frames)

    def mass_matrix(self, q):
        """M(q), the joint-space mass matrix (composite-rigid-body algorithm)."""
        return self._core.mass_matrix(_list(q))

    def gravity(self, q):
        """g(q) = ∂V/∂q, the joint torques that hold the robot still at q."""
        return self._core.bias(_list(q), [0.0] * self.dim, self.parameters["gravity"])

    def bias(self, q, v):
        """C(q, q̇)q̇ + g(q), with M(q)q̈ + C(q, q̇)q̇ + g(q) = τ (recursive Newton–Euler)."""
        return self._core.bias(_list(q), _list(v), self.parameters["gravity"])

    def energy(self, q, v):
        """The mechanical energy ½ q̇ᵀM(q)q̇ + V(q) [J], V = −Σ m g·c (zero at the base)."""
        return self._core.energy(_list(q), _list(v), self.parameters["gravity"])

    def pose(self, link, q):
        """The 4×4 homogeneous transform of link ``link``'s frame in the world at q."""
        return self._core.pose(link, _list(q))

    def animate(self, path, t, q, *, fps=60.0, mesh_path=(), title=None):
        """Writes the motion through rows ``q`` (len(t) × the robot's coordinates) at times
        ``t`` as a 3-D animation: one self-contained HTML page that any browser opens offline
        (docs/robots.md). Meshes are found beside the URDF file and in ``mesh_path``
        directories (package://PKG/PATH as DIR/PKG/PATH or DIR/PATH); a link whose mesh is
        missing is drawn as capsules, with a warning (``warnings.warn`` and on the page).
        ``fps``: frames kept per second of the motion's time (0: every row). With
        ``contact=1`` the ground and boxes are drawn, and each frame's contact points. Returns
        a dict: frames, bytes, warnings."""
        import warnings  # noqa: PLC0415

        if isinstance(mesh_path, (str, bytes, os.PathLike)):
            mesh_path = [mesh_path]  # one directory, not its characters
        q = np.asarray(q, dtype=float)
        if q.ndim == 1:
            q = q[:, None]
        try:
            out = dict(self._core.animate(np.asarray(t, dtype=float).ravel().tolist(), q,
                                          os.fspath(path), self._urdf or "",
                                          [os.fspath(d) for d in mesh_path], float(fps),
                                          title or "", self._values(), self._lists()))
        except ValueError as e:
            raise UsageError(str(e)) from None
        for w in out["warnings"]:
            warnings.warn(w, stacklevel=2)
        return out

    def _prepare(self, values, q0, p0, v0, lists):
        return self._core.prepare(values, q0, p0, v0, lists)

    def _ensemble(self, *args):
        return self._core.ensemble(*args)

    def __repr__(self):
        if self.base == "fixed":
            return f"varsym.Robot({self._core.name!r}, {self.dim} joints)"
        return f"varsym.Robot({self._core.name!r}, {self.base} base, {self.dim} coordinates)"


def _list(x):
    return np.asarray(x, dtype=float).ravel().tolist()
