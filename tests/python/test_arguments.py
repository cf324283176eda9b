"""Numbers a Python call passes to the C++ core are checked, each with an error naming the
argument: counts that are not whole (steps=2.5 became 2), degree 0 (became the default), h = 0
(ZeroDivisionError), NaN (a message about converting NaN to an integer), counts too large for
C++ (pybind11 TypeError), a Stepper with h = 0, NaN or inf (accepted), and non-ASCII text in an
expression (UnicodeDecodeError cut mid-character). Each case failed that way before."""

import math

import pytest

import varsym


@pytest.mark.parametrize("kwargs, message", [
    (dict(steps=2.5), "steps must be a whole number, got 2.5"),
    (dict(steps=True), "steps must be a whole number"),
    (dict(steps=10**30), "steps must be from 1 to 1e15"),
    (dict(scheme="gauss", degree=0), "degree must be from 1 to 8, got 0"),
    (dict(h=0), "h must be a finite positive number, got 0"),
    (dict(h=math.nan), "h must be a finite positive number, got nan"),
    (dict(every=10**30), "every must be from 0 to 1e15"),
])
def test_simulate_refuses_bad_numbers(kwargs, message):
    with pytest.raises(varsym.UsageError, match=message):
        varsym.simulate("pendulum", **kwargs)


@pytest.mark.parametrize("h", [0, math.nan, math.inf, -1e-3])
def test_stepper_refuses_a_bad_step(h):
    with pytest.raises(varsym.UsageError, match="h must be a finite positive number"):
        varsym.Stepper("pendulum", h)


def test_ensembles_refuse_bad_counts():
    with pytest.raises(varsym.UsageError, match="threads must be from 0 to 4096"):
        varsym.Model("kepler").ensemble(q0=[[1, 0]], threads=10**30)
    lag = varsym.Lagrangian("0.5*x_dot**2 - 0.5*x**2", ["x"])
    with pytest.raises(varsym.UsageError, match="steps must be a whole number"):
        lag.ensemble(q0=[[1.0]], steps=10.5)


def test_non_ascii_names_the_character():
    with pytest.raises(varsym.ExpressionError, match="'θ' at column 21 is not ASCII") as e:
        varsym.Lagrangian("0.5*th_dot**2 + cos(θ)", ["th"])
    assert e.value.position == 20


def test_whole_numbers_as_floats_and_in_range_values_are_taken():
    # Negative control: 50.0 steps is 50 steps; degree 2 and every 10 run.
    tr = varsym.simulate("pendulum", steps=50.0, every=10, scheme="gauss", degree=2)
    assert tr.q.shape == (6, 1)


def test_a_dimension_out_of_range_is_refused_before_anything_is_sized():
    # Model("chain", n=2e7) made 2e7 coordinate names (2.8 GB, 10 s) before its range error.
    # The ranges are checked first: the refusal takes well under the time that would take.
    import resource
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with pytest.raises(varsym.UsageError, match=r"chain: n must be .* <= 10000000, got 20000000"):
        varsym.Model("chain", n=2e7)
    with pytest.raises(varsym.UsageError, match="chain: n must be"):
        varsym.Model("chain", n=0)
    grown_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    assert grown_kb < 200_000, f"the refusal grew the process by {grown_kb} kB"
    assert varsym.Model("chain", n=5).dim == 5  # negative control: in range, sized


def test_a_separable_typed_lagrangian_takes_the_separable_predictors():
    # 0.5 q'^2 - 0.5 q^2 runs on the separable steppers, whose '+forces' start python.md
    # offers: it was refused as if it ran the general engine. Same answer as without the start
    # (to round-off) and as cos t; negative control: a configuration-dependent mass is refused.
    import numpy as np
    osc = varsym.Lagrangian("0.5*q_dot**2 - 0.5*q**2", coordinates="q")
    run = dict(q0=[1], t_span=10, steps=100, scheme="gauss", degree=4)
    forces = varsym.simulate(osc, iteration="fixed-point+forces", **run)
    plain = varsym.simulate(osc, iteration="fixed-point", **run)
    assert np.abs(forces.q - plain.q).max() < 1e-14
    assert np.abs(forces.q[:, 0] - np.cos(forces.t)).max() < 1e-12  # gauss-4: 8th order
    with pytest.raises(varsym.UsageError, match="general engine"):
        varsym.simulate(varsym.Lagrangian("0.5*q_dot**2*(1 + q**2) - 0.5*q**2", coordinates="q"),
                        iteration="fixed-point+forces", **run)
