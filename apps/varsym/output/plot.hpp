// apps/varsym/output/plot.hpp: figures drawn by gnuplot from a CSV and a script kept beside them.
#pragma once

#include <string>
#include <vector>

#include "output/files.hpp"

namespace varsym::cli {

/// A figure: its data files (suffix after the picture's stem, and content) and the body of a
/// gnuplot script that reads them as stem.SUFFIX (variable `stem`) and draws to `out` in the
/// format `fmt` ("png" or "svg"), both set by the script's header.
struct figure {
    std::vector<std::pair<std::string, std::string>> data;
    std::string script;
};

/// The start of every figure script: UTF-8, the terminal chosen by `fmt` (svg, or pngcairo at
/// 1.27 × the size for the same look), output to `out`, CSV input, a light grid.
std::string script_preamble(int svg_width, int svg_height);

/// Checks picture names before any work: .png or .svg, one folder and name, folder exists.
/// Throws usage_error (bad name) or std::runtime_error (missing folder).
void check_pictures(const std::vector<std::string>& outputs);

/// Adds the files a figure writes to `roles`: each picture, its data files STEM.SUFFIX for
/// each suffix (figure::data), its script STEM.gp, and their partial files.
void add_figure_files(file_roles& roles, const std::vector<std::string>& suffixes,
                      const std::vector<std::string>& outputs);

/// Writes the data files and STEM.gp beside the pictures, then renders each picture (.png or
/// .svg, same folder and stem) by running gnuplot there. The figure's files are checked against
/// each other and against `roles` (the command's other files) first; every file goes through
/// output_file (files.hpp) and all are committed at the end, so a failure leaves none.
void render_figure(const figure& fig, const std::vector<std::string>& outputs,
                   file_roles roles = {});

} // namespace varsym::cli
