// The compiled code of an expression graph (expression/tape.hpp): evaluating many input sets at
// once (run_batch, the separable family stepper's points of a sweep) gives each set the values of
// evaluating it alone, bit for bit; and the graph's rule (c·u)·(c'/v) = u·((c c')/v), which
// shortens the chain rule's code for distances.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "varsym/expression/parse.hpp"
#include "varsym/expression/tape.hpp"

namespace varsym::expr {
namespace {

/// The graph of `text` in x, y (inputs 0 and 1) and its gradient's nodes.
struct compiled {
    graph g;
    std::vector<int> gradient;
    explicit compiled(const std::string& text) {
        const int f = parse(text, g, [&](std::string_view n) -> std::optional<int> {
            if (n == "x") return g.input(0);
            if (n == "y") return g.input(1);
            return std::nullopt;
        });
        gradient = {f, g.derivative(f, 0), g.derivative(f, 1)};
    }
};

TEST(Tape, BatchGivesEachSetItsOwnValuesBitForBit) {
    // Every operation the interpreter has, in expressions and their derivatives; 1 … 11 sets,
    // so that chunks of four, of three (a repeated lane) and of one or two are all taken.
    const std::vector<std::string> texts{
        "1.3/sqrt(x**2 + y**2) - x*y**3", "sin(x)*cos(y) + tan(0.3*x) + exp(-y**2) + log(2 + x**2)",
        "(1.5 + x**2)**y + x**(-3) + sinh(x) - cosh(y) + tanh(x*y)",
        "asin(x/4) + acos(y/4) + atan(x - y) + -(x - y)/(1 + x**4)"};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.3, 2.0);
    for (const std::string& text : texts) {
        const compiled c(text);
        const tape t(c.g, c.gradient, 2);
        for (int count = 1; count <= 11; ++count) {
            std::vector<double> in(static_cast<std::size_t>(2 * count));
            for (double& v : in)
                v = u(rng);
            std::vector<double> out(3 * static_cast<std::size_t>(count));
            t.run_batch(in.data(), 2, count, out.data());
            for (int j = 0; j < count; ++j) {
                t.run_prefix(in.data() + 2 * j, 2);
                for (std::size_t k = 0; k < 3; ++k)
                    EXPECT_EQ(out[static_cast<std::size_t>(3 * j) + k], t.output(k))
                        << text << ", set " << j << " of " << count << ", output " << k;
            }
            // Negative control: the sets' values differ, so a batch that gave every set one
            // set's values would fail the comparison above.
            if (count > 1) {
                EXPECT_NE(out[0], out[3]) << text;
            }
        }
    }
}

TEST(Tape, ChainRuleConstantsMeet) {
    // ∇V for V = −mu/√(x² + y²), built as the separable path builds it, −∂L/∂q with
    // L ∋ mu/√(x² + y²): the rules give −(−((mu/r)/r) · (2x · (0.5/r))), fifteen operations with
    // both coordinates. With −(−a) = a and (c·u)·(c'/v) = u·((c c')/v) the factor is
    // x · (1/r), one quotient shared by x and y: eleven (x², y², +, √, mu/r, 1/r, (mu/r)/r,
    // and two products per coordinate).
    compiled c("2.5/sqrt(x**2 + y**2)");
    const tape t(c.g, {c.g.neg(c.gradient[1]), c.g.neg(c.gradient[2])}, 2);
    EXPECT_EQ(t.instructions(), 11U);
    // Against mu x/r³ computed directly: a few ulps.
    const double x = 0.8, y = -0.35, r = std::sqrt(x * x + y * y);
    const double in[2] = {x, y};
    t.run_prefix(in, 2);
    const double gx = 2.5 * x / (r * r * r), gy = 2.5 * y / (r * r * r);
    EXPECT_NEAR(t.output(0), gx, 8e-16 * std::abs(gx));
    EXPECT_NEAR(t.output(1), gy, 8e-16 * std::abs(gy));
}

} // namespace
} // namespace varsym::expr
