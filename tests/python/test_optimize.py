"""varsym.optimize: the acrobot and cart-pole swing-ups from Python, checked against the targets
and against the general engine's replay of the optimal controls (a second solver of the same
discrete equations), the invariant cost, the refusals, an unreachable target (SolverError with
the last iterate) and Ctrl-C (Interrupted with the last iterate). Run by CTest (test `python`)."""

import math
import os
import signal

import numpy as np
import pytest

import varsym


def pontryagin_gap(out, coordinate):
    """Optimality, checked apart from IPOPT's verdict: for the effort cost ∫ u²/2 with u pushing
    the momentum of `coordinate`, Pontryagin's condition ∂H/∂u = 0 is u(t) = λ_p(t), the costate
    of that momentum (tests/optimal/test_swing_up.cpp: u(0) = λ_ω(0)). The largest |u - λ_p| at
    the control points (λ_p there by the cubic through the four nearest nodes), relative to
    max |u|. A feasible motion that is not optimal has costates (IPOPT's multipliers) that do
    not satisfy it."""
    t, ct, u = out["t"], out["control_t"], out["u"][:, 0]
    lam = out["costate"][:, coordinate]
    gap = 0.0
    for tc, uc in zip(ct, u):
        k = int(np.clip(np.searchsorted(t, tc) - 2, 0, len(t) - 4))
        fit = np.polyfit(t[k:k + 4] - tc, lam[k:k + 4], 3)
        gap = max(gap, abs(uc - fit[-1]))
    return gap / np.abs(u).max()


def feasible_not_optimal(tmp_path, model, **args):
    """The negative control of the optimality checks: IPOPT told to stop at the first iterate that
    meets the equations to 1e-12, whatever its optimality (tol and dual_inf_tol loosened): a
    feasible motion that varsym's own checks (the equations, the closure) accept."""
    opt = tmp_path / "feasible.opt"
    opt.write_text("tol 1e3\ndual_inf_tol 1e6\ncompl_inf_tol 1e6\nconstr_viol_tol 1e-12\n")
    return varsym.optimize(model, ipopt_options=opt, **args)


# Budgets of the optimality checks (measured at the settings of the tests below): Pontryagin's
# |u - λ_p| / max |u| is 0.056 for the acrobot (Simpson, N = 40; 0.031 at N = 80) and 1.9e-3 for
# the cart-pole (gauss-2, N = 40), about twice those; a feasible cart-pole motion that IPOPT did
# not optimise gives 9.7. Gauss-2's cart-pole optimum is 6.4e-6 from Simpson's 37.0226: 3 times.
ACROBOT_GAP = 0.12
CART_POLE_GAP = 4e-3
CART_POLE_SCHEMES = 2e-5


def test_acrobot_swing_up_reaches_upright_at_rest():
    args = dict(time=4.0, steps=40, q_start=[0, 0], q_end=[math.pi, 0])
    out = varsym.optimize("acrobot", **args)
    assert out["status"] == "solved"
    assert out["q"].shape == (41, 2) and out["u"].shape == (120, 1)
    assert np.allclose(out["q"][-1], [math.pi, 0], atol=1e-12)
    assert np.abs(out["v"][-1]).max() < 1e-8  # at rest, from the discrete Legendre transform
    assert out["closure"] < 1e-8
    # The cost is the quadrature of u²/2 with Simpson's weights (the controls are at Lobatto's
    # three points of each step).
    h = 4.0 / 40
    w = np.tile([1 / 6, 4 / 6, 1 / 6], 40) * h
    assert out["cost"] == pytest.approx(float(np.sum(w * 0.5 * out["u"][:, 0] ** 2)), rel=1e-12)
    # Optimal, not merely feasible: the optimum of examples/optimal_swing_ups.cpp (docs/
    # optimal_control.md: 35.2165, the same problem through the C++ models layer), and
    # Pontryagin's u = λ_p2 at the nodes (the elbow torque pushes p2).
    assert out["cost"] == pytest.approx(35.2165, abs=5e-5)  # documented to 6 digits
    assert pontryagin_gap(out, 1) < ACROBOT_GAP


def test_cart_pole_gauss_with_bounded_push_and_progress(tmp_path):
    seen = []
    args = dict(time=2.0, steps=40, scheme="gauss", degree=2, q_start=[0, math.pi], q_end=[0, 0],
                max_control=30.0)
    out = varsym.optimize("cart-pole", progress=lambda it, cost, inf: seen.append(it), **args)
    assert out["status"] == "solved" and seen == list(range(len(seen))) and len(seen) > 1
    assert np.abs(out["u"]).max() <= 30.0 + 1e-6
    assert out["closure"] < 1e-8
    # Optimal, not merely feasible: the bound is not active (max |u| below 30 N), so this is the
    # unbounded problem of examples/optimal_swing_ups.cpp, whose Simpson optimum at N = 40 is
    # 37.0226 (docs/optimal_control.md): gauss-2, another quadrature, must agree to the two
    # schemes' difference (both order 4), and Pontryagin's u = λ_px holds at the nodes.
    assert out["controls_at_bound"] == 0
    assert out["cost"] == pytest.approx(37.0226, rel=CART_POLE_SCHEMES)
    assert pontryagin_gap(out, 0) < CART_POLE_GAP
    # Negative control: a feasible motion that IPOPT did not optimise passes varsym's own checks
    # (the equations, the closure) and fails both of these.
    loose = feasible_not_optimal(tmp_path, "cart-pole", **args)
    assert loose["closure"] < 1e-8 and loose["constraint_violation"] < 1e-10
    assert loose["cost"] > out["cost"] * (1 + 10 * CART_POLE_SCHEMES)
    assert pontryagin_gap(loose, 0) > 100 * CART_POLE_GAP


def test_free_end_and_terminal_weight():
    # The cart-pole swing-up with the cart's final place and speed free costs less than with the
    # cart brought back to 0; a terminal weight on its place pulls it back, at a cost between.
    common = dict(time=2.0, steps=40, scheme="gauss", degree=2, q_start=[0, math.pi],
                  q_end=[0, 0], max_control=30.0)
    fixed = varsym.optimize("cart-pole", **common)
    free = varsym.optimize("cart-pole", free_end="q1,v1", **common)
    pulled = varsym.optimize("cart-pole", free_end={"q1": 1000.0, "v1": 0.0}, **common)
    assert free["cost"] < pulled["cost"] < fixed["cost"]
    assert abs(pulled["q"][-1, 0]) < abs(free["q"][-1, 0]) / 10
    for out in (free, pulled):  # the pole still ends upright at rest
        assert abs(out["q"][-1, 1]) < 1e-12 and abs(out["v"][-1, 1]) < 1e-8
        assert out["closure"] < 1e-8
    with pytest.raises(varsym.UsageError, match="'q3' is not a coordinate"):
        varsym.optimize("cart-pole", free_end=["q3"], **common)


def test_invariant_cost_differs_from_effort():
    # 80 steps: the invariant optimum spins the elbow fast (|q2'| ~ 14 rad/s); at 30 steps
    # h |q2'| ~ 2 and the general engine's Newton, started from its own predictor, cannot
    # replay every step (closure_failure says which).
    # The effort optimum refined from N = 40 (cost 35.2); solved directly at N = 80, IPOPT
    # reaches another extremal (test_refinement_solves_from_a_coarser_solution).
    effort = varsym.optimize("acrobot", time=4.0, steps=80, refine=1, q_start=[0, 0],
                             q_end=[math.pi, 0])
    invariant = varsym.optimize("acrobot", time=4.0, steps=80, q_start=[0, 0],
                                q_end=[math.pi, 0], cost="invariant")
    assert invariant["status"] in ("solved", "acceptable")
    assert invariant["closure"] < 1e-8, invariant["closure_advice"]
    assert np.abs(invariant["u"] - effort["u"]).max() > 0.1  # a different optimum
    # Each optimum is the better at its own cost: the effort ∫ u²/2 of the invariant optimum's
    # controls (Simpson's quadrature, as the cost is computed) is above the effort optimum's.
    # The other direction, the invariant cost of both, is in tests/optimal/test_costs.cpp.
    w = np.tile([1 / 6, 4 / 6, 1 / 6], 80) * (4.0 / 80)
    assert effort["cost"] == pytest.approx(float(np.sum(w * 0.5 * effort["u"][:, 0] ** 2)),
                                           rel=1e-12)
    assert float(np.sum(w * 0.5 * invariant["u"][:, 0] ** 2)) > effort["cost"] + 1.0
    assert pontryagin_gap(effort, 1) < ACROBOT_GAP


def test_minimum_time_saturates_the_push():
    args = dict(time=3.0, steps=40, q_start=[0, math.pi], q_end=[1, math.pi], max_control=10.0,
                cost={"time": 1.0, "effort": 0.001})
    out = varsym.optimize("cart-pole", **args)
    # The horizon found is the minimum, not any T below the first guess: gauss-2, another
    # quadrature, finds the same T (measured 1.32584 and 1.32572 s, 8.9e-5 apart relative;
    # Simpson at N = 80: 1.32578); budget 3e-4, 3.4 times.
    other = varsym.optimize("cart-pole", scheme="gauss", degree=2, **args)
    assert out["t"][-1] == pytest.approx(other["t"][-1], rel=3e-4)
    assert out["t"][-1] == pytest.approx(1.32578, rel=3e-4)
    assert np.abs(out["u"]).max() == pytest.approx(10.0, abs=1e-6)
    assert out["closure"] < 1e-8
    # The active bound is counted, as the values at |u| = 10 are, to the check's 1e-9 (1 + |10|)
    # (include/varsym/optimal/solution_check.hpp; the exact Hessian's iterates stop 5e-9 to
    # 2.3e-8 inside the bound).
    assert out["controls_at_bound"] == np.sum(np.abs(np.abs(out["u"]) - 10.0) <= 1.1e-8) > 0


def test_refinement_solves_from_a_coarser_solution():
    # The acrobot has many extremals. Refined from N = 40, IPOPT reaches one of cost 35.2 at
    # N = 80; from the interpolated start it reaches another, which one depending on the round-off
    # of the linear algebra (measured: cost 45.5 with Debian's reference BLAS; 47.4 with OpenBLAS
    # on an AVX-512 machine, on spurious roots of the step equations, one step moving 5.2 rad, so
    # not trusted). The direct solve is only the comparison: its cost counts whether or not the
    # simulator replays it.
    try:
        direct = varsym.optimize("acrobot", time=4.0, steps=80, q_start=[0, 0],
                                 q_end=[math.pi, 0])
    except varsym.SolverError as e:  # an optimum, of the equations, whose replay alone failed
        direct = e.partial
        assert e.status == "solved" and not direct["trusted"], str(e)
        assert not direct["closure"] <= 1e-6  # NaN where the replay threw
        assert direct["constraint_violation"] < 1e-8
        assert np.allclose(direct["q"][-1], [math.pi, 0], atol=1e-12)
    refined = varsym.optimize("acrobot", time=4.0, steps=80, refine=1, q_start=[0, 0],
                              q_end=[math.pi, 0])
    assert refined["status"] == "solved" and refined["closure"] < 1e-8
    assert np.allclose(refined["q"][-1], [math.pi, 0], atol=1e-12)
    assert refined["cost"] < direct["cost"] - 1.0


def test_an_optimum_on_a_spurious_root_is_not_trusted():
    # Refined from N = 20, the N = 40 "optimum" costs 4.35: it rides on roots of the step
    # equations that the simulator does not reach (h |q'| of order 1); its replay ends
    # 4.75 rad away. SolverError says so, with the result in .partial.
    with pytest.raises(varsym.SolverError, match="too coarse") as e:
        varsym.optimize("acrobot", time=4.0, steps=40, refine=1, q_start=[0, 0],
                        q_end=[math.pi, 0])
    assert e.value.status == "solved" and not e.value.partial["trusted"]
    assert e.value.partial["closure"] > 1.0


def test_refusals():
    with pytest.raises(varsym.UsageError, match="needs max_control"):
        varsym.optimize("cart-pole", time=2.0, q_start=[0, 0], q_end=[1, 0], cost="time")
    with pytest.raises(varsym.UsageError, match="no control input"):
        varsym.optimize("oscillator", time=2.0, q_start=[0, 0], q_end=[1, 0])
    with pytest.raises(varsym.UsageError, match="unknown cost term"):
        varsym.optimize("acrobot", time=2.0, q_start=[0, 0], q_end=[1, 0], cost="speed")
    with pytest.raises(varsym.UsageError, match="q_end needs 2 values"):
        varsym.optimize("acrobot", time=2.0, q_start=[0, 0], q_end=[1])
    with pytest.raises(varsym.UsageError, match="time horizon must be positive"):
        varsym.optimize("acrobot", time=-1.0, q_start=[0, 0], q_end=[1, 0])


def test_unreachable_target_raises_with_the_last_iterate():
    with pytest.raises(varsym.SolverError) as e:
        varsym.optimize("acrobot", time=4.0, q_start=[0, 0], q_end=[math.pi, 0],
                        max_control=0.01)
    assert e.value.status == "infeasible"
    assert e.value.partial["q"].shape == (51, 2)


def test_ctrl_c_stops_the_solver_with_the_last_iterate():
    def interrupt(iteration, cost, infeasibility):
        if iteration == 2:
            os.kill(os.getpid(), signal.SIGINT)
    with pytest.raises(varsym.Interrupted) as e:
        varsym.optimize("acrobot", time=4.0, steps=40, q_start=[0, 0], q_end=[math.pi, 0],
                        progress=interrupt)
    assert e.value.partial["iterations"] <= 3
    assert e.value.partial["q"].shape == (41, 2)


def test_optimize_from_two_threads_at_once():
    # IPOPT's sequential MUMPS keeps global state: two solves at once crashed the interpreter
    # (SIGSEGV or a Fortran runtime error, 8 runs in 8). The solves now take turns; both give
    # the one-thread answer to the last bit.
    import threading

    args = dict(time=4.0, steps=40, q_start=[0, 0], q_end=[math.pi, 0])
    alone = varsym.optimize("acrobot", **args)
    results = [None] * 4

    def run(k):
        results[k] = varsym.optimize("acrobot", **args)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for out in results:
        assert out["status"] == "solved" and out["cost"] == alone["cost"]
        assert np.array_equal(out["u"], alone["u"])



def test_loosened_ipopt_options_are_caught_by_varsyms_own_check(tmp_path):
    # With its tolerances loosened and one iteration allowed, IPOPT calls the starting guess
    # "solved" (max |g| = 1.6; v(T) = 0 where 3 was asked). varsym re-evaluates the equations
    # and refuses it. Negative control: the same problem without the file is solved.
    loose = tmp_path / "loose.opt"
    loose.write_text("tol 1e3\nconstr_viol_tol 10\ndual_inf_tol 1e6\ncompl_inf_tol 1e6\n"
                     "max_iter 1\n")
    args = dict(time=2.0, q_start=[0], q_end=[3.14159], v_end=[3.0])
    with pytest.raises(varsym.SolverError, match="equations are not met") as e:
        varsym.optimize("pendulum", ipopt_options=loose, **args)
    assert e.value.status == "solved" and e.value.partial["constraint_violation"] > 1.0
    good = varsym.optimize("pendulum", **args)
    assert good["constraint_violation"] < 1e-10 and abs(good["v"][-1][0] - 3.0) < 1e-10
    (tmp_path / "bad.opt").write_text("no_such_option 1\n")
    with pytest.raises(varsym.UsageError, match="not an IPOPT option"):
        varsym.optimize("pendulum", ipopt_options=tmp_path / "bad.opt", **args)


def test_a_problem_too_large_for_memory_is_refused_before_it_is_sized():
    # 1e8 steps reached 24 GB before the OOM killer ended the process.
    with pytest.raises(varsym.UsageError, match=r"steps need about .* at most about \d+ steps fit"):
        varsym.optimize("acrobot", time=4.0, steps=10**8, q_start=[0, 0], q_end=[3, 0])
