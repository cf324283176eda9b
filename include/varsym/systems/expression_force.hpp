// varsym/systems/expression_force.hpp: a generalized force f(q, q̇, t) given at run time as one
// expression per coordinate, over the same names as an expression Lagrangian (coordinates,
// NAME_dot, t, parameters), e.g. Rayleigh damping on two joints: {"-c*th1_dot", "-c*th2_dot"}.
// Its Jacobians ∂f/∂q and ∂f/∂q̇ are differentiated symbolically once, and compiled with f into
// straight-line code (expression/tape.hpp). The general engine adds it by the discrete
// Lagrange–d'Alembert principle (schemes/variational.hpp; docs/mechanisms.md).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "varsym/expression/tape.hpp"
#include "varsym/expression/variables.hpp"
#include "varsym/systems/forcing.hpp"

namespace varsym {

class expression_force {
  public:
    static constexpr int dim = dynamic;
    /// Its functions are smooth where defined (expression/parse.hpp): f has a rate in t.
    static constexpr bool continuous_in_time = true;

    /// No force: d zero components.
    explicit expression_force(int d = 1)
        : expression_force(std::vector<std::string>(static_cast<std::size_t>(d), "0"),
                           default_names(d)) {}

    /// f_i = components[i] (units of ∂L/∂q_i), one per coordinate. Throws expr::parse_error
    /// and std::invalid_argument as expression_lagrangian does, and std::invalid_argument when
    /// the number of components is not the number of coordinates.
    expression_force(std::vector<std::string> components, std::vector<std::string> coordinates,
                     std::vector<expression_parameter> parameters = {})
        : texts_(std::move(components)), vars_(std::move(coordinates), std::move(parameters)) {
        const int d = dimension();
        if (static_cast<int>(texts_.size()) != d)
            throw std::invalid_argument("the force needs " + std::to_string(d) +
                                        " components, one per coordinate; got " +
                                        std::to_string(texts_.size()));
        expr::graph g;
        std::vector<int> f;
        for (const auto& text : texts_)
            f.push_back(vars_.parse(text, g));
        std::vector<int> out = f;
        for (int i = 0; i < d; ++i) // fq(i, j), then fv(i, j), row by row
            for (int j = 0; j < d; ++j)
                out.push_back(g.derivative(f[static_cast<std::size_t>(i)], j));
        for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j)
                out.push_back(g.derivative(f[static_cast<std::size_t>(i)], d + j));
        value_ = expr::tape(g, f, vars_.inputs());
        all_ = expr::tape(g, out, vars_.inputs());
        input_.assign(static_cast<std::size_t>(vars_.inputs()), 0.0);
        zero_ = std::all_of(f.begin(), f.end(), [&](int id) { return g.is(id, 0.0); });
    }

    [[nodiscard]] int dimension() const { return vars_.dimension(); }
    [[nodiscard]] const std::vector<std::string>& components() const { return texts_; }
    /// Whether every component is the constant 0 (no force).
    [[nodiscard]] bool zero() const { return zero_; }

    [[nodiscard]] vec<dynamic> operator()(const vec<dynamic>& q, const vec<dynamic>& v,
                                          double t) const {
        vars_.load(q, v, t, input_);
        value_.run(input_);
        vec<dynamic> f(dimension());
        for (int i = 0; i < dimension(); ++i)
            f(i) = value_.output(static_cast<std::size_t>(i));
        return f;
    }
    /// The value alone (the value tape: the same operations as derivatives()' f).
    void value(const vec<dynamic>& q, const vec<dynamic>& v, double t, vec<dynamic>& out) const {
        vars_.load(q, v, t, input_);
        value_.run(input_);
        out.resize(dimension());
        for (int i = 0; i < dimension(); ++i)
            out(i) = value_.output(static_cast<std::size_t>(i));
    }
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v, double t,
                     force_terms<dynamic>& r) const {
        const int d = dimension();
        vars_.load(q, v, t, input_);
        all_.run(input_);
        r.f.resize(d);
        r.fq.resize(d, d);
        r.fv.resize(d, d);
        std::size_t k = 0;
        for (int i = 0; i < d; ++i)
            r.f(i) = all_.output(k++);
        for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j)
                r.fq(i, j) = all_.output(k++);
        for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j)
                r.fv(i, j) = all_.output(k++);
    }

  private:
    static std::vector<std::string> default_names(int d) {
        std::vector<std::string> names;
        for (int i = 0; i < d; ++i) {
            std::string n("q"); // not "q" + …: GCC 12's -Wrestrict misfires on that (PR 105651)
            n += std::to_string(i + 1);
            names.push_back(n);
        }
        return names;
    }
    std::vector<std::string> texts_;
    expr::variables vars_;
    expr::tape value_, all_;
    mutable std::vector<double> input_;
    bool zero_ = true;
};

} // namespace varsym
