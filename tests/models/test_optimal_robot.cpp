// The one compiled transcription (varsym/optimize/transcription.hpp) over systems of run-time
// size from the models layer: a URDF robot (recursive derivatives, exact third derivatives by dual
// numbers) and its derivatives against finite differences, the KKT conditions at a solution, and
// each system's exact third derivatives against the difference of its second ones; the steps'
// derivatives on several threads against one.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <numbers>
#include <set>
#include <stdexcept>
#include <thread>

#include "../optimal/fixtures.hpp"
#include "varsym/models/model.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/optimize/model.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

using namespace varsym;

namespace {

std::string urdf_path(const std::string& file) {
    return VARSYM_TEST_DATA "/urdf/" + file;
}

/// The iiwa's model `urdf` rest to rest: from 0 to `to` in 2 s.
optimal::control_problem iiwa_problem(int steps, const scheme_spec& scheme) {
    optimal::control_problem p;
    p.time = 2.0;
    p.steps = steps;
    p.scheme = scheme;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(7);
    p.q_end = (Eigen::VectorXd(7) << 0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2).finished();
    return p;
}

} // namespace

TEST(OptimalRobot, DerivativesMatchFiniteDifferences) {
    // The iiwa's transcription at an arbitrary point: ∂g/∂x from the recursive second
    // derivatives, and the Hessian of σJ + λᵀg from their dual-number rates (third derivatives),
    // against central differences of g and of σ∇J + Jᵀλ (step 1e-6: error about 1e-9 relative
    // to entries of size up to 1e3).
    const auto robot =
        models::robot_model(models::load_urdf(urdf_path("iiwa14_no_collision.urdf")));
    const auto tr =
        optimal::transcribe(robot, robot.defaults(), {}, iiwa_problem(2, {scheme_kind::gauss, 2}));
    EXPECT_EQ(tr->variables(), 5 * 7 + 4 * 7);
    const Eigen::VectorXd x =
        0.5 * Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin();
    const auto e = optimal_test::check_derivatives(
        *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
    EXPECT_LT(e.jacobian, 1e-6 * e.largest_jacobian);
    EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian);
    EXPECT_GT(e.largest_hessian, 1.0); // not vacuous: L's third derivatives are there
    // The cost's gradient (measured 5.9e-11 of entries up to 0.25); budget 1e-8, 170×.
    EXPECT_LT(e.gradient, 1e-8 * std::max(1.0, e.largest_gradient));
    // With a free final time (its Hessian row from the damping's ∂f/∂q̇ and the torques' B as
    // well as L's derivatives) and the URDF's velocity limits (rows V/h that depend on T).
    auto p = iiwa_problem(2, {scheme_kind::gauss, 2});
    p.free_time = true;
    p.cost.time = 1.0;
    robot.limits(robot.defaults(), {}, p);
    const auto timed = optimal::transcribe(robot, robot.defaults(), {}, p);
    ASSERT_TRUE(timed->has_hessian());
    Eigen::VectorXd y =
        0.5 * Eigen::VectorXd::LinSpaced(timed->variables(), 0.3, 2.9).array().sin();
    y(y.size() - 1) = 1.7; // T
    const Eigen::VectorXd mu = Eigen::VectorXd::LinSpaced(timed->constraints(), -1.0, 2.0);
    const auto f = optimal_test::check_derivatives(*timed, y, 0.7, mu);
    EXPECT_LT(f.jacobian, 1e-6 * f.largest_jacobian);
    EXPECT_LT(f.hessian, 1e-6 * f.largest_hessian);
    std::vector<double> hv; // the row of T is there
    timed->hessian(y, 0.7, mu, hv);
    const int nt = timed->variables();
    EXPECT_GT(timed->hessian_pattern().dense(hv, nt, nt).row(nt - 1).cwiseAbs().maxCoeff(), 1.0);
}

TEST(OptimalRobot, KarushKuhnTuckerConditionsHoldAtTheSolution) {
    // At IPOPT's solution: g(x) = 0 and ∇J + Jᵀλ = 0 on every unknown off its bounds (the
    // fixed ends excepted), re-evaluated here from the transcription, not IPOPT's report.
    const auto robot =
        models::robot_model(models::load_urdf(urdf_path("iiwa14_no_collision.urdf")));
    const auto tr =
        optimal::transcribe(robot, robot.defaults(), {}, iiwa_problem(20, scheme_kind::simpson));
    const auto r = optimal::solve(*tr);
    ASSERT_EQ(r.verdict, optimal::status::solved) << r.message;
    Eigen::VectorXd g, grad, lower, upper;
    tr->residual(r.x, g);
    EXPECT_LT(g.lpNorm<Eigen::Infinity>(), 1e-10);
    tr->cost_gradient(r.x, grad);
    std::vector<double> values;
    tr->jacobian(r.x, values);
    const Eigen::MatrixXd jac =
        tr->jacobian_pattern().dense(values, tr->constraints(), tr->variables());
    const Eigen::VectorXd stationarity = grad + jac.transpose() * r.lambda;
    tr->bounds(lower, upper);
    double worst = 0.0, scale = grad.lpNorm<Eigen::Infinity>();
    int free = 0;
    for (int i = 0; i < tr->variables(); ++i)
        if (lower(i) < r.x(i) - 1e-6 && r.x(i) < upper(i) - 1e-6) {
            worst = std::max(worst, std::abs(stationarity(i)));
            ++free;
        }
    EXPECT_GT(free, tr->variables() / 2);
    EXPECT_LT(worst, 1e-8 * scale);
    // Negative control: with λ = 0 the stationarity fails (the constraints' forces matter).
    EXPECT_GT(grad.lpNorm<Eigen::Infinity>(), 1e-3 * scale);
}

namespace {

/// A two-link arm as a C++ Lagrangian (automatic derivatives).
struct ad_two_link {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const T c2 = cos(q(1));
        const T m11 = 1.0 / 4.0 + (1.0 + 1.0 / 4.0 + c2) + 1.0 / 6.0;
        const T m12 = 1.0 / 4.0 + 0.5 * c2 + 1.0 / 12.0;
        const double m22 = 1.0 / 4.0 + 1.0 / 12.0;
        return 0.5 * m11 * v(0) * v(0) + m12 * v(0) * v(1) + 0.5 * m22 * v(1) * v(1) +
               1.5 * 9.81 * cos(q(0)) + 0.5 * 9.81 * cos(q(0) + q(1));
    }
};

} // namespace

/// Largest |x − y| over the largest |y|.
double third_gap(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y) {
    return (x - y).cwiseAbs().maxCoeff() / y.cwiseAbs().maxCoeff();
}

TEST(OptimalRobot, ExactThirdDerivativesAgreeWithTheDifferenceOfSecondOnes) {
    // Each system's exact third derivatives (lagrangian_part::third: nested AD for a C++ L,
    // dual numbers for a URDF robot, the typed L's code run along the direction) against the
    // fallback every system has, a central difference of its exact second derivatives
    // (controlled_system::third, relative error about 1e-10 on smooth L): 1e-7 relative.
    const Eigen::VectorXd q7 = Eigen::VectorXd::LinSpaced(7, -0.9, 1.2),
                          v7 = Eigen::VectorXd::LinSpaced(7, 1.5, -0.7),
                          a7 = Eigen::VectorXd::LinSpaced(7, 0.3, -2.0),
                          b7 = Eigen::VectorXd::LinSpaced(7, -1.0, 0.8);
    const multibody::robot_lagrangian iiwa(
        models::load_urdf(urdf_path("iiwa14_no_collision.urdf")));
    const optimal::input_system robot(iiwa, Eigen::MatrixXd::Identity(7, 7));
    const optimal::input_system cpp(ad_two_link{}, Eigen::MatrixXd::Identity(2, 2));
    const optimal::input_system typed(
        expression_lagrangian("0.5*(2 + cos(b))*a_dot**2 + 0.5*b_dot**2 + a_dot*b_dot*sin(b)"
                              " + 9.81*cos(a) + t*sin(a)*b_dot",
                              {"a", "b"}),
        Eigen::MatrixXd::Identity(2, 2));
    const Eigen::VectorXd q2 = q7.head(2), v2 = v7.head(2), a2 = a7.head(2), b2 = b7.head(2);
    for (const auto* sys :
         std::initializer_list<const optimal::controlled_system*>{&robot, &cpp, &typed}) {
        const bool seven = sys->dimension() == 7;
        const Eigen::VectorXd &q = seven ? q7 : q2, &v = seven ? v7 : v2, &a = seven ? a7 : a2,
                              &b = seven ? b7 : b2;
        EXPECT_TRUE(sys->exact_third());
        Eigen::MatrixXd exact, difference;
        sys->third(q, v, 0.4, a, b, exact);
        sys->controlled_system::third(q, v, 0.4, a, b, difference);
        EXPECT_LT(third_gap(difference, exact), 1e-7) << "dimension " << sys->dimension();
        EXPECT_GT(third_gap(difference, exact), 0.0);          // two computations, not one
        EXPECT_LT(third_gap(exact.transpose(), exact), 1e-13); // symmetric to round-off
        sys->third(q, v, 0.4, b, a, difference); // negative control: the direction matters
        EXPECT_GT(third_gap(difference, exact), 1e-3);
    }
}

TEST(OptimalRobot, InputSystemAndSystemOfGiveOneTranscription) {
    // The same L and inputs through system_of (every derivative by automatic differentiation)
    // and input_system (L's second derivatives by AD, the input force's by hand, third ones by
    // nested AD): their Hessians agree to round-off, and the optima to IPOPT's tolerance.
    optimal::control_problem p;
    p.time = 2.0;
    p.steps = 20;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(2);
    p.q_end = Eigen::Vector2d(std::numbers::pi, 0.0);
    const auto exact = optimal::transcribe(ad_two_link{}, optimal_test::direct_input<2>{}, p);
    const auto diff = optimal::transcribe_inputs(ad_two_link{}, Eigen::MatrixXd::Identity(2, 2), p);
    const Eigen::VectorXd x =
        Eigen::VectorXd::LinSpaced(exact->variables(), 0.3, 2.9).array().sin();
    const Eigen::VectorXd lambda = Eigen::VectorXd::LinSpaced(exact->constraints(), -3.0, 2.0);
    const auto gap = optimal_test::hessian_gap(*exact, *diff, x, 0.5, lambda);
    ASSERT_TRUE(gap.same_size);
    EXPECT_LT(gap.worst, 1e-13 * gap.largest);
    EXPECT_GT(gap.largest, 1.0);
    const auto ra = optimal::solve(*exact), rb = optimal::solve(*diff);
    ASSERT_TRUE(ra.converged() && rb.converged());
    EXPECT_NEAR(ra.cost, rb.cost, 1e-9 * ra.cost);
    EXPECT_EQ(ra.iterations, rb.iterations);
}

TEST(OptimalRobot, StructuralZerosLeaveTheKktPatterns) {
    // The iiwa's torques enter as f = B u with B constant (the actuated joints' selection,
    // controlled_system::constant_input_matrix): its transcription leaves B's zeros, the
    // controls' (u, Q) Hessian blocks and the off-diagonal of their (u, u) blocks out of its
    // patterns. The same system undeclared (dense_inputs) keeps them: both give the same
    // matrices, and the patterns differ by exactly the counted zeros.
    const auto robot =
        models::robot_model(models::load_urdf(urdf_path("iiwa14_no_collision.urdf")));
    const auto sys = robot.control(robot.defaults(), {});
    ASSERT_NE(sys->constant_input_matrix(), nullptr);
    const auto dense = std::make_shared<const optimal_test::dense_inputs>(sys);
    const int d = 7, steps = 3;
    for (const scheme_spec scheme : {scheme_spec(scheme_kind::simpson), {scheme_kind::gauss, 2}}) {
        for (const double power : {0.0, 1.0}) {
            auto p = iiwa_problem(steps, scheme);
            p.cost.power = power;
            const auto sparse_tr = optimal::transcribe(sys, p),
                       dense_tr = optimal::transcribe(dense, p);
            const int n = sparse_tr->variables(), m = sparse_tr->constraints();
            const Eigen::VectorXd x = 0.5 * Eigen::VectorXd::LinSpaced(n, 0.3, 2.9).array().sin();
            const Eigen::VectorXd lambda = Eigen::VectorXd::LinSpaced(m, -1.0, 2.0);
            std::vector<double> a, b;
            sparse_tr->jacobian(x, a);
            dense_tr->jacobian(x, b);
            const auto js = sparse_tr->jacobian_pattern(), jd = dense_tr->jacobian_pattern();
            // One computation: the entries left out are exact zeros of the other.
            EXPECT_EQ((js.dense(a, m, n) - jd.dense(b, m, n)).cwiseAbs().maxCoeff(), 0.0);
            const auto gap = optimal_test::hessian_gap(*sparse_tr, *dense_tr, x, 0.7, lambda);
            ASSERT_TRUE(gap.same_size);
            EXPECT_EQ(gap.worst, 0.0);
            EXPECT_GT(gap.largest, 1.0);
            // And against central differences, independently of either pattern.
            const auto e = optimal_test::check_derivatives(*sparse_tr, x, 0.7, lambda);
            EXPECT_LT(e.jacobian, 1e-6 * e.largest_jacobian);
            EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian);
            // Counted, per step: both leave out the nodes that a point's controls do not reach
            // (Simpson's ℓ_i(c_j) = δ_ij: 3 of 9 node-point pairs kept, gauss-2 all 6) and the
            // (u_j, u_j') blocks of two points; the declared B keeps d of each pair's d × d
            // entries, and with the effort alone R's diagonal of each point's (u_j, u_j) block
            // and no (u_j, Q) entry: r (d wq + d (d + 1) / 2 − d) fewer, wq = (s + 1) d. The
            // power cost couples u with q̇: none fewer.
            const bool simpson = scheme.kind == scheme_kind::simpson;
            const int pairs = simpson ? 3 : 6, r = simpson ? 3 : 2, wq = 3 * d;
            EXPECT_EQ(jd.size() - js.size(), steps * pairs * (d * d - d));
            EXPECT_EQ(dense_tr->hessian_pattern().size() - sparse_tr->hessian_pattern().size(),
                      power == 0.0 ? steps * r * (d * wq + d * (d + 1) / 2 - d) : 0);
        }
    }
    // The same optimum from both patterns (MUMPS orders and pivots them differently).
    const auto p = iiwa_problem(20, scheme_kind::simpson);
    const auto rs = optimal::solve(*optimal::transcribe(sys, p)),
               rd = optimal::solve(*optimal::transcribe(dense, p));
    ASSERT_TRUE(rs.converged() && rd.converged()) << rs.message << " / " << rd.message;
    EXPECT_NEAR(rs.cost, rd.cost, 1e-9 * rd.cost);
}

namespace {

/// A robot's controlled system that records the threads calling its second and third
/// derivatives, and throws from them on request (the threads' error path).
class thread_recorder final : public optimal::controlled_system {
  public:
    using matrix = optimal::matrix;
    using vector = optimal::vector;
    explicit thread_recorder(std::shared_ptr<const optimal::controlled_system> s)
        : s_(std::move(s)) {}
    [[nodiscard]] int dimension() const override { return s_->dimension(); }
    [[nodiscard]] int inputs() const override { return s_->inputs(); }
    [[nodiscard]] bool concurrent() const override { return true; }
    void gradient(const vector& q, const vector& v, double t,
                  lagrangian_terms<dynamic>& out) const override {
        s_->gradient(q, v, t, out);
    }
    void derivatives(const vector& q, const vector& v, double t,
                     lagrangian_terms<dynamic>& out) const override {
        seen();
        s_->derivatives(q, v, t, out);
    }
    void third(const vector& q, const vector& v, double t, const vector& a, const vector& b,
               matrix& out) const override {
        seen();
        s_->third(q, v, t, a, b, out);
    }
    void force(const vector& q, const vector& v, double t, const vector& u,
               optimal::input_terms& out, bool jacobians) const override {
        s_->force(q, v, t, u, out, jacobians);
    }
    [[nodiscard]] const matrix* constant_input_matrix() const override {
        return s_->constant_input_matrix();
    }
    /// The distinct threads seen since the last call.
    std::size_t threads() const {
        const std::lock_guard<std::mutex> lock(mutex_);
        const std::size_t n = ids_.size();
        ids_.clear();
        return n;
    }
    std::atomic<bool> fail{false};

  private:
    void seen() const {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            ids_.insert(std::this_thread::get_id());
        }
        if (fail && std::this_thread::get_id() != main_)
            throw std::runtime_error("a worker's evaluation failed");
    }
    std::shared_ptr<const optimal::controlled_system> s_;
    std::thread::id main_ = std::this_thread::get_id();
    mutable std::mutex mutex_;
    mutable std::set<std::thread::id> ids_;
};

} // namespace

TEST(OptimalRobot, ThreadsGiveTheSameDerivativesToTheBit) {
    // The steps' Jacobian and Hessian blocks on 1, 2, 3 and 5 threads (13 steps: unequal parts):
    // each step writes its own block, so the values are equal to the bit. The recorder sees as
    // many threads as asked for (so the parts did run apart), and a worker's exception reaches
    // the caller. Automatic: one thread for 13 iiwa steps (1274 units of r d² < 2048); one for
    // a system that does not declare itself concurrent (the acrobot's C++ Lagrangian).
    const auto robot =
        models::robot_model(models::load_urdf(urdf_path("iiwa14_no_collision.urdf")));
    const auto sys = robot.control(robot.defaults(), {});
    EXPECT_TRUE(sys->concurrent());
    const auto rec = std::make_shared<thread_recorder>(sys);
    auto p = iiwa_problem(13, {scheme_kind::gauss, 2});
    robot.limits(robot.defaults(), {}, p);
    const auto tr = optimal::transcribe(rec, p);
    EXPECT_EQ(tr->evaluation_threads(), 1);
    const Eigen::VectorXd x =
        0.5 * Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin();
    const Eigen::VectorXd lambda = Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0);
    std::vector<double> j1, h1, j, h;
    tr->set_threads(1);
    tr->jacobian(x, j1);
    tr->hessian(x, 0.7, lambda, h1);
    EXPECT_EQ(rec->threads(), 1U);
    EXPECT_GT(Eigen::Map<const Eigen::VectorXd>(h1.data(), std::ssize(h1)).cwiseAbs().maxCoeff(),
              1.0);
    for (const int threads : {2, 3, 5}) {
        tr->set_threads(threads);
        EXPECT_EQ(tr->evaluation_threads(), threads);
        tr->jacobian(x, j);
        tr->hessian(x, 0.7, lambda, h);
        EXPECT_EQ(rec->threads(), static_cast<std::size_t>(threads));
        EXPECT_TRUE(j == j1) << threads << " threads";
        EXPECT_TRUE(h == h1) << threads << " threads";
    }
    rec->fail = true;
    EXPECT_THROW(tr->hessian(x, 0.7, lambda, h), std::runtime_error);
    rec->fail = false;
    EXPECT_THROW(tr->set_threads(-1), std::invalid_argument);
    // Through the service both front ends call: model_request::threads reaches the
    // transcription (the outcome reports it), the answer is the same to the bit, and a count out
    // of [0, 4096] is refused.
    optimal::model_request request;
    request.problem = iiwa_problem(13, {scheme_kind::gauss, 2});
    std::vector<optimal::model_outcome> outcomes;
    for (const int threads : {1, 3}) {
        request.threads = threads;
        outcomes.push_back(optimal::optimize(robot, robot.defaults(), {}, request));
        EXPECT_EQ(outcomes.back().threads, threads);
    }
    EXPECT_TRUE(outcomes[0].result.x == outcomes[1].result.x);
    EXPECT_EQ(outcomes[0].verdict, optimal::verdict::solved);
    for (const int threads : {-1, 4097}) {
        request.threads = threads;
        EXPECT_THROW((void)optimal::optimize(robot, robot.defaults(), {}, request),
                     std::invalid_argument);
    }
    // Not declared concurrent: one thread whatever is asked.
    const auto& acrobot = models::get("acrobot");
    auto q = iiwa_problem(13, {scheme_kind::gauss, 2});
    q.q_start = q.v_start = q.v_end = Eigen::VectorXd::Zero(2);
    q.q_end = Eigen::Vector2d(1.0, 0.5);
    const auto typed = optimal::transcribe(acrobot, acrobot.defaults(), {}, q);
    auto* dmoc = dynamic_cast<optimal::dmoc_transcription*>(typed.get());
    ASSERT_NE(dmoc, nullptr);
    dmoc->set_threads(4);
    EXPECT_EQ(dmoc->evaluation_threads(), 1);
}
