"""varsym.Robot: URDF robots from Python. M(q), g(q) and C(q, q̇)q̇ of the UR5, the iiwa 14 and
the Panda (with prismatic fingers) against a second implementation in NumPy that shares nothing
with varsym's: it reads the URDF itself (xml.etree), poses every link, fixed ones included (no
merging), and sums geometric Jacobians, M = Σ m J_vᵀJ_v + J_ωᵀ I J_ω, g = −Σ m J_vᵀ g; C q̇ =
Ṁ q̇ − ½ ∂(q̇ᵀMq̇)/∂q by central differences of that M. Then simulate, poses and ensembles.
Run by CTest (test `python`)."""

import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import varsym

DATA = os.path.join(os.path.dirname(__file__), "..", "data", "urdf")


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = (math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y),
                              math.sin(y))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def numbers(element, name, default):
    if element is None or element.get(name) is None:
        return np.array(default, dtype=float)
    return np.array([float(x) for x in element.get(name).split()])


class NumpyRobot:
    """Forward kinematics and geometric Jacobians of every link, straight from the URDF."""

    def __init__(self, path):
        root = ET.parse(path).getroot()
        self.links = {l.get("name"): l for l in root.findall("link")}
        self.joints = root.findall("joint")
        children = {j.find("child").get("link") for j in self.joints}
        self.root = next(n for n in self.links if n not in children)
        self.moving = []  # joint names in varsym's order: depth first, children in file order

        def visit(link):
            for j in self.joints:
                if j.find("parent").get("link") == link:
                    if j.get("type") != "fixed":
                        self.moving.append(j.get("name"))
                    visit(j.find("child").get("link"))

        visit(self.root)

    def links_at(self, q):
        """For each link with mass: (m, c, I about c in the world, [(joint index, kind, axis,
        point)] of the moving joints above it)."""
        index = {name: k for k, name in enumerate(self.moving)}
        out = []

        def visit(link, rot, pos, chain):
            inertial = self.links[link].find("inertial")
            if inertial is not None and float(inertial.find("mass").get("value")) > 0:
                o = inertial.find("origin")
                ri = rot @ rpy_matrix(*numbers(o, "rpy", [0, 0, 0]))
                c = rot @ numbers(o, "xyz", [0, 0, 0]) + pos
                t = inertial.find("inertia")
                g = {k: float(t.get(k, 0)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
                ic = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]],
                               [g["ixz"], g["iyz"], g["izz"]]])
                out.append((float(inertial.find("mass").get("value")), c, ri @ ic @ ri.T, chain))
            for j in self.joints:
                if j.find("parent").get("link") != link:
                    continue
                o = j.find("origin")
                rj = rot @ rpy_matrix(*numbers(o, "rpy", [0, 0, 0]))
                pj = rot @ numbers(o, "xyz", [0, 0, 0]) + pos
                kind = j.get("type")
                if kind == "fixed":
                    visit(j.find("child").get("link"), rj, pj, chain)
                    continue
                a0 = numbers(j.find("axis"), "xyz", [1, 0, 0])
                a0 = a0 / np.linalg.norm(a0)
                a = rj @ a0
                qi = q[index[j.get("name")]]
                if kind == "prismatic":
                    visit(j.find("child").get("link"), rj, pj + a * qi,
                          chain + [(index[j.get("name")], "prismatic", a, pj)])
                else:
                    k = np.array([[0, -a0[2], a0[1]], [a0[2], 0, -a0[0]], [-a0[1], a0[0], 0]])
                    r = np.eye(3) + math.sin(qi) * k + (1 - math.cos(qi)) * k @ k
                    visit(j.find("child").get("link"), rj @ r, pj,
                          chain + [(index[j.get("name")], "revolute", a, pj)])

        visit(self.root, np.eye(3), np.zeros(3), [])
        return out

    def mass_matrix(self, q):
        n = len(self.moving)
        m_q = np.zeros((n, n))
        for m, c, ic, chain in self.links_at(q):
            jv, jw = np.zeros((3, n)), np.zeros((3, n))
            for k, kind, a, p in chain:
                if kind == "prismatic":
                    jv[:, k] = a
                else:
                    jw[:, k] = a
                    jv[:, k] = np.cross(a, c - p)
            m_q += m * jv.T @ jv + jw.T @ ic @ jw
        return m_q

    def gravity(self, q, g=9.81):
        n = len(self.moving)
        tau = np.zeros(n)
        for m, c, _, chain in self.links_at(q):
            for k, kind, a, p in chain:
                jv = a if kind == "prismatic" else np.cross(a, c - p)
                tau[k] -= m * jv @ np.array([0, 0, -g])
        return tau

    def coriolis(self, q, v, eps=1e-6):
        """C(q, v) v = Ṁ v − ½ ∂(vᵀMv)/∂q, by central differences of mass_matrix."""
        q, v = np.asarray(q, float), np.asarray(v, float)
        m_dot = (self.mass_matrix(q + eps * v) - self.mass_matrix(q - eps * v)) / (2 * eps)
        grad = np.array([(v @ self.mass_matrix(q + eps * e) @ v
                          - v @ self.mass_matrix(q - eps * e) @ v) / (2 * eps)
                         for e in np.eye(len(q))])
        return m_dot @ v - 0.5 * grad


@pytest.mark.parametrize("name", ["ur5_robot.urdf", "iiwa14_no_collision.urdf",
                                  "panda_fingers_free.urdf"])
def test_dynamics_match_a_numpy_implementation(name):
    path = os.path.join(DATA, name)
    robot, ref = varsym.Robot(path), NumpyRobot(path)
    assert robot.joints == ref.moving
    rng = np.random.default_rng(3)
    for _ in range(4):
        q = rng.uniform(-2, 2, robot.dim)
        v = rng.uniform(-2, 2, robot.dim)
        m_ref = ref.mass_matrix(q)
        # Same quantity, different round-off paths: 1e-12 of the largest entry.
        assert np.abs(robot.mass_matrix(q) - m_ref).max() < 1e-12 * np.abs(m_ref).max()
        g_ref = ref.gravity(q)
        assert np.abs(robot.gravity(q) - g_ref).max() < 1e-12 * np.abs(g_ref).max()
        # Central differences of step 1e-6: truncation ~1e-12, cancellation ~1e-10 relative.
        c_ref = ref.coriolis(q, v)
        c = robot.bias(q, v) - robot.gravity(q)
        assert np.abs(c - c_ref).max() < 1e-7 * max(1.0, np.abs(c_ref).max())


def test_numpy_reference_sees_a_changed_inertia():
    # Negative control: one link's iyy changed by 1 % changes M beyond the tolerance above.
    path = os.path.join(DATA, "ur5_robot.urdf")
    text = open(path).read().replace('iyy="0.22689067591"', 'iyy="0.2291595826691"')
    q = np.array([0.3, -1.0, 1.2, 0.4, 0.5, 0.1])
    m_ref = NumpyRobot(path).mass_matrix(q)
    assert np.abs(varsym.Robot(text=text).mass_matrix(q) - m_ref).max() > 1e-6


def test_simulate_conserves_energy_and_names_the_joints():
    robot = varsym.Robot(os.path.join(DATA, "ur5_robot.urdf"))
    q0 = [0, -1, 1, 0, 0.5, 0]
    tr = varsym.simulate(robot, q0=q0, t_span=1.0, steps=1000, scheme="gauss", degree=2,
                         every=100)
    assert isinstance(tr, varsym.Trajectory) and tr.q.shape == (11, 6)
    assert tr.coordinates == robot.joints
    assert np.array_equal(tr["elbow_joint"], tr.q[:, 2])
    # E from the robot's own energy at each row equals the run's column, and stays within
    # 1e-8 of its start (order 4 at h ω ≈ 0.02; measured 3e-9 J of 51 J).
    e = [robot.energy(q, np.linalg.solve(robot.mass_matrix(q), p)) for q, p in zip(tr.q, tr.p)]
    assert np.allclose(e, tr["energy"], rtol=1e-13, atol=0)
    assert np.abs(np.array(e) - e[0]).max() < 1e-8 * e[0]
    # Gravity along −z: the pose of the end falls when the arm is released horizontal.
    z0 = robot.pose("ee_link", tr.q[0])[2, 3]
    z1 = robot.pose("ee_link", tr.q[3])[2, 3]
    assert z1 < z0


def test_damping_and_control_parameters():
    path = os.path.join(DATA, "iiwa14_no_collision.urdf")
    robot = varsym.Robot(path)
    assert robot.limits["damping"].tolist() == [0.5] * 7
    target = [0.5, 0.5, 0, -1, 0, 0.5, 0]
    pd = varsym.Robot(robot, kp=[400, 400, 300, 300, 100, 50, 20], kd=[40, 40, 30, 30, 10, 5, 2],
                      target=target, move_time=1.0)
    tr = pd.simulate(q0=[0.3, 1, 0, -1, 0, 0.5, 0], t_span=3.0, steps=3000, every=3000)
    assert np.abs(tr.q[-1] - target).max() < 1e-3
    assert abs(tr["energy_balance"]).max() < 1e-6


def test_refusals_and_ensemble():
    # The real Panda's second finger mimics the first: 8 coordinates, the mimic joint not one.
    panda = varsym.Robot(os.path.join(DATA, "panda.urdf"))
    assert len(panda.joints) == 8 and "panda_finger_joint2" not in panda.joints
    assert panda.mass_matrix([0.1] * 8).shape == (8, 8)
    with open(os.path.join(DATA, "panda.urdf")) as f:
        text = f.read().replace('mimic joint="panda_finger_joint1"', 'mimic joint="nothing"')
    with pytest.raises(varsym.UsageError, match=r":348: <mimic>: joint panda_finger_joint2 mimics"):
        varsym.Robot(text=text)
    with pytest.raises(varsym.UsageError, match="cannot (open the|read) URDF file"):
        varsym.Robot(os.path.join(DATA, "missing.urdf"))
    robot = varsym.Robot(os.path.join(DATA, "ur5_robot.urdf"))
    with pytest.raises(varsym.UsageError, match="q needs 6 values"):
        robot.mass_matrix([0, 0])
    with pytest.raises(varsym.UsageError, match="no link 'hand'"):
        robot.pose("hand", np.zeros(6))
    q0 = np.array([[0, -1.0, 1, 0, 0.5, 0], [0, -0.5, 1, 0, 0.5, 0]])
    out = robot.ensemble(q0=q0, t_span=0.2, steps=200)
    assert list(out["status"]) == ["completed", "completed"]
    assert (out["max_energy_error"] < 1e-8).all()


def test_typed_torques_do_work_that_balances_the_energy():
    path = os.path.join(DATA, "ur5_robot.urdf")
    robot = varsym.Robot(path, torques=["5*sin(3*t)", "0", "-2*elbow_joint_dot", "0", "0", "0"])
    tr = robot.simulate(q0=[0, -1, 1, 0, 0.5, 0], t_span=2.0, steps=2000, scheme="gauss",
                        degree=2, every=100)
    assert abs(tr["work"]).max() > 0.1  # the torques act
    assert abs(tr["energy_balance"]).max() < 1e-6  # E − E0 − W: the scheme's error alone
    with pytest.raises(varsym.ExpressionError):
        varsym.Robot(path, torques=["hand", "0", "0", "0", "0", "0"])
    with pytest.raises(varsym.UsageError, match="6 expressions"):
        varsym.Robot(path, torques=["1"])



BODY = """<?xml version="1.0"?>
<robot name="tumbling_body">
  <link name="body">
    <inertial>
      <origin xyz="0.1 -0.2 0.05" rpy="0.3 0.2 0.1"/>
      <mass value="2.0"/>
      <inertia ixx="1.0" ixy="0" ixz="0" iyy="2.0" iyz="0" izz="3.0"/>
    </inertial>
  </link>
</robot>"""


def test_a_free_body_keeps_both_momenta_and_its_quaternion():
    # Noether: in free flight the total momenta are conserved to round-off (|L| ≈ 6 N m s over
    # 2000 steps: 1e-12); the quaternion stays on its sphere; the body tumbles (its orientation
    # moves), so the check is not of a body at rest.
    body = varsym.Robot(text=BODY, base="free", gravity=0)
    assert body.base == "free"
    assert body.joints == ["base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy",
                           "base_qz"]
    tr = body.simulate(v0=[0, 0, 0, 0, 0.5, 0.05, 1.0], t_span=20.0, steps=2000,
                       scheme="gauss", degree=2, every=10)
    for name in ["angular_momentum_x", "angular_momentum_y", "angular_momentum_z",
                 "momentum_x", "momentum_y", "momentum_z"]:
        column = tr[name]
        assert abs(column - column[0]).max() < 1e-12, name
    assert abs(tr["angular_momentum_z"][0]) > 1.0
    assert abs(tr["quaternion_residual"]).max() < 1e-14
    assert abs(tr["base_qw"] - 1.0).max() > 0.5


def test_a_floating_base_is_chosen_when_the_robot_is_read():
    path = os.path.join(DATA, "ur5_robot.urdf")
    planar = varsym.Robot(path, base="planar", gravity=0)
    assert planar.joints[:3] == ["base_x", "base_z", "base_ry"] and planar.dim == 9
    tr = planar.simulate(torque=[1, -2, 1, 0.5, 0.3, 0.2], t_span=0.5, steps=500, every=50)
    assert abs(tr["momentum_x"]).max() < 1e-11
    with pytest.raises(varsym.UsageError, match="fixed', 'free' or 'planar"):
        varsym.Robot(path, base="sideways")
    with pytest.raises(varsym.UsageError, match="base are fixed"):
        varsym.Robot(planar, base="free")
    with pytest.raises(varsym.UsageError, match="nothing moves"):
        varsym.Robot(text=BODY)
    with pytest.raises(varsym.UsageError, match="free base"):
        varsym.Robot(text=BODY, base="free").mass_matrix([0, 0, 0, 1, 0, 0, 0])
    free = varsym.Robot(path, base="free")
    assert all(len(v) == free.dim == 13 for v in free.limits.values())
    assert list(free.limits["effort"][:7]) == [0.0] * 7  # the base is not actuated
    for robot in (free, planar):  # optimal control takes fixed bases only
        with pytest.raises(varsym.UsageError, match="floating base"):
            varsym.optimize(robot, time=1.0, q_start=[0.0] * robot.dim,
                            q_end=[0.0] * robot.dim, steps=10)
