// apps/varsym/options/config.cpp: TOML config files for `varsym run` (toml++, from Debian).
#include "options/config.hpp"

#include <algorithm>

#include <toml++/toml.h>

#include "output/files.hpp"

namespace varsym::cli {

namespace {

std::string where(const std::string& file, const toml::node& node) {
    return file + ":" + std::to_string(node.source().begin.line);
}

/// One TOML scalar as an argument string, checked against the option's type ("INT", "FLOAT",
/// "TEXT"). Returns "" and sets `error` when the type does not fit.
std::string scalar_argument(const toml::node& node, const std::string& type, std::string& error) {
    if (type == "INT" || type == "UINT") {
        if (const auto v = node.value_exact<int64_t>()) return std::to_string(*v);
        error = "expects a whole number";
        return {};
    }
    if (type == "FLOAT") {
        if (const auto v = node.value_exact<int64_t>()) return std::to_string(*v);
        if (const auto v = node.value_exact<double>()) {
            std::string s;
            append_number(s, *v);
            return s;
        }
        error = "expects a number";
        return {};
    }
    if (const auto v = node.value_exact<std::string>()) return *v;
    error = "expects a string";
    return {};
}

bool on_command_line(const std::vector<std::string>& args, const CLI::Option& opt) {
    for (const std::string& a : args)
        for (const std::string& name : opt.get_lnames())
            if (a == "--" + name || a.starts_with("--" + name + "=")) return true;
    for (const std::string& a : args)
        for (const std::string& name : opt.get_snames())
            if (a == "-" + name) return true;
    return false;
}

} // namespace

std::vector<std::string> expand_config(const std::vector<std::string>& args, const CLI::App& app,
                                       config_origins& origins) {
    if (args.empty()) return args;
    const CLI::App* command = nullptr;
    for (const CLI::App* sub : app.get_subcommands({}))
        if (sub->check_name(args[0])) command = sub;
    if (command == nullptr || command->get_option_no_throw("--config") == nullptr) return args;
    std::string file;
    bool given = false;
    for (std::size_t i = 1; i < args.size(); ++i) {
        if (args[i] == "--config" && i + 1 < args.size()) file = args[i + 1], given = true;
        if (args[i].starts_with("--config=")) file = args[i].substr(9), given = true;
    }
    if (!given) return args;
    if (file.empty()) throw usage_error("--config needs a file name");

    toml::table table;
    try {
        // A valid config file is a few lines; 1 MiB is far beyond any.
        table = toml::parse(read_regular_file(file, 1U << 20, "config file"), file);
    } catch (const toml::parse_error& e) {
        const auto line = e.source().begin.line;
        if (line == 0)
            throw usage_error("cannot read config file '" + file +
                              "': " + std::string(e.description()));
        throw usage_error(file + ":" + std::to_string(line) + ": " + std::string(e.description()));
    }
    std::vector<std::string> inserted;
    for (auto&& [key, node] : table) {
        const std::string name(key.str());
        const std::string at = where(file, node);
        const CLI::Option* opt = command->get_option_no_throw("--" + name);
        if (opt == nullptr || name == "config" || name == "help")
            throw usage_error(at + ": unknown key '" + name +
                              "' (keys are the long options of 'varsym " + args[0] +
                              "' without '--', e.g. model, scheme; see 'varsym " + args[0] +
                              " --help')");
        const std::string full_type = opt->get_type_name();
        const std::string type = full_type.substr(0, full_type.find(':'));
        const bool flag = opt->get_expected_max() == 0;
        const bool list = full_type == list_type_name;
        std::string error, value;
        if (flag) {
            const auto b = node.value_exact<bool>();
            if (!b) throw usage_error(at + ": key '" + name + "' expects true or false");
            if (on_command_line(args, *opt)) continue;
            if (*b) inserted.push_back("--" + name);
            origins["--" + name] = at;
            continue;
        }
        const toml::array* arr = node.as_array();
        if (arr != nullptr && !list && opt->get_expected_max() > 1) {
            // A repeatable option (plot = ["a.png", "a.svg"]): one --name per entry.
            if (arr->empty()) throw usage_error(at + ": key '" + name + "' is an empty list");
            if (on_command_line(args, *opt)) continue;
            for (const toml::node& item : *arr) {
                const std::string one = scalar_argument(item, type, error);
                if (!error.empty())
                    throw usage_error(at + ": key '" + name + "': every entry " + error);
                inserted.push_back("--" + name);
                inserted.push_back(one);
            }
            origins["--" + name] = at;
            continue;
        }
        if (arr != nullptr) {
            if (!list) throw usage_error(at + ": key '" + name + "' takes one value, not a list");
            for (const toml::node& item : *arr) {
                const std::string one = scalar_argument(item, "FLOAT", error);
                if (!error.empty())
                    throw usage_error(at + ": key '" + name + "': every entry " + error);
                value += (value.empty() ? "" : ",") + one;
            }
            if (value.empty()) throw usage_error(at + ": key '" + name + "' is an empty list");
        } else {
            value = scalar_argument(node, type, error);
            if (!error.empty()) throw usage_error(at + ": key '" + name + "' " + error);
        }
        if (on_command_line(args, *opt)) continue;
        inserted.push_back("--" + name);
        inserted.push_back(value);
        origins["--" + name] = at;
    }
    std::vector<std::string> out{args[0]};
    out.insert(out.end(), inserted.begin(), inserted.end());
    out.insert(out.end(), args.begin() + 1, args.end());
    return out;
}

std::string locate(const std::string& message, const config_origins& origins) {
    for (const auto& [option, at] : origins) {
        const auto pos = message.find(option);
        if (pos == std::string::npos) continue;
        const auto end = pos + option.size();
        // a whole option name, not the prefix of a longer one (--steps vs --steps-per-period)
        if (end < message.size() &&
            (std::isalnum(static_cast<unsigned char>(message[end])) || message[end] == '-'))
            continue;
        return at + ": key '" + option.substr(2) + "': " + message;
    }
    return message;
}

} // namespace varsym::cli
