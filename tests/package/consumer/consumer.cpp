// A user's program: a double well on the family with a run-time degree, against the installed
// headers. Prints the version, the largest relative energy error over 10 periods and OK.
#include <cmath>
#include <cstdio>

#include <varsym/varsym.hpp>

struct double_well { // V = (q² − 1)²/4
    double value(const varsym::vec<1>& q) const { return 0.25 * std::pow(q(0) * q(0) - 1, 2); }
    varsym::vec<1> gradient(const varsym::vec<1>& q) const {
        return varsym::vec<1>{q(0) * (q(0) * q(0) - 1)};
    }
    varsym::mat<1> hessian(const varsym::vec<1>& q) const {
        return varsym::mat<1>{3 * q(0) * q(0) - 1};
    }
};

int main() {
    const varsym::separable_system<1, double_well> sys(varsym::mat<1>{1.0}, double_well{});
    varsym::phase_state<1> x{varsym::vec<1>{1.5}, varsym::vec<1>{0.0}};
    const double e0 = sys.energy(x);
    double worst = 0;
    varsym::with_stepper({varsym::scheme_kind::gauss, 3}, sys, 0.05, {}, [&](auto& stepper) {
        varsym::integrate(stepper, x, 0.0, 2000, [&](auto, double, const auto& y) {
            worst = std::fmax(worst, std::abs(sys.energy(y) - e0) / e0);
        });
    });
    std::printf("varsym %s: gauss-3, max relative energy error %.2e\n", varsym::version_string,
                worst);
    if (!(worst < 1e-9)) return 1; // order 6 at h = 0.05: about 1e-11
    std::puts("OK");
}
