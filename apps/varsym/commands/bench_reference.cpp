// apps/varsym/commands/bench_reference.cpp: the reference solution of `varsym bench`'s outer solar
// system, which has no closed form: Kahan & Li's order-8 composition of Störmer–Verlet (the
// coefficients of schemes/composition.hpp) in long double, 1 day per step. Its truncation error
// (Jupiter's period is 4333 days: (2π/4333)^8 ≈ 2e-23 per step) and its round-off (~1e-19 per
// step, a random walk over 2·10⁵ steps) are far below the double-precision errors it judges.
#include "commands/bench_methods.hpp"

#include <cmath>

#include "varsym/problems/solar_system.hpp"
#include "varsym/schemes/composition.hpp"

namespace varsym::cli {

namespace {

using LD = long double;
constexpr int bodies = static_cast<int>(solar_system::bodies.size());
using state = std::array<LD, 3 * bodies>;

/// a_i = −G Σ_{j≠i} m_j (q_i − q_j) / |q_i − q_j|³, in long double.
void accelerations(const state& q, state& a) {
    a.fill(0);
    for (int i = 0; i < bodies; ++i)
        for (int j = i + 1; j < bodies; ++j) {
            LD r[3], r2 = 0;
            for (int k = 0; k < 3; ++k) {
                r[k] = q[3 * i + k] - q[3 * j + k];
                r2 += r[k] * r[k];
            }
            const LD inv3 = solar_system::gravitational_constant / (r2 * std::sqrt(r2));
            const LD mi = solar_system::bodies[static_cast<std::size_t>(i)].mass,
                     mj = solar_system::bodies[static_cast<std::size_t>(j)].mass;
            for (int k = 0; k < 3; ++k) {
                a[3 * i + k] -= mj * inv3 * r[k];
                a[3 * j + k] += mi * inv3 * r[k];
            }
        }
}

} // namespace

Eigen::VectorXd solar_reference_positions(double days) {
    state q{}, v{}, a{};
    for (int b = 0; b < bodies; ++b)
        for (int k = 0; k < 3; ++k) {
            q[3 * b + k] = solar_system::bodies[static_cast<std::size_t>(b)].q[k];
            v[3 * b + k] = solar_system::bodies[static_cast<std::size_t>(b)].v[k];
        }
    // The γ as doubles, rescaled in long double to sum to one (consistency; the higher order
    // conditions' ulp-level misses only add terms of size ε h^k).
    const auto gamma = composition::make(composition::method::kahan_li8).gamma;
    LD sum = 0;
    for (double g : gamma)
        sum += g;
    const long steps = std::lround(days);
    const LD h = static_cast<LD>(days) / steps;
    accelerations(q, a);
    for (long n = 0; n < steps; ++n)
        for (double g : gamma) { // kick ½τ, drift τ, kick ½τ
            const LD tau = g / sum * h;
            for (int i = 0; i < 3 * bodies; ++i)
                v[i] += tau / 2 * a[i];
            for (int i = 0; i < 3 * bodies; ++i)
                q[i] += tau * v[i];
            accelerations(q, a);
            for (int i = 0; i < 3 * bodies; ++i)
                v[i] += tau / 2 * a[i];
        }
    Eigen::VectorXd out(3 * bodies);
    for (int i = 0; i < 3 * bodies; ++i)
        out(i) = static_cast<double>(q[i]);
    return out;
}

} // namespace varsym::cli
