// apps/varsym/options/config.hpp: `varsym run --config FILE` (and `varsym optimize --config
// FILE`): a TOML file of options, turned into command-line arguments before parsing, with each
// key's line kept for error messages.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "options/cli_common.hpp"

namespace varsym::cli {

/// Where each option read from a config file came from: "--eccentricity" -> "run.toml:3".
using config_origins = std::map<std::string, std::string>;

/// If args (argv without the program name) run a subcommand of `app` that has a --config option
/// with --config FILE, returns args with the file's options inserted after the subcommand's name
/// (options already on the command line win), and fills `origins`. Unknown keys and values of
/// the wrong type are refused with FILE:LINE and the key; the subcommand's options say what keys
/// and types are valid.
std::vector<std::string> expand_config(const std::vector<std::string>& args, const CLI::App& app,
                                       config_origins& origins);

/// The message, prefixed with "FILE:LINE: key 'k': " if it names an option that came from the
/// config file.
std::string locate(const std::string& message, const config_origins& origins);

} // namespace varsym::cli
