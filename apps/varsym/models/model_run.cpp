// apps/varsym/models/model_run.cpp: what the models of `varsym run` share: the registry, step
// plans, initial vectors and option validators.
#include <algorithm>
#include <cmath>

#include "models/models.hpp"
#include "models/registry_models.hpp"

namespace varsym::cli {

std::vector<model> make_models(std::shared_ptr<parameter_options> po) {
    if (!po) po = std::make_shared<parameter_options>();
    std::vector<model> all;
    for (const models::model& m : models::registry())
        all.push_back(make_registry_model(m, po));
    all.push_back(make_expression_model(po));
    all.push_back(make_robot_model(po));
    return all;
}

// At most this many steps in one run: about 2 years at 50 ns/step; beyond it something is off.
double max_run_steps = 1e15;

run_plan plan_steps(const run_setup& s, const std::string& model, double period,
                    long long default_steps_per_period, double default_time,
                    long long default_steps) {
    double count =
        0.0; // number of steps, checked against max_run_steps before it becomes an integer
    double h = 0.0;
    if (s.by_time) {
        count = static_cast<double>(s.steps);
        h = s.time / count;
    } else if (period > 0.0) {
        const long long spp =
            s.steps_per_period > 0 ? s.steps_per_period : default_steps_per_period;
        const double total = static_cast<double>(spp) * s.periods;
        count = std::round(total);
        if (std::abs(total - count) > 1e-9 * total || count < 1.0)
            throw usage_error("--periods " + std::to_string(s.periods) +
                              " times --steps-per-period " + std::to_string(spp) +
                              " is not a whole number of steps; choose periods so that it is");
        h = period / static_cast<double>(spp);
    } else {
        if (s.steps_per_period > 0 || s.periods_given)
            throw usage_error("--model " + model +
                              " has no period: give the run's length with --time and --steps");
        count = static_cast<double>(default_steps);
        h = default_time / count;
    }
    if (count > max_run_steps) {
        std::string limit;
        append_number(limit, max_run_steps);
        throw usage_error("more than " + limit + " steps requested");
    }
    if (!(std::isfinite(h) && h > 0.0)) throw usage_error("the time step is not a positive number");
    return {static_cast<std::size_t>(count), h, period > 0.0 ? period : 0.0};
}

vec<dynamic> initial_vector(const std::vector<double>& given, const char* option, int d,
                            const std::string& names, const vec<dynamic>& fallback) {
    if (given.empty()) return fallback;
    if (static_cast<int>(given.size()) != d)
        throw usage_error(std::string(option) + " needs " + std::to_string(d) + " value" +
                          (d == 1 ? "" : "s") + " (" + names + "), got " +
                          std::to_string(given.size()));
    return Eigen::Map<const vec<dynamic>>(given.data(), d);
}

} // namespace varsym::cli
