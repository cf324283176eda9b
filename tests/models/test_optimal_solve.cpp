// optimal::solve's choices that follow the system: a robot's KKT solves refined only where their
// residual asks for it (IPOPT's min_refinement_steps 0), every other system's at least once (its
// default), read back from IPOPT's own list of the options it was given.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <unistd.h>

#include "varsym/models/model.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/optimize/model.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"

using namespace varsym;

namespace {

/// IPOPT's list of the options set for a one-iteration solve of t (print_user_options), as it
/// prints it on standard error; `extra` goes into the options file too.
std::string ipopt_options_list(const optimal::transcription& t, const std::string& extra = "") {
    const std::string path =
        testing::TempDir() + "varsym_options_list_" + std::to_string(getpid()) + ".opt";
    std::ofstream(path) << "print_user_options yes\nprint_level 1\n" << extra;
    optimal::solver_options o;
    o.options_file = path;
    o.max_iterations = 1; // the options are asked for, not the optimum
    testing::internal::CaptureStderr();
    try {
        (void)optimal::solve(t, o);
    } catch (...) {
        (void)testing::internal::GetCapturedStderr();
        std::remove(path.c_str());
        throw;
    }
    std::string list = testing::internal::GetCapturedStderr();
    std::remove(path.c_str());
    return list;
}

/// Rest to rest on d coordinates, the last one moved by 0.3, in 1 s and 4 steps.
optimal::control_problem short_move(int d) {
    optimal::control_problem p;
    p.time = 1.0;
    p.steps = 4;
    p.scheme = {scheme_kind::gauss, 2};
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(d);
    p.q_end = Eigen::VectorXd::Zero(d);
    p.q_end(d - 1) = 0.3;
    return p;
}

/// Whether IPOPT's list has `option` set to `value` and used: "   name = value   yes".
bool lists(const std::string& list, const std::string& option, const std::string& value) {
    const std::string entry = " " + option + " = " + value + " ";
    const auto at = list.find(entry);
    if (at == std::string::npos) return false;
    const auto end = list.find('\n', at);
    return list.substr(at + entry.size(), end - at - entry.size()).find("yes") != std::string::npos;
}

} // namespace

TEST(OptimalSolve, ARobotsLinearSolvesAreRefinedOnlyWhereTheirResidualAsks) {
    const auto iiwa =
        models::robot_model(models::load_urdf(VARSYM_TEST_DATA "/urdf/iiwa14_no_collision.urdf"));
    const auto robot = optimal::transcribe(iiwa, iiwa.defaults(), {}, short_move(7));
    EXPECT_TRUE(robot->multibody());
    const std::string robot_list = ipopt_options_list(*robot);
    EXPECT_TRUE(lists(robot_list, "mumps_pivot_order", "6")) << robot_list; // the list was read
    EXPECT_TRUE(lists(robot_list, "min_refinement_steps", "0")) << robot_list;

    // Negative control: the pendulum (not a multibody model) keeps IPOPT's default of one.
    const models::model& pendulum = models::get("pendulum");
    const auto other = optimal::transcribe(pendulum, pendulum.defaults(), {}, short_move(1));
    EXPECT_FALSE(other->multibody());
    const std::string other_list = ipopt_options_list(*other);
    EXPECT_TRUE(lists(other_list, "mumps_pivot_order", "6")) << other_list;
    EXPECT_EQ(other_list.find("min_refinement_steps"), std::string::npos) << other_list;

    // The user's options file is read after varsym's settings: it sets the minimum back.
    const std::string asked = ipopt_options_list(*robot, "min_refinement_steps 1\n");
    EXPECT_TRUE(lists(asked, "min_refinement_steps", "1")) << asked;
}
