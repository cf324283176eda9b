// tests/numeric/test_round_off.cpp: round-off does not tilt the energy of any member of the
// family over 10⁴ periods: its trend stays within a random walk's reach, and the same stepper
// with its tables plainly rounded to double (the negative control) leaves that reach.
//
// Measure: the pendulum's energy error, averaged over each tenth of the run (10³ periods, so the
// truncation error's oscillation averages to a constant), relative to E; the trend is the last
// average minus the first. Truncation alone gives a constant here (a symplectic scheme's energy
// error is bounded); a step that is not exactly the map of one discrete Lagrangian adds a
// linear drift. Bound: each step adds a round-off error of a few ulps of E, independent from
// step to step, so after n steps a random walk of about √n·ε; the tests allow 10 ε √n (9.8e-13
// at n = 2·10⁵). Measured with the tables as built (tableau::kinetic, wphi with their low parts):
// |trend| ≤ 5.5e-13 for every member (gauss-3, N = 60, the largest), most below 1.5e-13; with
// the low parts dropped, gauss-6 and lobatto-6 at N = 20 drift by +6.1e-12 and +6.3e-12, as the
// textbook form of the equations did (+6.3e-12 and +6.6e-12; docs/design.md, "Round-off").
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;
using std::numbers::pi;

namespace {

constexpr long periods = 10000;
constexpr double eps = std::numeric_limits<double>::epsilon();

double bound(long steps) {
    return 10.0 * eps * std::sqrt(static_cast<double>(steps));
}

/// The last tenth's mean relative energy error minus the first tenth's, over `periods` periods
/// of `n` steps each (energy(x) gives the energy to watch).
template <class Stepper, class Energy>
double energy_trend(Stepper& stepper, phase_state<1> x, int n, const Energy& energy) {
    const double e0 = energy(x);
    const long block = periods / 10 * n;
    double first = 0.0, last = 0.0;
    for (int b = 0; b < 10; ++b) {
        double sum = 0.0;
        for (long j = 0; j < block; ++j) {
            if (!stepper.step(x).converged) return std::numeric_limits<double>::infinity();
            sum += energy(x) - e0;
        }
        last = sum / static_cast<double>(block) / e0;
        if (b == 0) first = last;
    }
    return last - first;
}

const pendulum::system round_off_pendulum = pendulum::make_system(1.0, 2 * pi);

double pendulum_trend(auto& stepper, double q0, int n) {
    return energy_trend(stepper, phase_state<1>{vec<1>{q0}, vec<1>{0.0}}, n,
                        [](const phase_state<1>& y) { return round_off_pendulum.energy(y); });
}

double period(double q0) {
    return pendulum::exact_solution(1.0, 2 * pi, q0, 0.0).period();
}

} // namespace

// Every member through with_stepper (what the tool runs: lobatto-2 and gauss-1 are the reduced
// Simpson and Newmark steppers), at steps per period where its error is small.
TEST(RoundOff, NoMemberTiltsThePendulumsEnergy) {
    const int steps[] = {0, 0, 200, 60, 40, 30, 20}; // by degree
    for (auto kind : {scheme_kind::lobatto, scheme_kind::gauss})
        for (int s = 2; s <= 6; ++s)
            for (double q0 : s >= 5 ? std::vector<double>{pi / 2, 1.0} : std::vector{pi / 2}) {
                const int n = steps[s];
                with_stepper(
                    scheme_spec{kind, s}, round_off_pendulum, period(q0) / n, {},
                    [&](auto& stepper) {
                        EXPECT_LE(std::abs(pendulum_trend(stepper, q0, n)), bound(periods * n))
                            << scheme_spec(kind, s).label() << ", q0 = " << q0;
                    });
            }
}

// The linear iterations stop at the round-off floor (the fixed point's last sweep with its
// tables' low parts, docs/design.md "Solving the step"), from every predictor: a stop that left
// the last iteration's (systematic) remainder would tilt the map as a rounded table does.
TEST(RoundOff, LinearIterationsDoNotTiltTheEnergy) {
    for (auto kind : {galerkin::rule_kind::lobatto, galerkin::rule_kind::gauss})
        for (auto iteration : {iteration_kind::simplified, iteration_kind::fixed_point})
            for (auto predictor :
                 {predictor_kind::taylor, predictor_kind::previous, predictor_kind::forces}) {
                newton_options opt;
                opt.iteration = iteration;
                opt.predictor = predictor;
                galerkin::stepper stepper(round_off_pendulum, period(pi / 2) / 20, kind, 6, opt);
                EXPECT_LE(std::abs(pendulum_trend(stepper, pi / 2, 20)), bound(periods * 20))
                    << (kind == galerkin::rule_kind::gauss ? "gauss-6" : "lobatto-6")
                    << ", iteration " << static_cast<int>(iteration) << ", predictor "
                    << static_cast<int>(predictor);
            }
}

// The general engine, for the members where the textbook equations drifted most.
TEST(RoundOff, GeneralEngineDoesNotTiltTheEnergy) {
    const lagrangian_system sys{separable_lagrangian<pendulum::system>{round_off_pendulum}};
    for (auto kind : {scheme_kind::lobatto, scheme_kind::gauss}) {
        general::stepper stepper(sys, period(pi / 2) / 20, {kind, 6});
        EXPECT_LE(std::abs(pendulum_trend(stepper, pi / 2, 20)), bound(periods * 20))
            << scheme_spec(kind, 6).label();
    }
}

// Degree 1 on the oscillator q'' = −q, with h such that 64 steps are exactly one period of the
// numerical solution (midpoint: ω̃h = 2 atan(h/2); Störmer–Verlet: cos ω̃h = 1 − h²/2): its
// energy error is then exactly periodic, and any trend is round-off.
TEST(RoundOff, FirstMembersOnTheOscillator) {
    struct harmonic {
        [[nodiscard]] double value(const vec<1>& q) const { return 0.5 * q(0) * q(0); }
        [[nodiscard]] vec<1> gradient(const vec<1>& q) const { return q; }
        [[nodiscard]] mat<1> hessian(const vec<1>&) const { return mat<1>{1.0}; }
    };
    const separable_system<1, harmonic> sys(mat<1>{1.0}, harmonic{});
    const auto energy = [&](const phase_state<1>& y) { return sys.energy(y); };
    const phase_state<1> x0{vec<1>{1.0}, vec<1>{0.0}};
    constexpr int n = 64;
    newmark::stepper midpoint(sys, 2.0 * std::tan(pi / n));
    EXPECT_LE(std::abs(energy_trend(midpoint, x0, n, energy)), bound(periods * n)) << "gauss-1";
    galerkin::stepper verlet(sys, 2.0 * std::sin(pi / n), galerkin::rule_kind::lobatto, 1);
    EXPECT_LE(std::abs(energy_trend(verlet, x0, n, energy)), bound(periods * n)) << "lobatto-1";
}

// Negative control: Newton on the residual with the tables' low parts dropped (each coefficient
// plainly rounded to double) drifts beyond the bound, so the measure can see a one-ulp tilt.
// (The fixed point's closed form with its low parts dropped too, sweep.lo and flight.lo, was
// measured within the bound: trends 1.7e-19 and 3.3e-13 for lobatto-6 and gauss-6. It keeps
// them because they make its root the residual's to round-off, tests/schemes/test_iteration.cpp,
// at the cost of one product in its last sweep.)
TEST(RoundOff, PlainlyRoundedTablesDrift) {
    for (auto kind : {galerkin::rule_kind::lobatto, galerkin::rule_kind::gauss}) {
        auto tab = galerkin::tableau::make(kind, 6);
        tab.kinetic.lo.setZero();
        tab.wphi.lo.setZero();
        for (double& w : tab.weights_lo)
            w = 0.0;
        newton_options opt;
        opt.iteration = iteration_kind::newton;
        galerkin::stepper stepper(round_off_pendulum, period(pi / 2) / 20, tab, opt);
        EXPECT_GT(std::abs(pendulum_trend(stepper, pi / 2, 20)), 4.0 * bound(periods * 20))
            << (kind == galerkin::rule_kind::gauss ? "gauss-6" : "lobatto-6");
    }
}
