// varsym/models/parameters.hpp: a model's parameters declared once, each bound to a member of the
// model's own parameter struct P. The declaration gives the model its parameter list (name,
// default, unit, meaning, range: what the tool's options, the Python keywords and the config
// keys are made from), and reads the values a front end passes, in the declaration's order, into
// a P whose members the model's code then reads by name. Only this file indexes the values.
//
//     struct pendulum_parameters { double mass, omega; };
//     const parameter_set<pendulum_parameters> set{
//         {{&pendulum_parameters::mass, {.name = "mass", .value = 1.0, .unit = "kg m^2", …}},
//          {&pendulum_parameters::omega, {.name = "omega", …}}}};
//     set.declare(m);                                   // m.parameters, m.lists
//     m.make = set.make([](const pendulum_parameters& p, const start& s) { … p.mass … });
#pragma once

#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "varsym/models/model.hpp"

namespace varsym::models {

template <class P>
class parameter_set {
  public:
    /// A scalar parameter: the member that holds it and its declaration.
    struct scalar {
        double P::*member;
        parameter spec;
    };
    /// A parameter of several values (model.hpp's list_parameter): an empty list given is its
    /// declared default value (which may itself be empty, where the model's rule sets it).
    struct list {
        std::vector<double> P::*member;
        list_parameter spec;
    };

    parameter_set(std::vector<scalar> declared, std::vector<list> declared_lists = {})
        : scalars_(std::move(declared)), lists_(std::move(declared_lists)) {}

    /// The declarations, in order: what model::parameters and model::lists hold.
    [[nodiscard]] std::vector<parameter> parameters() const {
        std::vector<parameter> out;
        for (const scalar& s : scalars_)
            out.push_back(s.spec);
        return out;
    }
    [[nodiscard]] std::vector<list_parameter> lists() const {
        std::vector<list_parameter> out;
        for (const list& l : lists_)
            out.push_back(l.spec);
        return out;
    }
    /// Sets m.parameters and m.lists from the declarations.
    void declare(model& m) const {
        m.parameters = parameters();
        m.lists = lists();
    }

    /// P from the values in the declaration's order and the lists (none: all defaults; an empty
    /// one: its default). Throws std::invalid_argument for a count that does not match.
    [[nodiscard]] P read(std::span<const double> values, const models::lists& given = {}) const {
        if (values.size() != scalars_.size())
            throw std::invalid_argument(std::to_string(scalars_.size()) +
                                        " parameter values needed, got " +
                                        std::to_string(values.size()));
        if (!given.empty() && given.size() != lists_.size())
            throw std::invalid_argument(std::to_string(lists_.size()) + " lists needed, got " +
                                        std::to_string(given.size()));
        P p{};
        auto value = values.begin();
        for (const scalar& s : scalars_)
            p.*s.member = *value++;
        // A P smaller than a vector holds none, so it has no lists. (GCC 12 at -O3 would report
        // the assignment below as outside such a P's bounds: it cannot see that lists_ is then
        // empty.)
        if constexpr (sizeof(P) >= sizeof(std::vector<double>)) {
            auto each = given.begin();
            for (const list& l : lists_) {
                const bool default_one = given.empty() || each->empty();
                p.*l.member = default_one ? l.spec.value : *each;
                if (!given.empty()) ++each;
            }
        }
        return p;
    }

    // The model's functions (model.hpp) from functions of P: each reads P once.

    /// model::make from f(const P&, const start&) -> problem.
    template <class F>
    [[nodiscard]] auto make(F f) const {
        return [set = *this, f = std::move(f)](std::span<const double> v, const start& s,
                                               const models::lists& l) {
            return f(set.read(v, l), s);
        };
    }
    /// model::dimension from f(const P&) -> int.
    template <class F>
    [[nodiscard]] auto dimension(F f) const {
        return [set = *this, f = std::move(f)](std::span<const double> v, const models::lists& l) {
            return f(set.read(v, l));
        };
    }
    /// model::control from f(const P&) -> the controlled system.
    template <class F>
    [[nodiscard]] auto control(F f) const {
        return [set = *this, f = std::move(f)](std::span<const double> v, const models::lists& l) {
            return f(set.read(v, l));
        };
    }
    /// model::limits from f(const P&, optimal::control_problem&).
    template <class F>
    [[nodiscard]] auto limits(F f) const {
        return
            [set = *this, f = std::move(f)](std::span<const double> v, const models::lists& l,
                                            optimal::control_problem& p) { f(set.read(v, l), p); };
    }
    /// model::drawing from f(const P&) -> the 3-D figure.
    template <class F>
    [[nodiscard]] auto drawing(F f) const {
        return [set = *this, f = std::move(f)](std::span<const double> v, const models::lists& l) {
            return f(set.read(v, l));
        };
    }
    /// model::pose from f(const P&, std::span<const double> q) -> the polyline.
    template <class F>
    [[nodiscard]] auto pose(F f) const {
        return [set = *this, f = std::move(f)](std::span<const double> v, const models::lists& l,
                                               std::span<const double> q) {
            return f(set.read(v, l), q);
        };
    }

  private:
    std::vector<scalar> scalars_;
    std::vector<list> lists_;
};

/// A list parameter's values checked against the count n it needs (one per link, per joint):
/// `given` itself, or std::invalid_argument "NAME needs n values (one per WHAT), got k".
inline const std::vector<double>& sized(const std::vector<double>& given, std::size_t n,
                                        const std::string& name, const std::string& what) {
    if (given.size() != n)
        throw std::invalid_argument(name + " needs " + std::to_string(n) + " values (one per " +
                                    what + "), got " + std::to_string(given.size()));
    return given;
}

} // namespace varsym::models
