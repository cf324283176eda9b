// Tests for systems/constraints.hpp's hidden-constraint projection, tangent_momentum: with the
// mass matrix by hand (lagrangian_with_mass_matrix) it solves the saddle-point system by M's
// factors (LDLᵀ) and the Schur complement; without it, by Newton on the full saddle-point
// matrix (a full-pivoting LU), a second implementation of the same equations.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "varsym/systems/constraints.hpp"

namespace {

using namespace varsym;

/// L = ½ q̇ᵀ A(q) q̇ at run-time size, A(q) = B + diag(sin² q) with B symmetric: derivatives by
/// hand (as the engines need at a run-time size); with_mass adds mass_matrix.
struct quadratic_base {
    static constexpr int dim = dynamic;
    Eigen::MatrixXd b;
    [[nodiscard]] int dimension() const { return static_cast<int>(b.rows()); }
    [[nodiscard]] Eigen::MatrixXd a(const vec<dynamic>& q) const {
        return b + Eigen::MatrixXd(q.array().sin().square().matrix().asDiagonal());
    }
    template <class T>
    T operator()(const tvec<T, dynamic>&, const tvec<T, dynamic>&) const {
        return T(0.0); // not evaluated: the derivatives are by hand
    }
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        const Eigen::MatrixXd m = a(q);
        const Eigen::Index n = q.size();
        t.value = 0.5 * v.dot(m * v);
        t.lv = m * v;
        t.lq = (q.array().sin() * q.array().cos() * v.array().square()).matrix();
        t.lvv = m;
        t.lqv.setZero(n, n);
        t.lqq.setZero(n, n); // not used by the projection
    }
};
struct with_mass : quadratic_base {
    static inline int calls = 0; // mass_matrix's: 1 by the Schur complement, 2 with the fallback
    void mass_matrix(const vec<dynamic>& q, mat<dynamic>& out) const {
        ++calls;
        out = a(q);
    }
};

/// A fixed rows × cols matrix with entries in [−1, 1] (sin of a seeded linear phase).
Eigen::MatrixXd fixed_matrix(int rows, int cols, double seed) {
    Eigen::MatrixXd out(rows, cols);
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j)
            out(i, j) = std::sin(seed + 1.3 * i + 0.7 * j * j + 0.1 * i * j);
    return out;
}

struct case_data {
    with_mass l;
    vec<dynamic> q, p;
    constraint_jacobian<dynamic, dynamic> g;
};

/// d = 7 coordinates, m = 2 constraints; `indefinite`: B with a negative eigenvalue (the
/// saddle-point matrix stays regular: M is positive definite on G's null space here).
case_data make(bool indefinite) {
    case_data c;
    const int d = 7, m = 2;
    const Eigen::MatrixXd r = fixed_matrix(d, d, 1.1);
    c.l.b = r * r.transpose() + Eigen::MatrixXd::Identity(d, d);
    c.g = fixed_matrix(m, d, 0.4);
    if (indefinite) { // −1 along a direction G sees, so M is indefinite but not on null(G)
        const Eigen::VectorXd u = c.g.row(0).transpose().normalized();
        c.l.b -= (u.dot(c.l.b * u) + 1.0) * u * u.transpose();
    }
    c.q = vec<dynamic>::LinSpaced(d, -0.8, 1.1);
    c.p = vec<dynamic>::LinSpaced(d, 2.0, -1.5);
    return c;
}

} // namespace

TEST(Constraints, TheTangentMomentumBySchurComplementIsNewtonsOnTheSaddlePointMatrix) {
    static_assert(lagrangian_with_mass_matrix<with_mass>);
    static_assert(!lagrangian_with_mass_matrix<quadratic_base>);
    for (const bool indefinite : {false, true}) {
        SCOPED_TRACE(indefinite ? "M indefinite (the LU fallback)" : "M positive definite");
        const case_data c = make(indefinite);
        const Eigen::MatrixXd m = c.l.a(c.q);
        EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(m).info() == Eigen::Success, !indefinite);
        vec<dynamic> v = vec<dynamic>::Zero(7), v_newton = v;
        with_mass::calls = 0;
        const vec<dynamic> mu = tangent_momentum(c.l, c.q, c.p, c.g, v);
        EXPECT_EQ(with_mass::calls, indefinite ? 2 : 1); // the path taken
        const quadratic_base& plain = c.l;
        const vec<dynamic> mu_newton = tangent_momentum(plain, c.q, c.p, c.g, v_newton);
        // The equations to round-off: M v + Gᵀμ = p, G v = 0 (|M| ~ 10, |p| ~ 2).
        EXPECT_LE((m * v + c.g.transpose() * mu - c.p).lpNorm<Eigen::Infinity>(), 1e-13);
        EXPECT_LE((c.g * v).lpNorm<Eigen::Infinity>(), 1e-13);
        // The second implementation agrees to its convergence (1e-14 relative) and round-off.
        EXPECT_LE((v - v_newton).lpNorm<Eigen::Infinity>(), 1e-13 * v.lpNorm<Eigen::Infinity>());
        EXPECT_LE((mu - mu_newton).lpNorm<Eigen::Infinity>(), 1e-13 * mu.lpNorm<Eigen::Infinity>());
        EXPECT_GT(mu.norm(), 0.1); // negative control: p was not already tangent
    }
}

TEST(Constraints, TheTangentMomentumOfASmallConstraintJacobianIsNotRefused) {
    // G scaled by 1e-9: S = G M⁻¹Gᵀ by 1e-18, μ by 1e9, v unchanged. Regular, and solved by the
    // Schur complement; the full matrix's LU takes its small pivots for a singular matrix.
    const case_data c = make(false);
    const constraint_jacobian<dynamic, dynamic> small = 1e-9 * c.g;
    vec<dynamic> v = vec<dynamic>::Zero(7), v_unit = v;
    with_mass::calls = 0;
    const vec<dynamic> mu = tangent_momentum(c.l, c.q, c.p, small, v);
    EXPECT_EQ(with_mass::calls, 1);
    const vec<dynamic> mu_unit = tangent_momentum(c.l, c.q, c.p, c.g, v_unit);
    EXPECT_LE((v - v_unit).lpNorm<Eigen::Infinity>(), 1e-13 * v.lpNorm<Eigen::Infinity>());
    EXPECT_LE((1e-9 * mu - mu_unit).lpNorm<Eigen::Infinity>(),
              1e-13 * mu_unit.lpNorm<Eigen::Infinity>());
    // What the full matrix's LU does with it (the path without the mass matrix by hand).
    const quadratic_base& plain = c.l;
    vec<dynamic> v_lu = vec<dynamic>::Zero(7);
    EXPECT_THROW((void)tangent_momentum(plain, c.q, c.p, small, v_lu), std::domain_error);
}

TEST(Constraints, TheTangentMomentumRefusesDependentConstraints) {
    case_data c = make(false);
    c.g.row(1) = 2.0 * c.g.row(0); // dependent rows: S = G M⁻¹Gᵀ is singular
    vec<dynamic> v = vec<dynamic>::Zero(7);
    with_mass::calls = 0;
    EXPECT_THROW((void)tangent_momentum(c.l, c.q, c.p, c.g, v), std::domain_error);
    EXPECT_EQ(with_mass::calls, 2); // S refused, then the full matrix's LU
}
