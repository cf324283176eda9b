// tests/models/test_parameters.cpp: models::parameter_set (varsym/models/parameters.hpp), the one
// place a model's parameter values are read by position, and the optimal control service
// optimal::optimize (varsym/optimize/model.hpp) that both front ends call.
#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "varsym/models/model.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/optimize/model.hpp"

namespace {

using namespace varsym;

struct two_and_a_list {
    double mass, omega;
    std::vector<double> gains, target;
};

const models::parameter_set<two_and_a_list> set{
    {{&two_and_a_list::mass, {.name = "mass", .value = 1.0}},
     {&two_and_a_list::omega, {.name = "omega", .value = 2.0}}},
    {{&two_and_a_list::gains, {.name = "gains", .value = {5.0, 6.0}}},
     {&two_and_a_list::target, {.name = "target"}}}};

TEST(ParameterSet, ReadsEachValueIntoItsMember) {
    // Values 3 and 7 in the declaration's order: mass 3, omega 7 (not the other way round).
    const two_and_a_list p = set.read(std::vector{3.0, 7.0}, {{1.0}, {0.5, 0.25}});
    EXPECT_EQ(p.mass, 3.0);
    EXPECT_EQ(p.omega, 7.0);
    EXPECT_EQ(p.gains, std::vector{1.0});
    EXPECT_EQ(p.target, (std::vector{0.5, 0.25}));
}

TEST(ParameterSet, AnEmptyListIsItsDeclaredDefault) {
    const two_and_a_list p = set.read(std::vector{3.0, 7.0}, {{}, {}});
    EXPECT_EQ(p.gains, (std::vector{5.0, 6.0}));
    EXPECT_TRUE(p.target.empty()); // declared without a default: "not given"
    const two_and_a_list none = set.read(std::vector{3.0, 7.0}); // no lists at all
    EXPECT_EQ(none.gains, (std::vector{5.0, 6.0}));
}

TEST(ParameterSet, RefusesCountsThatDoNotMatch) {
    EXPECT_THROW((void)set.read(std::vector{3.0}), std::invalid_argument);
    EXPECT_THROW((void)set.read(std::vector{3.0, 7.0}, {{}}), std::invalid_argument);
    EXPECT_THROW((void)models::sized({1.0, 2.0}, 3, "kp", "joint"), std::invalid_argument);
    EXPECT_NO_THROW((void)models::sized({1.0, 2.0, 3.0}, 3, "kp", "joint"));
}

TEST(ParameterSet, DeclaresTheModelsParametersInOrder) {
    models::model m;
    set.declare(m);
    ASSERT_EQ(m.parameters.size(), 2U);
    EXPECT_EQ(m.parameters[0].name, "mass");
    EXPECT_EQ(m.parameters[1].name, "omega");
    ASSERT_EQ(m.lists.size(), 2U);
    EXPECT_EQ(m.lists[0].name, "gains");
}

/// The pendulum swung from hanging to upright in 2 s, 20 Simpson steps, |u| free.
optimal::model_request swing_up() {
    optimal::model_request r;
    optimal::control_problem& p = r.problem;
    p.time = 2.0;
    p.steps = 20;
    p.scheme = {scheme_kind::simpson};
    p.q_start = Eigen::VectorXd::Constant(1, 0.0);
    p.q_end = Eigen::VectorXd::Constant(1, std::numbers::pi);
    p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    return r;
}

TEST(OptimizeService, SolvesAndChecksAsTheSequenceByHand) {
    const models::model& m = models::get("pendulum");
    const auto values = m.defaults();
    const optimal::model_outcome out = optimal::optimize(m, values, {}, swing_up());
    ASSERT_EQ(out.verdict, optimal::verdict::solved) << out.message;
    EXPECT_TRUE(out.check.ok());
    EXPECT_LT(out.residual(), 1e-9);
    // The second path: the model's transcription solved directly. Same problem, same start:
    // the same optimum to IPOPT's tolerance.
    const auto tr = optimal::transcribe(m, values, {}, swing_up().problem);
    const optimal::nlp_result direct = optimal::solve(*tr);
    ASSERT_TRUE(direct.converged());
    const optimal::trajectory path = tr->unpack(direct);
    EXPECT_NEAR(out.path.cost, path.cost, 1e-8 * (1.0 + path.cost));
    EXPECT_GT(out.path.cost, 1.0); // not a trivial zero-effort answer
}

/// The message optimal::optimize refuses the request with ("" if it does not).
std::string service_refusal(const models::model& m, const models::lists& lists,
                            optimal::model_request request) {
    try {
        (void)optimal::optimize(m, m.defaults(), lists, std::move(request));
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

TEST(OptimizeService, RefusesWhatItCannotSolve) {
    // The arm with a controller gain (a simulation's parameter), on its own 3 coordinates so
    // that nothing else is wrong: the same request without the gain is solved.
    const models::model& arm = models::get("arm");
    auto three = swing_up();
    three.problem.q_start = Eigen::VectorXd::Zero(3);
    three.problem.q_end = Eigen::VectorXd::Constant(3, 0.2);
    three.problem.v_start = three.problem.v_end = Eigen::VectorXd::Zero(3);
    models::lists gains(arm.lists.size());
    for (std::size_t i = 0; i < arm.lists.size(); ++i)
        if (arm.lists[i].name == "kp") gains[i] = {1.0, 1.0, 1.0};
    EXPECT_NE(service_refusal(arm, gains, three).find("kp is a simulation's parameter of arm"),
              std::string::npos)
        << service_refusal(arm, gains, three);
    EXPECT_EQ(service_refusal(arm, {}, three), ""); // negative control: solvable without the gain
    EXPECT_NE(service_refusal(models::get("kepler"), {}, swing_up()).find("no control input"),
              std::string::npos);
    auto invariant = swing_up();
    invariant.problem.cost.invariant = 1.0;
    invariant.solver.hessian = optimal::hessian_kind::exact;
    EXPECT_NE(service_refusal(models::get("pendulum"), {}, invariant).find("exact Hessian"),
              std::string::npos);
    EXPECT_THROW((void)optimal::hessian_of("newton"), std::invalid_argument);
    EXPECT_EQ(optimal::hessian_of("limited-memory"), optimal::hessian_kind::limited_memory);
}

TEST(OptimizeService, ATooShortIterationLimitIsNotSolved) {
    const models::model& m = models::get("pendulum");
    auto request = swing_up();
    request.solver.max_iterations = 2;
    const optimal::model_outcome out = optimal::optimize(m, m.defaults(), {}, request);
    EXPECT_EQ(out.verdict, optimal::verdict::not_solved);
    EXPECT_NE(out.message.find("iteration"), std::string::npos) << out.message;
}

} // namespace
