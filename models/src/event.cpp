// models/src/event.cpp: ensemble events, compiled from expressions (varsym/models/event.hpp).
#include "varsym/models/event.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

#include "varsym/expression/parse.hpp"

namespace varsym::models {

expr::tape compile_event(const std::string& text, int d) {
    expr::graph g;
    const int root = expr::parse(text, g, [&](std::string_view id) -> std::optional<int> {
        if (id == "t") return g.input(2 * d);
        for (int i = 0; i < d; ++i) {
            const std::string n = std::to_string(i + 1);
            if (id.size() < 2 || id.substr(1) != n) continue;
            if (id[0] == 'q') return g.input(i);
            if (id[0] == 'p') return g.input(d + i);
        }
        return std::nullopt;
    });
    return expr::tape(g, {root}, 2 * d + 1);
}

event_function event_of(const expr::tape& tape) {
    auto own = std::make_shared<expr::tape>(tape);
    auto in = std::make_shared<std::vector<double>>();
    return [own, in](double t, std::span<const double> q, std::span<const double> p) {
        in->assign(q.begin(), q.end());
        in->insert(in->end(), p.begin(), p.end());
        in->push_back(t);
        own->run(*in);
        return own->output(0);
    };
}

} // namespace varsym::models
