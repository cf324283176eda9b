// Tests for varsym/solvers/solver_name.hpp: ITERATION[+START] read and written back.
#include <gtest/gtest.h>

#include <stdexcept>

#include "varsym/solvers/solver_name.hpp"

namespace {

using varsym::iteration_kind;
using varsym::predictor_kind;

TEST(SolverName, ReadsIterationAndStart) {
    const auto opt = varsym::parse_solver("fixed-point+forces");
    EXPECT_EQ(opt.iteration, iteration_kind::fixed_point);
    EXPECT_EQ(opt.predictor, predictor_kind::forces);
    EXPECT_EQ(varsym::parse_solver("newton+previous").predictor, predictor_kind::previous);
    EXPECT_EQ(varsym::parse_solver("simplified").iteration, iteration_kind::simplified);
}

TEST(SolverName, WithoutStartKeepsTheBasesOtherFields) {
    varsym::newton_options base;
    base.predictor = predictor_kind::forces;
    base.max_iterations = 7;
    const auto opt = varsym::parse_solver("newton", base);
    EXPECT_EQ(opt.iteration, iteration_kind::newton);
    EXPECT_EQ(opt.predictor, predictor_kind::forces);
    EXPECT_EQ(opt.max_iterations, 7);
    EXPECT_EQ(varsym::parse_solver("newton+taylor", base).predictor, predictor_kind::taylor);
}

TEST(SolverName, EveryNameReadsBack) {
    for (const auto& [iname, iteration] : varsym::iteration_names)
        for (const auto& [pname, start] : varsym::predictor_names) {
            varsym::newton_options opt;
            opt.iteration = iteration;
            opt.predictor = start;
            const auto back = varsym::parse_solver(varsym::solver_name(opt));
            EXPECT_EQ(back.iteration, iteration) << iname;
            EXPECT_EQ(back.predictor, start) << pname;
        }
    EXPECT_EQ(varsym::solver_name(varsym::parse_solver("fixed-point+forces")),
              "fixed-point+forces");
}

TEST(SolverName, RefusesWhatItDoesNotKnow) {
    for (const char* bad : {"", "chord", "newton+", "+forces", "newton+forces+previous", "Newton",
                            "fixed-point+guess"})
        EXPECT_THROW(varsym::parse_solver(bad), std::invalid_argument) << bad;
}

} // namespace
