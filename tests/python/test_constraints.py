"""Typed holonomic constraints g(q) = 0 from Python (varsym.simulate(..., constraints=...)):
the pendulum as a point mass on a rod in Cartesian coordinates, against the built-in pendulum
model in its angle and against the rod's tension (the multiplier), the projection of a start
off the rod, and the refusals. Run by CTest (test `python`)."""

import math

import numpy as np
import pytest

import varsym

ROD = varsym.Lagrangian("0.5*m*(x_dot**2 + y_dot**2) - m*g*y", ["x", "y"],
                        {"m": 2.0, "g": 9.81, "l": 1.5})
THETA0 = 1.0  # from the downward vertical, at rest


def rod_run(steps, length=1.5):
    return varsym.simulate(ROD, constraints=[f"x**2 + y**2 - {length}**2"],
                           q0=[length * math.sin(THETA0), -length * math.cos(THETA0)],
                           t_span=3.0, steps=steps)


def test_rod_pendulum_matches_the_exact_pendulum_and_its_tension():
    m, g, l = 2.0, 9.81, 1.5
    tr = rod_run(600)
    assert list(tr.columns)[-3:] == ["constraint_residual", "hidden_residual", "lambda_1"]
    assert np.max(np.abs(tr["constraint_residual"])) < 1e-13
    assert np.max(np.abs(tr["hidden_residual"])) < 1e-13
    assert np.max(np.abs(tr["energy_balance"])) < 1e-8  # E is conserved: no force
    # The same pendulum in its angle: the built-in model's exact solution (Jacobi elliptic
    # functions), ω² = g / l. Measured: 4.4e-10 at h = 5 ms, 16× less at h/2 (Simpson's order 4).
    ref = varsym.simulate("pendulum", q0=[THETA0], t_span=3.0, steps=600, omega=math.sqrt(g / l))
    theta = np.arctan2(tr["x"], -tr["y"])
    error = np.max(np.abs(theta - ref["q_exact"]))
    assert error < 5e-9
    fine = rod_run(1200)
    fine_error = np.max(np.abs(np.arctan2(fine["x"], -fine["y"])[::2] - ref["q_exact"]))
    assert 12 < error / fine_error < 20
    # The rod's tension T = m g cos θ + m l θ̇² is −Gᵀλ = −2λ q: λ = T / (2 l), up to the
    # multiplier's average over a step (O(h): measured 0.43 % of max T / 2l, 0.22 % at h/2).
    omega = (tr["x"] * tr.p[:, 1] / m - tr["y"] * tr.p[:, 0] / m) / l**2
    tension = m * g * np.cos(theta) + m * l * omega**2
    assert np.max(np.abs(tr["lambda_1"][1:] - tension[1:] / (2 * l))) < 0.01 * np.max(
        tension) / (2 * l)
    # Negative control: another rod length is seen.
    other = rod_run(600, length=1.4)
    assert np.max(np.abs(np.arctan2(other["x"], -other["y"]) - ref["q_exact"])) > 1e-2


def test_a_start_off_the_rod_is_refused_or_projected():
    with pytest.raises(varsym.UsageError, match="project=True"):
        varsym.simulate(ROD, constraints=["x**2 + y**2 - l**2"], q0=[1.0, -1.0], v0=[1.0, 0.0],
                        t_span=0.1, steps=10)
    tr = varsym.simulate(ROD, constraints=["x**2 + y**2 - l**2"], q0=[1.0, -1.0],
                         v0=[1.0, 0.0], t_span=0.1, steps=10, project=True)
    assert abs(math.hypot(tr["x"][0], tr["y"][0]) - 1.5) < 1e-14
    assert abs(tr["x"][0] * tr.p[0, 0] + tr["y"][0] * tr.p[0, 1]) < 1e-13  # tangent


def test_what_is_not_a_holonomic_constraint_is_refused():
    with pytest.raises(varsym.UsageError, match="velocity x_dot"):
        varsym.simulate(ROD, constraints=["x*x_dot"], t_span=0.1, steps=10)
    with pytest.raises(varsym.UsageError, match="constraints= are for a Lagrangian"):
        varsym.simulate("pendulum", constraints=["q"], t_span=0.1, steps=10)
    with pytest.raises(varsym.UsageError, match="needs constraints="):
        varsym.simulate(ROD, project=True, t_span=0.1, steps=10)
    with pytest.raises(varsym.UsageError, match="needs constraints="):
        ROD.ensemble(q0=[[1.5, 0.0]], project=True, t_span=0.1, steps=10)
    with pytest.raises(TypeError, match="constraints"):
        varsym.simulate(ROD, constrains=["x"], t_span=0.1, steps=10)


def test_lagrangian_ensemble_with_constraints():
    # Two starts on the rod's circle at rest (0.9² + 1.2² = 1.5²) and one off it, which is an
    # invalid member naming its cause unless projected.
    starts = [[0.9, -1.2], [1.2, -0.9], [0.3, -1.0]]
    members = ROD.ensemble(q0=starts, constraints=["x**2 + y**2 - l**2"], t_span=1.0, steps=100)
    assert list(members["status"]) == ["completed", "completed", "invalid"]
    assert "off the constraints" in members["cause"][2]
    projected = ROD.ensemble(q0=starts, constraints=["x**2 + y**2 - l**2"], project=True,
                             t_span=1.0, steps=100)
    assert list(projected["status"]) == ["completed"] * 3
    # The circle is kept: |q| = l at the end of every member; E to the scheme's error (7e-10).
    assert np.max(np.abs(np.hypot(projected["q"][:, 0], projected["q"][:, 1]) - 1.5)) < 1e-13
    assert np.max(projected["max_energy_error"]) < 1e-7
