// apps/varsym/commands/cmd_models.cpp: `varsym models`, the built-in models with their parameters
// and conserved quantities, as text or as CSV (one row per parameter, for scripts).
#include <charconv>
#include <iostream>

#include "commands/commands.hpp"
#include "models/models.hpp"
#include "models/registry_models.hpp"

namespace varsym::cli {

namespace {

/// A CSV field: quoted when it holds a comma or a quote.
std::string field(const std::string& s) {
    if (s.find_first_of(",\"") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s)
        q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + '"';
}

void print_csv() {
    std::cout << "model,commands,parameter,option,default,unit,range,meaning\n";
    for (const model& m : make_models()) {
        const models::model* rm = models::find(m.name);
        // lagrangian, made from its options (Python: Lagrangian), runs in every command.
        const std::string commands = rm == nullptr ? "run ensemble section converge python"
                                     : make_registry_ensemble(unowned(*rm)).section
                                         ? "run ensemble section converge python"
                                         : "run ensemble converge python";
        if (rm == nullptr || (rm->parameters.empty() && rm->lists.empty())) {
            std::cout << m.name << ',' << field(commands) << ",,,,,,\n";
            continue;
        }
        for (const auto& p : rm->parameters) {
            char buf[32];
            const auto r = std::to_chars(buf, buf + sizeof buf, p.value);
            std::cout << m.name << ',' << field(commands) << ',' << p.name << ",--"
                      << p.option_name() << ',' << std::string(buf, r.ptr) << ',' << field(p.unit)
                      << ',' << field(p.range()) << ',' << field(p.doc) << '\n';
        }
        for (const auto& l : rm->lists) { // a default of several values: space-separated
            std::string values;
            for (double v : l.value) {
                char buf[32];
                const auto r = std::to_chars(buf, buf + sizeof buf, v);
                if (!values.empty()) values += ' ';
                values.append(buf, r.ptr);
            }
            std::cout << m.name << ',' << field(commands) << ',' << l.name << ",--"
                      << l.option_name() << ',' << values << ',' << field(l.unit) << ','
                      << field("each " + l.range()) << ',' << field(l.doc) << '\n';
        }
    }
}

} // namespace

void add_models_command(CLI::App& app, action& todo) {
    auto* cmd = app.add_subcommand("models", "List the built-in models, their parameters and what "
                                             "they conserve");
    auto format = std::make_shared<std::string>("text");
    cmd->add_option("--format", *format,
                    "text (descriptions) or csv (one row per parameter: model, the commands that "
                    "run it, parameter, option, default, unit, range, meaning)")
        ->check(CLI::IsMember({"text", "csv"}))
        ->capture_default_str();
    cmd->footer("\nEach model runs with 'varsym run --model NAME [its parameters]', and also in "
                "'varsym ensemble',\n'varsym converge' and Python; and in 'varsym section' where "
                "its stepper has dense\noutput (all but the rigid bodies and the constrained "
                "mechanisms).");
    cmd->callback([&todo, format] {
        todo = [format] {
            if (*format == "csv") {
                print_csv();
                return;
            }
            for (const model& m : make_models())
                std::cout << m.name << ": " << m.summary << '\n' << m.description << "\n\n";
            std::cout << "All models: --scheme simpson|newmark|lobatto|gauss (--degree s) "
                         "(rigid bodies: --order 2|4|6),\n--steps-per-period/--periods or "
                         "--time/--steps, --every, --output; see 'varsym run --help'.\n";
        };
    });
}

} // namespace varsym::cli
