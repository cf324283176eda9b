"""Robots and files from Python that must not hang, be ignored or be read without bound: Ctrl-C on
a robot whose steps are slow (a long chain), a simulation-only parameter given to optimize, and
an IPOPT options "file" that is a directory. Run by CTest (test `python`)."""

import os
import signal
import subprocess
import sys
import time

import pytest

import varsym


def chain_urdf(links):
    """A planar chain of `links` revolute links (1 kg, 0.1 m, about y), built as text."""
    parts = ['<robot name="chain"><link name="l0"/>']
    for i in range(1, links + 1):
        parts.append(
            f'<link name="l{i}"><inertial><origin xyz="0 0 -0.05"/><mass value="1"/>'
            f'<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/>'
            f'</inertial></link><joint name="j{i}" type="continuous"><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><origin xyz="0 0 {-0.1 if i > 1 else 0}"/>'
            f'<axis xyz="0 1 0"/></joint>')
    parts.append("</robot>")
    return "".join(parts)


SLOW_CHILD = """
import sys, time, varsym
sys.path.insert(0, {here!r})
from test_inputs import chain_urdf
robot = varsym.Robot(text=chain_urdf({links}))
robot.simulate(q0=[0.0] * {links}, t_span=0.001, steps=1)  # warm
start = time.time()
robot.simulate(q0=[0.0] * {links}, t_span=0.004, steps=4)  # the cost of one step
step = (time.time() - start) / 4
print("ready", step, flush=True)
try:
    robot.simulate(q0=[0.0] * {links}, t_span=1e4, steps=10**7, every=10**6)
except varsym.Interrupted as e:
    print(time.time(), e.stepper.steps, flush=True)
    sys.exit(7)
"""


def test_ctrl_c_stops_a_slow_robot_within_0_2_s_plus_a_step():
    # 250 links hanging at rest: each step takes about 10 ms (printed below), so that the 64
    # steps the stop flag was once read after take over half a second; the bound is the
    # documented 0.2 s plus the step in flight (not cut short) and one step of slack.
    here = os.path.dirname(os.path.abspath(__file__))
    child = subprocess.Popen([sys.executable, "-c", SLOW_CHILD.format(here=here, links=250)],
                             stdout=subprocess.PIPE, text=True, env={**os.environ})
    word, step = child.stdout.readline().split()
    assert word == "ready"
    step = float(step)
    assert 64 * step > 0.2 + 2 * step, f"a step of {step:.4f} s is too cheap to test the bound"
    time.sleep(1.0)
    sent = time.time()
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=120)
    assert child.returncode == 7, out
    stopped, steps = out.split()
    print(f"step {step * 1e3:.1f} ms, stopped {float(stopped) - sent:.3f} s after SIGINT, "
          f"{steps} steps")
    assert float(stopped) - sent < 0.2 + 2 * step
    assert int(steps) >= 1


def test_a_forty_link_chain_swings():
    # Its mass matrix has a condition number of 7e6 at q = 0.05 (NumPy's cond of
    # Robot.mass_matrix): the velocity of a row, solved from p, stops improving at about
    # 1e-9 |v|, which the velocity solve once did not accept ("could not solve dL/dqdot = p" at
    # step 2). Reference: energy, conserved by Simpson to its order-4 error at h = 1 ms (budget
    # 1e-6 of the swing's 20 J energy scale, measured below 1e-9 of it).
    robot = varsym.Robot(text=chain_urdf(40))
    tr = robot.simulate(q0=[0.05] * 40, t_span=0.1, steps=100, every=10)
    energy = tr.energy
    assert len(energy) == 11
    assert abs(energy - energy[0]).max() < 1e-6 * 20.0


def test_optimize_refuses_a_simulation_only_parameter():
    robot = varsym.Robot(os.path.join(os.path.dirname(__file__), "..", "data", "urdf",
                                      "pendulum.urdf"))
    with pytest.raises(varsym.UsageError, match="simulation's parameter"):
        varsym.optimize(robot, time=1.0, steps=10, q_start=[0.0], q_end=[0.5], kp=[10.0])
    # Negative control: without kp the same problem is solved.
    assert varsym.optimize(robot, time=1.0, steps=10, q_start=[0.0], q_end=[0.5]).status == \
        "solved"


def test_an_ipopt_options_directory_is_refused_at_once(tmp_path):
    start = time.time()
    with pytest.raises(varsym.UsageError, match="it is a directory"):
        varsym.optimize("pendulum", time=1.0, steps=10, q_start=[0.0], q_end=[0.5],
                        ipopt_options=str(tmp_path))
    assert time.time() - start < 5.0
