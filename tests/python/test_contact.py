"""Contact from Python (varsym.Robot(..., contact=1)): a ball thrown without spin on the ground
ends rolling at 5/7 of its speed (I = 2/5 m r^2, the classical result), never sinking; the
contact parameters without contact are refused."""
import os

import numpy as np
import pytest

import varsym

DATA = os.path.join(os.path.dirname(__file__), "..", "data", "urdf")
BALL = os.path.join(DATA, "contact_ball.urdf")


def test_a_thrown_ball_ends_rolling_at_five_sevenths_of_its_speed():
    robot = varsym.Robot(BALL, base="free", contact=1, friction=0.3)
    run = varsym.simulate(robot, t_span=(0.0, 1.0), steps=1000, q0=[0, 0, 0.4, 1, 0, 0, 0],
                          v0=[1, 0, 0, 0, 0, 0, 0])
    # Dropped 0.3 m while moving at 1 m/s: lands, slides, then rolls (after 2 v0/(7 mu g) =
    # 0.1 s of sliding) at 5/7 m/s; the speed's error is O(h) (measured 3e-6 m/s).
    assert run["base_vx"][-1] == pytest.approx(5.0 / 7.0, abs=3e-5)
    assert run.q[-1, 2] == pytest.approx(0.1, abs=1e-9)  # base_z: at its radius
    assert run["penetration"].max() < 1e-12
    assert run["contacts"][-1] == 1
    # Not vacuous: with friction 0 it keeps sliding at 1 m/s.
    slide = varsym.simulate(varsym.Robot(BALL, base="free", contact=1, friction=0.0),
                            t_span=(0.0, 1.0), steps=1000, q0=[0, 0, 0.4, 1, 0, 0, 0],
                            v0=[1, 0, 0, 0, 0, 0, 0])
    assert slide["base_vx"][-1] == pytest.approx(1.0, abs=1e-9)


def test_contact_parameters_without_contact_are_refused():
    with pytest.raises(varsym.UsageError, match="give contact too"):
        varsym.simulate(varsym.Robot(BALL, base="free", friction=0.3), t_span=(0.0, 1.0),
                        steps=10, q0=[0, 0, 0.4, 1, 0, 0, 0])


def test_an_ensemble_of_drops_rests_and_needs_no_indicators():
    robot = varsym.Robot(BALL, base="free", contact=1)
    q0 = np.tile([0.0, 0.0, 0.4, 1.0, 0.0, 0.0, 0.0], (3, 1))
    q0[:, 2] = [0.3, 0.4, 0.5]
    with pytest.raises(varsym.UsageError, match="indicators=False"):
        robot.ensemble(q0=q0, t_span=0.5, steps=500)
    members = robot.ensemble(q0=q0, t_span=0.5, steps=500, indicators=False)
    assert list(members["status"]) == ["completed"] * 3
    assert np.allclose(members["q"][:, 2], 0.1, atol=1e-9)  # each at rest at its radius
    # The stepper steps the same way.
    stepper = varsym.Stepper(robot, 1e-3, q0=[0, 0, 0.4, 1, 0, 0, 0])
    stepper.step(1000)
    assert stepper.q[2] == pytest.approx(0.1, abs=1e-9)
