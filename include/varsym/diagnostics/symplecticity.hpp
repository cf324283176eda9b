// varsym/diagnostics/symplecticity.hpp: the tangent map of a step by finite differences, and
// its symplecticity defect |Jᵀ Ω J − Ω|. Independent of how the scheme is written: it only
// calls the step map.
#pragma once

#include <stdexcept>

#include "varsym/types.hpp"

namespace varsym {

/// J = ∂(q_{j+1}, p_{j+1}) / ∂(q_j, p_j) by central differences with one Richardson
/// extrapolation (error O(δ⁴) + O(ε/δ)). `step(x)` must advance x by one step in place.
template <int D, class StepMap>
mat<blocks(2, D)> tangent_map(StepMap&& step, const phase_state<D>& x, double delta = 1e-3) {
    constexpr int Z = blocks(2, D);
    const int d = static_cast<int>(x.q.size());
    auto flow = [&](const vec<Z>& z) {
        phase_state<D> y{block_of<D>(z, 0, d), block_of<D>(z, 1, d)};
        step(y);
        vec<Z> out(2 * d);
        block_of<D>(out, 0, d) = y.q;
        block_of<D>(out, 1, d) = y.p;
        return out;
    };
    vec<Z> z(2 * d);
    block_of<D>(z, 0, d) = x.q;
    block_of<D>(z, 1, d) = x.p;
    mat<Z> jac(2 * d, 2 * d);
    for (int i = 0; i < 2 * d; ++i) {
        auto central = [&](double dl) {
            vec<Z> plus = z, minus = z;
            plus(i) += dl;
            minus(i) -= dl;
            return vec<Z>((flow(plus) - flow(minus)) / (2.0 * dl));
        };
        jac.col(i) = (4.0 * central(0.5 * delta) - central(delta)) / 3.0;
    }
    return jac;
}

/// max |Jᵀ Ω J − Ω| with Ω = [[0, I], [−I, 0]] in (q, p) order; 0 for a symplectic map.
/// For D = 1 this is |det J − 1|.
template <int Z>
double symplecticity_defect(const mat<Z>& jac) {
    const int d = static_cast<int>(jac.rows()) / 2;
    mat<Z> omega = mat<Z>::Zero(2 * d, 2 * d);
    for (int i = 0; i < d; ++i) {
        omega(i, d + i) = 1.0;
        omega(d + i, i) = -1.0;
    }
    return (jac.transpose() * omega * jac - omega).template lpNorm<Eigen::Infinity>();
}

} // namespace varsym
