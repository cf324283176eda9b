"""The Python package: built-in models and the paper through varsym.run/table1, expression
Lagrangians (strings, SymPy, functions) against the built-in models and conservation laws, and
errors as exceptions. Run by CTest (test `python`) with PYTHONPATH at the build's package."""

import math

import numpy as np
import pytest

import varsym

DOUBLE_PENDULUM = ("0.5*(m1+m2)*l1**2*th1_dot**2 + 0.5*m2*l2**2*th2_dot**2"
                   " + m2*l1*l2*th1_dot*th2_dot*cos(th1-th2) + (m1+m2)*g*l1*cos(th1)"
                   " + m2*g*l2*cos(th2)")
DP_PARAMETERS = {"m1": 1.0, "m2": 1.0, "l1": 1.0, "l2": 1.0, "g": 9.81}

# Table 1 of Dubois & Rojas-Quintero (2023) as printed (3 digits): Simpson's state errors at
# N = 50, 100, 200 steps per period (docs/design.md cites the paper).
PAPER_SIMPSON_STATE = [1.05e-6, 6.51e-8, 4.06e-9]


def test_table1_matches_the_paper():
    tab = varsym.table1()
    rows = tab[(tab["scheme"] == "simpson") & (tab["quantity"] == "state")]
    assert len(rows) == 3
    for got, want in zip(sorted(rows, key=lambda r: r["steps"]), PAPER_SIMPSON_STATE):
        assert abs(got["error"] - want) <= 0.01 * want


def test_kepler_run_follows_the_exact_orbit_and_conserves():
    tr = varsym.run("kepler", scheme="gauss", degree=4, steps_per_period=200, periods=10,
                    eccentricity=0.5)
    assert tr.q.shape == (2001, 2) and tr.q_exact.shape == (2001, 2)
    # Gauss-4 (order 8) at 200 steps per period: far below 1e-6 from the exact orbit.
    assert np.max(np.abs(tr.q - tr.q_exact)) < 1e-6
    assert np.ptp(tr.energy) < 1e-10
    assert np.ptp(tr["angular_momentum"]) < 1e-12  # a symmetry: conserved to round-off


def test_run_takes_the_predictor_in_process_as_the_tool_does():
    # predictor="forces" runs in-process (iteration "fixed-point+forces"); newton_max_iter (at
    # its default) sends the same run through the command-line engine: the same steps.
    opts = dict(scheme="gauss", degree=4, steps_per_period=50, periods=20, eccentricity=0.6,
                iteration="fixed-point", predictor="forces")
    here = varsym.run("kepler", **opts)
    tool = varsym.run("kepler", newton_max_iter=25, **opts)
    assert np.array_equal(here.q, tool.q) and np.array_equal(here.p, tool.p)
    # Negative control: the Taylor start takes other steps (round-off apart, not identical).
    taylor = varsym.run("kepler", **dict(opts, predictor="taylor"))
    assert not np.array_equal(here.q, taylor.q)
    assert np.max(np.abs(here.q - taylor.q)) < 1e-9


def test_expression_double_pendulum_matches_the_builtin_model():
    # Same scheme and steps: the two differ only by round-off in L's derivatives (the built-in
    # model is differentiated by AD), amplified by the chaotic motion over 1 s.
    builtin = varsym.run("double-pendulum", time=1.0, steps=1000, q0=[1.0, 0.5])
    lag = varsym.Lagrangian(DOUBLE_PENDULUM, ["th1", "th2"], DP_PARAMETERS)
    own = varsym.Stepper(lag, 1e-3, q0=[1.0, 0.5]).run(1000, every=1)
    assert np.max(np.abs(own["q"] - builtin.q)) < 1e-9
    assert np.max(np.abs(own["p"] - builtin.p)) < 1e-9
    # Negative control: another g is seen.
    other = varsym.Stepper(varsym.Lagrangian(DOUBLE_PENDULUM, ["th1", "th2"],
                                             dict(DP_PARAMETERS, g=9.8)), 1e-3, q0=[1.0, 0.5])
    assert np.max(np.abs(other.run(1000)["q"][-1] - builtin.q[-1])) > 1e-4


def test_command_line_lagrangian_equals_the_stepper():
    lag = varsym.Lagrangian("0.5*q_dot**2 - 0.5*w**2*q**2 - 0.25*q**4", ["q"], {"w": 2.0})
    by_cli = varsym.run(lagrangian=lag, time=2.0, steps=200, q0=[1.0], scheme="gauss", degree=3)
    by_stepper = varsym.Stepper(lag, 0.01, scheme="gauss", degree=3, q0=[1.0]).run(200)
    assert np.array_equal(by_cli.q, by_stepper["q"])
    assert np.array_equal(by_cli.p, by_stepper["p"])


def test_lagrangian_section_finds_the_exact_crossings():
    # L = x_dot²/2 − 2x² (ω = 2) from x = 1 crosses x = 0 upwards at t_n = (3π/2 + 2πn)/2 with
    # p = 2 (exact solution); gauss-2 at h = 0.01: phase error ~ (hω)⁴ωt/720 ~ 1e-8 at t = 20.
    lag = varsym.Lagrangian("0.5*x_dot**2 - 2*x**2", ["x"])
    s = varsym.Stepper(lag, 0.01, scheme="gauss", degree=2, q0=[1.0])
    times, states = s.section("q1=0", "+", 2000, 100)
    n = np.arange(len(times))
    assert len(times) == 6
    assert np.allclose(times, (1.5 * np.pi + 2 * np.pi * n) / 2, rtol=0, atol=1e-6)
    assert np.allclose(states[:, 1], 2.0, rtol=0, atol=1e-6)
    assert np.allclose(states[:, 0], 0.0, rtol=0, atol=1e-9)


def test_time_dependent_lagrangian_balances_its_energy():
    # L = x_dot²/2 − (1 + t/2)x²/2: E grows by dE/dt = −∂L/∂t = x²/4 (more than 10 % over 10 s),
    # E − E0 − W with W = −∫∂L/∂t dt stays at Simpson's error (h = 0.01: below 1e-6).
    lag = varsym.Lagrangian("0.5*x_dot**2 - 0.5*(1 + 0.5*t)*x**2", ["x"])
    assert lag.depends_on_time
    rows = varsym.Stepper(lag, 0.01, q0=[1.0]).run(1000)
    assert rows["energy"][-1] - rows["energy"][0] > 0.1 * rows["energy"][0]
    assert np.abs(rows["energy_balance"]).max() < 1e-6


def test_cyclic_coordinate_keeps_its_momentum_to_round_off():
    # Kepler in polar coordinates: phi is cyclic, so p_phi is conserved exactly by the
    # discrete Noether theorem; the energy error stays bounded.
    lag = varsym.Lagrangian("0.5*(r_dot**2 + r**2*ph_dot**2) + k/r", "r,ph", {"k": 1.0})
    s = varsym.Stepper(lag, 0.01, q0=[1.0, 0.0], v0=[0.0, 1.2])
    rows = s.run(5000, every=10)
    p_phi = rows["p"][:, 1]
    assert np.max(np.abs(p_phi - p_phi[0])) < 1e-13
    assert np.ptp(rows["energy"]) < 1e-5


def test_sympy_and_function_give_the_string_lagrangian():
    import sympy  # not importorskip: make test installs python3-sympy, so its absence must fail
    th, th_dot, m, g = sympy.symbols("th th_dot m g")
    text = varsym.Lagrangian("m*th_dot**2/2 + m*g*cos(th)", ["th"], {"m": 2.0, "g": 9.81})
    sym = varsym.Lagrangian(m * th_dot**2 / 2 + m * g * sympy.cos(th), ["th"],
                            {"m": 2.0, "g": 9.81})
    fun = varsym.Lagrangian.from_function(
        lambda q, v, t, m, g: m * v[0]**2 / 2 + m * g * sympy.cos(q[0]), ["th"],
        {"m": 2.0, "g": 9.81})
    for other in (sym, fun):
        for q, v in [(0.3, 0.1), (2.0, -1.0)]:
            a, b = text.derivatives([q], [v]), other.derivatives([q], [v])
            for key in a:
                assert np.allclose(a[key], b[key], rtol=1e-15, atol=1e-15), key


def test_time_dependent_lagrangian():
    # Caldirola–Kanai: L = e^{γt}(q̇² − ω²q²)/2, whose momentum is e^{γt} q̇.
    lag = varsym.Lagrangian("exp(c*t)*0.5*(q_dot**2 - q**2)", ["q"], {"c": 0.1})
    assert lag.depends_on_time
    assert lag.momentum([0.0], [2.0], t=3.0)[0] == pytest.approx(2.0 * math.exp(0.3))


def test_errors_are_exceptions_with_the_tool_messages():
    with pytest.raises(varsym.ExpressionError) as e:
        varsym.Lagrangian("0.5*q_dot**2 - (q", ["q"])
    assert e.value.position == 17 and "at column 18" in str(e.value)
    with pytest.raises(varsym.ExpressionError, match="unknown name 'mass'"):
        varsym.Lagrangian("0.5*mass*q_dot**2", ["q"])
    with pytest.raises(varsym.UsageError, match="eccentricity must be 0 <= eccentricity < 1"):
        varsym.run("kepler", eccentricity=1.5)
    with pytest.raises(varsym.UsageError, match="singular"):
        varsym.run(lagrangian="q**2*q_dot**2", q0=[0.0])
    with pytest.raises(ValueError, match="singular"):
        varsym.Stepper(varsym.Lagrangian("q*q_dot**3"), 0.1)


def test_nan_during_a_step_is_a_step_failure_keeping_the_rows_before_it():
    # sqrt(q) is NaN once q < 0: the particle accelerates towards q = 0 (V = -1/q) and crosses.
    lag = varsym.Lagrangian("0.5*q_dot**2 + 1/sqrt(q)", ["q"])
    s = varsym.Stepper(lag, 0.01, q0=[1.0], max_energy_error=0)  # the watch would stop it first
    with pytest.raises(varsym.StepFailure) as e:
        s.run(10000, every=1)
    assert e.value.step is not None and e.value.step > 1
    assert len(e.value.partial["t"]) == e.value.step  # rows 0 … step − 1
    assert np.all(np.isfinite(e.value.partial["q"]))
    assert s.steps == e.value.step - 1 and np.isfinite(s.q[0])
    with pytest.raises(varsym.StepFailure) as e:
        varsym.run(lagrangian=lag.expression, q0=[1.0], time=100.0, steps=10000,
                   max_energy_error=0)
    assert e.value.partial is not None and len(e.value.partial) > 1
    assert "the exception's .partial" in str(e.value)


def test_damping_force_keeps_the_energy_balance():
    # A damped pendulum: E falls, and E − E0 equals the forces' work up to the scheme's error
    # (Simpson, order 4, h = 0.01: measured 5e-12 over 10 s; bound 1e-9). Negative control:
    # the energy did fall, by far more than the bound.
    lag = varsym.Lagrangian("0.5*q_dot**2 + cos(q)", ["q"])
    with pytest.raises(varsym.ExpressionError):
        varsym.Stepper(lag, 0.01, q0=[1.0], force=["-c*q_dot"])  # c is not a parameter
    lag = varsym.Lagrangian("0.5*q_dot**2 + cos(q)", ["q"], {"c": 0.1})
    s = varsym.Stepper(lag, 0.01, q0=[1.0], force=["-c*q_dot"])
    e0 = s.energy
    s.step(1000)
    assert s.energy - e0 < -0.2
    assert abs(s.energy - e0 - s.work) < 1e-9
    tr = varsym.run(lagrangian=lag, force=["-c*q_dot"], q0=[1.0], time=10, steps=1000)
    assert abs(tr["energy_balance"]).max() < 1e-9
    assert tr.q[-1, 0] == s.q[0]  # the tool and the Stepper take the same steps
