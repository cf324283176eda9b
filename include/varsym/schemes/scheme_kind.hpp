// varsym/schemes/scheme_kind.hpp: choosing a scheme at run time (command line, config files).
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <utility>

#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

namespace varsym {

enum class scheme_kind { newmark, simpson };

inline constexpr std::array all_schemes{scheme_kind::newmark, scheme_kind::simpson};

constexpr std::string_view scheme_name(scheme_kind k) {
    return k == scheme_kind::newmark ? newmark::name : simpson::name;
}

constexpr int scheme_order(scheme_kind k) {
    return k == scheme_kind::newmark ? newmark::order : simpson::order;
}

inline std::optional<scheme_kind> parse_scheme(std::string_view s) {
    for (auto k : all_schemes)
        if (s == scheme_name(k)) return k;
    return std::nullopt;
}

/// Calls f(stepper) with the fast stepper of scheme k for `sys` and time step h.
template <class System, class F>
decltype(auto) with_stepper(scheme_kind k, const System& sys, double h, const newton_options& opt,
                            F&& f) {
    if (k == scheme_kind::newmark) {
        newmark::stepper<System> s(sys, h, opt);
        return std::forward<F>(f)(s);
    }
    simpson::stepper<System> s(sys, h, opt);
    return std::forward<F>(f)(s);
}

} // namespace varsym
