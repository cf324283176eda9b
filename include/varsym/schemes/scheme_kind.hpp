// varsym/schemes/scheme_kind.hpp: choosing a scheme at run time (command line, config files):
// the paper's two schemes and the Lobatto and Gauss members of the variational family.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

namespace varsym {

enum class scheme_kind { newmark, simpson, lobatto, gauss };

/// The two schemes of the paper.
inline constexpr std::array paper_schemes{scheme_kind::newmark, scheme_kind::simpson};
inline constexpr std::array all_scheme_kinds{scheme_kind::newmark, scheme_kind::simpson,
                                             scheme_kind::lobatto, scheme_kind::gauss};

constexpr std::string_view scheme_name(scheme_kind k) {
    switch (k) {
    case scheme_kind::newmark:
        return newmark::name;
    case scheme_kind::simpson:
        return simpson::name;
    case scheme_kind::lobatto:
        return "lobatto";
    case scheme_kind::gauss:
        return "gauss";
    }
    return {};
}

/// Polynomial degree s of q(t) on a step: fixed for the paper's schemes, chosen for the family.
constexpr int natural_degree(scheme_kind k) {
    return k == scheme_kind::newmark ? 1 : 2;
}
constexpr bool has_degree_choice(scheme_kind k) {
    return k == scheme_kind::lobatto || k == scheme_kind::gauss;
}

inline std::optional<scheme_kind> parse_scheme(std::string_view s) {
    for (auto k : all_scheme_kinds)
        if (s == scheme_name(k)) return k;
    return std::nullopt;
}

/// A scheme and its degree s; every member has order 2s.
struct scheme_spec {
    scheme_kind kind = scheme_kind::simpson;
    int degree = 2;

    constexpr scheme_spec() = default;
    constexpr scheme_spec(scheme_kind k) : kind(k), degree(natural_degree(k)) {} // NOLINT: implicit
    scheme_spec(scheme_kind k, int s) : kind(k), degree(s) {
        if (!has_degree_choice(k) && s != natural_degree(k))
            throw std::invalid_argument(std::string(scheme_name(k)) + " has degree " +
                                        std::to_string(natural_degree(k)) +
                                        "; choose lobatto or gauss for another degree");
        if (s < 1 || s > galerkin::max_degree)
            throw std::invalid_argument("degree must be between 1 and " +
                                        std::to_string(galerkin::max_degree) + ", got " +
                                        std::to_string(s));
    }
    [[nodiscard]] constexpr int order() const { return 2 * degree; }
    /// "newmark", "simpson", "lobatto-3", "gauss-2".
    [[nodiscard]] std::string label() const {
        std::string l(scheme_name(kind));
        return has_degree_choice(kind) ? l + "-" + std::to_string(degree) : l;
    }
};

/// The rule and degree of the family member that a scheme_spec names: Simpson is Lobatto 2,
/// Newmark is Gauss 1.
inline std::pair<galerkin::rule_kind, int> family_member(const scheme_spec& spec) {
    switch (spec.kind) {
    case scheme_kind::simpson:
        return {galerkin::rule_kind::lobatto, 2};
    case scheme_kind::newmark:
        return {galerkin::rule_kind::gauss, 1};
    case scheme_kind::lobatto:
        return {galerkin::rule_kind::lobatto, spec.degree};
    case scheme_kind::gauss:
        break;
    }
    return {galerkin::rule_kind::gauss, spec.degree};
}

/// Calls f(stepper) with a stepper of scheme `spec` for the separable system `sys` and time
/// step h. Simpson and Newmark, also when named as lobatto-2 and gauss-1, run on their reduced
/// steppers (one d × d solve a step); every other member on the run-time-degree family stepper.
/// So f is compiled for three stepper types, whatever the member.
template <separable System, class F>
decltype(auto) with_stepper(const scheme_spec& spec, const System& sys, double h,
                            const newton_options& opt, F&& f) {
    const auto [rule, degree] = family_member(spec);
    if (rule == galerkin::rule_kind::gauss && degree == 1) {
        newmark::stepper<System> s(sys, h, opt);
        return std::forward<F>(f)(s);
    }
    if (rule == galerkin::rule_kind::lobatto && degree == 2) {
        simpson::stepper<System> s(sys, h, opt);
        return std::forward<F>(f)(s);
    }
    galerkin::stepper<System> s(sys, h, rule, degree, opt);
    return std::forward<F>(f)(s);
}

} // namespace varsym
