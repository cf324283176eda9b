"""3-D animation pages from Python (Trajectory.animate, OptimalControl.animate, Robot.animate,
Model.animate): the page holds every frame asked for and the robot's or figure's poses; a missing
mesh is a warning, not an error; what has no figure, and the robot's own URDF as the page, are
refused. (The
page in a real browser: tests/cli/animate_test.sh.)"""
import base64
import json
import os
import re
import shutil

import numpy as np
import pytest

import varsym

DATA = os.path.join(os.path.dirname(__file__), "..", "data", "urdf")
UR5 = os.path.join(DATA, "ur5_robot.urdf")
PENDULUM = os.path.join(DATA, "pendulum.urdf")
three = os.path.isfile("/usr/share/javascript/three/three.min.js") or os.environ.get(
    "VARSYM_THREE_JS")
pytestmark = pytest.mark.skipif(not three, reason="no three.js (apt-get install libjs-three)")


def motion(path):
    text = open(path, encoding="utf-8").read()
    data = re.search(r'<script id="varsym-motion" type="application/json">\n(.*?)\n</script>',
                     text, re.S).group(1)
    return json.loads(data), len(text.encode())


def test_a_simulated_robot_animates_with_its_frames_and_warns_of_missing_meshes(tmp_path):
    robot = varsym.Robot(UR5)
    tr = varsym.simulate(robot, q0=[0, -1, 1, 0, 0.5, 0], t_span=1.0, h=1e-3)
    with pytest.warns(UserWarning, match="not found"):  # the UR5's meshes are not in the repo
        out = tr.animate(tmp_path / "ur5.html")
    page, size = motion(tmp_path / "ur5.html")
    assert out["bytes"] == size
    assert out["frames"] == page["frames"] == 61  # at 0, 1/60, ..., 60/60 s
    assert page["names"] == robot.joints
    t = np.frombuffer(base64.b64decode(page["t"]), dtype=np.float64)
    assert t[0] == 0.0 and t[-1] == pytest.approx(1.0)
    q = np.frombuffer(base64.b64decode(page["q"]), dtype=np.float32).reshape(len(t), 6)
    row = np.searchsorted(tr.t, t[30])
    assert np.allclose(q[30], tr.q[row], atol=1e-6)  # the frame is the trajectory's row
    # The poses are the links' frames: the wrist_3 body's origin against Robot.pose.
    poses = np.frombuffer(base64.b64decode(page["poses"]), dtype=np.float32)
    poses = poses.reshape(len(t), page["bodies"], 7)
    tip = robot.pose("wrist_3_link", tr.q[row])[:3, 3]
    assert np.abs(poses[30, :, :3] - tip).sum(axis=1).min() < 1e-6
    assert len(page["warnings"]) == 7
    # Every row on request.
    with pytest.warns(UserWarning, match="not found"):
        assert robot.animate(tmp_path / "all.html", tr.t, tr.q, fps=0)["frames"] == len(tr.t)


def test_the_optimal_motion_animates_and_other_motions_are_refused(tmp_path):
    pend = varsym.Robot(PENDULUM)
    best = varsym.optimize(pend, time=1.0, q_start=[0.0], q_end=[1.0], steps=20)
    out = best.animate(tmp_path / "opt.html")
    assert out["frames"] == 21 and out["warnings"] == []  # the nodes; no <visual>: capsules
    page, _ = motion(tmp_path / "opt.html")
    assert any(s["k"] == "capsule" for s in page["shapes"])
    lag = varsym.simulate(varsym.Lagrangian("0.5*q_dot**2 - 0.5*q**2", ["q"]), q0=[1.0],
                          t_span=1.0, h=0.01)
    with pytest.raises(varsym.UsageError, match="URDF robot or a built-in model"):
        lag.animate(tmp_path / "x.html")
    with pytest.raises(varsym.UsageError, match="coordinates"):
        pend.animate(tmp_path / "x.html", [0.0, 1.0], np.zeros((2, 3)))
    assert not (tmp_path / "x.html").exists()


def test_the_page_never_overwrites_the_robots_urdf(tmp_path):
    urdf = tmp_path / "pendulum.urdf"
    shutil.copy(PENDULUM, urdf)
    before = urdf.read_bytes()
    with pytest.raises(RuntimeError, match="URDF"):
        varsym.Robot(urdf).animate(urdf, [0.0, 1.0], [[0.0], [1.0]])
    assert urdf.read_bytes() == before


def test_a_built_in_models_motion_animates_as_its_figure(tmp_path):
    # The spherical pendulum's bob (its red sphere, at (0, 0, l) on the one body) is at q.
    tr = varsym.simulate("spherical-pendulum", t_span=1.0, h=1e-3)
    out = tr.animate(tmp_path / "pend.html", fps=0)
    page, size = motion(tmp_path / "pend.html")
    assert out["frames"] == page["frames"] == len(tr.t) and out["bytes"] == size
    assert page["names"] == ["x", "y", "z"]
    poses = np.frombuffer(base64.b64decode(page["poses"]), dtype=np.float32).reshape(-1, 7)
    x, w = poses[500, :3].astype(float), poses[500, 3:].astype(float)  # qx, qy, qz, qw
    bob = 2 * np.cross(w[:3], np.cross(w[:3], [0, 0, 1]) + w[3] * np.array([0, 0, 1])) + [0, 0, 1]
    assert np.allclose(x + bob, tr.q[500], atol=1e-6)  # rotate (0, 0, l = 1) by the quaternion
    # The arm's optimal motion too; a model without a figure is refused.
    best = varsym.optimize("arm", time=1.0, q_start=[0, 0, 0], q_end=[1.0, 0.5, 0.2], steps=20)
    assert best.animate(tmp_path / "arm.html")["frames"] == 21
    assert motion(tmp_path / "arm.html")[0]["title"] == "arm: optimal motion"
    kepler = varsym.simulate("kepler", t_span=1.0, steps=100)
    with pytest.raises(varsym.UsageError, match="no 3-D figure"):
        kepler.animate(tmp_path / "k.html")
    assert not (tmp_path / "k.html").exists()
