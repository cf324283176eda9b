// varsym/expression/variables.hpp: the names an expression of mechanics may use: the coordinates
// q_i (named by the user), their velocities NAME_dot, the time t (unless a coordinate or a
// parameter is called t), numeric parameters, and the constants pi and E. The inputs of the
// compiled code are q_0 … q_{d−1}, q̇_0 … q̇_{d−1}, t, in that order.
#pragma once

#include <algorithm>
#include <cctype>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "varsym/expression/parse.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// A named parameter of an expression and its value.
struct expression_parameter {
    std::string name;
    double value = 0.0;
};

namespace expr {

class variables {
  public:
    /// Checks the names: identifiers, none twice (velocities included), none a function or a
    /// constant; at least one coordinate. Throws std::invalid_argument.
    variables(std::vector<std::string> coordinates, std::vector<expression_parameter> parameters)
        : coordinates_(std::move(coordinates)), parameters_(std::move(parameters)) {
        if (coordinates_.empty()) throw std::invalid_argument("give at least one coordinate");
        std::vector<std::string> seen;
        auto take = [&](const std::string& n, const char* what) {
            const bool identifier =
                !n.empty() &&
                (std::isalpha(static_cast<unsigned char>(n[0])) != 0 || n[0] == '_') &&
                std::all_of(n.begin(), n.end(), [](char c) {
                    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
                });
            if (!identifier)
                throw std::invalid_argument(std::string(what) + " name '" + n +
                                            "' is not a name (letters, digits, _; not first a "
                                            "digit)");
            if (n == "pi" || n == "E" || functions().contains(n))
                throw std::invalid_argument(std::string(what) + " name '" + n +
                                            "' is taken by a constant or a function");
            if (n == "t")
                throw std::invalid_argument(std::string(what) +
                                            " name 't' is taken by the time; choose another");
            if (std::find(seen.begin(), seen.end(), n) != seen.end())
                throw std::invalid_argument("the name '" + n + "' is given twice");
            seen.push_back(n);
        };
        for (const auto& c : coordinates_)
            take(c, "coordinate");
        for (const auto& c : coordinates_)
            take(c + "_dot", "velocity");
        for (const auto& p : parameters_)
            take(p.name, "parameter");
    }

    [[nodiscard]] int dimension() const { return static_cast<int>(coordinates_.size()); }
    /// The number of inputs of the compiled code: 2d + 1.
    [[nodiscard]] int inputs() const { return 2 * dimension() + 1; }
    [[nodiscard]] const std::vector<std::string>& coordinates() const { return coordinates_; }
    [[nodiscard]] const std::vector<expression_parameter>& parameters() const {
        return parameters_;
    }
    /// Whether an expression parsed so far named the time t.
    [[nodiscard]] bool uses_time() const { return uses_time_; }

    /// Parses `text` into g, whose inputs are these variables'. Throws parse_error.
    int parse(std::string_view text, graph& g) {
        const int d = dimension();
        return expr::parse(text, g, [&](std::string_view id) -> std::optional<int> {
            for (int i = 0; i < d; ++i) {
                const std::string& c = coordinates_[static_cast<std::size_t>(i)];
                if (id == c) return g.input(i);
                if (id.size() == c.size() + 4 && id.starts_with(c) && id.ends_with("_dot"))
                    return g.input(d + i);
            }
            for (const auto& p : parameters_)
                if (id == p.name) return g.constant(p.value);
            if (id == "t") { // no coordinate or parameter may be called t
                uses_time_ = true;
                return g.input(2 * d);
            }
            return std::nullopt;
        });
    }

    /// (q, v, t) into `in` (inputs() values). Throws std::invalid_argument on a wrong size.
    void load(const vec<dynamic>& q, const vec<dynamic>& v, double t, std::span<double> in) const {
        const int d = dimension();
        if (q.size() != d || v.size() != d)
            throw std::invalid_argument("q and v must have " + std::to_string(d) +
                                        " entries, one per coordinate");
        for (int i = 0; i < d; ++i) {
            in[static_cast<std::size_t>(i)] = q(i);
            in[static_cast<std::size_t>(d + i)] = v(i);
        }
        in[static_cast<std::size_t>(2 * d)] = t;
    }

  private:
    std::vector<std::string> coordinates_;
    std::vector<expression_parameter> parameters_;
    bool uses_time_ = false;
};

} // namespace expr
} // namespace varsym
