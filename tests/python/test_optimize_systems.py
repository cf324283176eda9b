"""varsym.optimize on systems known at run time, through the one compiled transcription: a
URDF robot (varsym.Robot), a typed Lagrangian with inputs, and the arm. References: one pendulum
written as a one-joint URDF (recursive derivatives), a typed L (symbolic) and the built-in model
(automatic) reaches one optimum; a robot's torques stay within its URDF efforts and its joints
within their limits, which bind (negative control: without them the optimum differs); the
result is an OptimalControl. Run by CTest (test `python`)."""

import math
import os

import numpy as np
import pytest

import varsym
from test_optimize import pontryagin_gap

DATA = os.path.join(os.path.dirname(__file__), "..", "data", "urdf")


def pendulum_problem(model, **kw):
    return varsym.optimize(model, time=3.0, steps=40, q_start=[0], q_end=[math.pi], **kw)


def test_one_pendulum_three_ways_reaches_one_optimum():
    # L = 0.135 th'^2 + 4.905 cos th: the URDF's link (1 kg, 0.5 m, Iyy 0.02), the same typed,
    # and the built-in pendulum with mass 0.27 and omega^2 = 4.905 / 0.27.
    robot = pendulum_problem(varsym.Robot(os.path.join(DATA, "pendulum.urdf")))
    typed = pendulum_problem(varsym.Lagrangian("0.135*th_dot**2 + 4.905*cos(th)", ["th"]),
                             inputs=["th"])
    model = pendulum_problem("pendulum", mass=0.27, omega=math.sqrt(4.905 / 0.27))
    assert robot.cost == pytest.approx(model.cost, rel=1e-9)
    assert typed.cost == pytest.approx(model.cost, rel=1e-9)
    assert np.abs(robot.q - model.q).max() < 1e-8 and np.abs(typed.u - model.u).max() < 1e-6
    assert robot.inputs == ["th"] and typed.inputs == ["th"] and robot.coordinates == ["th"]
    # Negative control: twice the gravity is another optimum.
    heavy = pendulum_problem(varsym.Lagrangian("0.135*th_dot**2 + 9.81*cos(th)", ["th"]),
                             inputs="th")
    assert abs(heavy.cost - model.cost) > 1e-3 * model.cost


def test_the_result_is_an_optimal_control():
    out = pendulum_problem(varsym.Lagrangian("0.5*th_dot**2 + 9.81*cos(th)", ["th"]),
                           inputs=["th"])
    assert isinstance(out, varsym.OptimalControl)
    assert out.status == "solved" and out.trusted and out.closure < 1e-8
    assert out.q.shape == (41, 1) and out.u.shape == (120, 1) and out["cost"] == out.cost
    assert "OptimalControl lagrangian: solved" in repr(out)


def test_a_robot_keeps_its_urdf_limits_and_they_bind():
    iiwa = varsym.Robot(os.path.join(DATA, "iiwa14_no_collision.urdf"))
    target = [0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2]
    out = varsym.optimize(iiwa, time=2.0, steps=30, q_start=np.zeros(7), q_end=target)
    lim = iiwa.limits
    assert np.all(np.abs(out.u) <= lim["effort"] + 1e-6)
    assert np.all(out.q >= lim["lower"] - 1e-9) and np.all(out.q <= lim["upper"] + 1e-9)
    assert np.allclose(out.q[-1], target, atol=1e-12) and out.closure < 1e-8
    assert out.inputs == iiwa.joints  # every iiwa joint is actuated
    # The node velocities are unknowns within the velocity limits: exactly within, one binding.
    ratio = (np.abs(out.v) / lim["velocity"]).max()
    assert 0.999 < ratio <= 1.0 + 1e-9 and out.velocity_excess < 1e-12
    free = varsym.optimize(iiwa, time=2.0, steps=30, q_start=np.zeros(7), q_end=target,
                           limits=False)
    assert (np.abs(free.v) / lim["velocity"]).max() > 2  # without the limits it goes faster
    assert free.cost < out.cost and free.velocity_excess == 0.0
    # max_velocity tightens every joint's bound: a dearer motion.
    slow = varsym.optimize(iiwa, time=2.0, steps=30, q_start=np.zeros(7), q_end=target,
                           max_velocity=1.0)
    assert slow.cost > out.cost


def test_threads_give_the_same_answer_to_the_bit():
    # A robot's step derivatives on one thread, on three and on every CPU (the default): each
    # step's values are its own (docs/optimal_control.md, "Threads in the derivatives"), so the
    # nodes and controls are equal, not merely close. Negative control: another N differs.
    iiwa = varsym.Robot(os.path.join(DATA, "iiwa14_no_collision.urdf"))
    target = [0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2]
    runs = [varsym.optimize(iiwa, time=2.0, steps=60, q_start=np.zeros(7), q_end=target,
                            scheme="gauss", degree=2, threads=t) for t in (1, 3, 0)]
    for other in runs[1:]:
        assert np.array_equal(other.q, runs[0].q) and np.array_equal(other.u, runs[0].u)
    coarser = varsym.optimize(iiwa, time=2.0, steps=50, q_start=np.zeros(7), q_end=target,
                              scheme="gauss", degree=2, threads=1)
    assert coarser.cost != runs[0].cost
    with pytest.raises(varsym.UsageError, match="threads must be from 0 to 4096"):
        varsym.optimize(iiwa, time=2.0, q_start=np.zeros(7), q_end=target, threads=-1)


def test_a_robot_in_minimum_time_within_its_urdf_efforts():
    # No max_control: the URDF efforts bound the torques (unbounded inputs are refused), and the
    # fastest motion rides a velocity limit (T = 0.567 s). Negative control: limits=False
    # leaves the torques unbounded, refused.
    iiwa = varsym.Robot(os.path.join(DATA, "iiwa14_no_collision.urdf"))
    target = [0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2]
    out = varsym.optimize(iiwa, time=2.0, steps=25, q_start=np.zeros(7), q_end=target,
                          cost={"time": 1.0, "effort": 0.001})
    effort = np.asarray(iiwa.limits["effort"])
    assert out.status == "solved" and out.closure < 1e-8 and out.t[-1] < 1.0
    assert np.all(np.abs(out.u) <= effort * (1 + 1e-9))
    assert 0.999 < (np.abs(out.v) / iiwa.limits["velocity"]).max() <= 1 + 1e-9
    with pytest.raises(varsym.UsageError, match="needs max_control, or a Robot's URDF efforts"):
        varsym.optimize(iiwa, time=2.0, steps=25, q_start=np.zeros(7), q_end=target,
                        cost="time", limits=False)


def test_refusals():
    L = varsym.Lagrangian("0.5*x_dot**2", ["x"])
    with pytest.raises(varsym.UsageError, match="the input 'y' is not a coordinate"):
        varsym.optimize(L, inputs=["y"], time=1.0, q_start=[0], q_end=[1])
    with pytest.raises(varsym.UsageError, match="needs inputs"):
        varsym.optimize(L, time=1.0, q_start=[0], q_end=[1])
    with pytest.raises(varsym.UsageError, match="inputs= and constraints= are a Lagrangian"):
        varsym.optimize("pendulum", inputs=["q"], time=1.0, q_start=[0], q_end=[1])
    robot = varsym.Robot(os.path.join(DATA, "pendulum.urdf"))
    with pytest.raises(varsym.UsageError, match="outside the position bounds"):
        varsym.optimize(robot, time=3.0, q_start=[0], q_end=[5.0])
    text = open(os.path.join(DATA, "pendulum.urdf")).read().replace('effort="100"', 'effort="0"')
    with pytest.raises(varsym.UsageError, match="is actuated"):
        varsym.optimize(varsym.Robot(text=text), time=3.0, q_start=[0], q_end=[1.0])


def test_the_arm_with_joint_torques():
    out = varsym.optimize("arm", time=2.0, steps=30, q_start=[0, 0, 0], q_end=[0.8, 0.5, 0.3])
    assert out.u.shape == (90, 3) and out.closure < 1e-8
    one = varsym.optimize("arm", masses=[2.0], lengths=[1.5], damping=[0.0], time=3.0, steps=40,
                          q_start=[0], q_end=[math.pi])
    typed = pendulum_problem(varsym.Lagrangian("0.5*2*1.5**2*th_dot**2 + 2*9.81*1.5*cos(th)",
                                               ["th"]), inputs=["th"])
    assert one.cost == pytest.approx(typed.cost, rel=1e-9)


def test_a_link_reaches_its_target_pose():
    # The UR5 (six joints) sent to the tool pose of a joint-space problem's end, from a guess
    # near that end: the same optimum and end joints (the pose fixes the joints up to a branch);
    # reach_miss reports the tool on its target. Its pose is computed here by Robot.pose.
    robot = varsym.Robot(os.path.join(DATA, "ur5_robot.urdf"))
    start, end = [0, -1.57, 0, -1.57, 0, 0], np.array([0.5, -1.2, 0.6, -1.4, 0.4, 0.3])
    joints = varsym.optimize(robot, time=2.0, steps=20, q_start=start, q_end=end)
    pose = robot.pose("tool0", end)
    r = pose[:3, :3]
    rpy = [math.atan2(r[2, 1], r[2, 2]), -math.asin(r[2, 0]), math.atan2(r[1, 0], r[0, 0])]
    reach = varsym.optimize(robot, time=2.0, steps=20, q_start=start, q_end=end + 0.05,
                            reach="tool0", reach_position=pose[:3, 3], reach_rpy=rpy)
    assert reach.cost == pytest.approx(joints.cost, rel=1e-8)
    assert np.allclose(reach.q[-1], end, atol=1e-7)
    assert reach.reach_miss[0] < 1e-10 and reach.reach_miss[1] < 1e-7
    assert joints.reach_miss is None
    # Out of reach: SolverError "infeasible", the last iterate kept with its miss.
    iiwa = varsym.Robot(os.path.join(DATA, "iiwa14_no_collision.urdf"))
    with pytest.raises(varsym.SolverError) as far:
        varsym.optimize(iiwa, time=2.0, steps=20, q_start=np.zeros(7), reach="iiwa_link_ee",
                        reach_position=[2.0, 0.0, 1.0])
    assert far.value.status == "infeasible" and far.value.partial.reach_miss[0] > 0.5
    with pytest.raises(varsym.UsageError, match="no link 'hand'"):
        varsym.optimize(robot, time=1.0, q_start=start, reach="hand", reach_position=[0, 0, 1])
    with pytest.raises(varsym.UsageError, match="reach names a link of a robot"):
        varsym.optimize("pendulum", time=1.0, q_start=[0], reach="x", reach_position=[0, 0, 1])


def test_a_typed_lagrangian_under_typed_constraints():
    # A unit mass on the unit circle (Cartesian x, y) pushed horizontally, from hanging to
    # horizontal at rest in 2 s: every node on the circle, and the same optimum as the tool's
    # (tests/cli/optimize_systems_test.sh; against the same system in C++:
    # tests/models/test_optimal_typed.cpp). Negative control: another gravity, another optimum.
    def quarter_turn(g):
        L = varsym.Lagrangian("0.5*(x_dot**2 + y_dot**2) - g*y", ["x", "y"], {"g": g})
        return varsym.optimize(L, inputs=["x"], constraints="x**2 + y**2 - 1", time=2.0,
                               steps=40, q_start=[0, -1], q_end=[1, 0])
    out = quarter_turn(9.81)
    assert out.status == "solved"
    assert out.q.shape == (41, 2)
    assert np.max(np.abs(out.q[:, 0] ** 2 + out.q[:, 1] ** 2 - 1)) < 1e-10
    assert out.closure < 1e-9
    # The tool's cost (11 digits): one transcription, so a check of the binding, not of the
    # optimum. The optimum's own check, independent of what IPOPT or the tool says: Pontryagin's
    # u = λ_px (the push acts on p_x alone, the constraint's force is not an input), measured
    # 3.4e-4 of max |u|; budget 3 times.
    assert out.cost == pytest.approx(11.910305053, rel=1e-9)
    assert pontryagin_gap(out, 0) < 1e-3
    assert abs(quarter_turn(9.0).cost - out.cost) > 1e-3 * out.cost
    with pytest.raises(varsym.UsageError, match="inputs= and constraints= are a Lagrangian"):
        varsym.optimize("pendulum", constraints=["q - 1"], time=1.0, q_start=[0], q_end=[1])
