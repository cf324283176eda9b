// apps/varsym/plot.cpp: writes a figure's data and gnuplot script, and runs gnuplot.
#include "plot.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_common.hpp"

namespace varsym::cli {

namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::string& content) {
    output_file f(path.string());
    f.write(content);
    f.commit();
}

// Runs `gnuplot -e "out='NAME'; fmt='EXT'" SCRIPT` in `dir`, with its messages in `log`.
// Returns gnuplot's exit status (127 if gnuplot could not be started).
int run_gnuplot(const fs::path& dir, const std::string& script, const std::string& out,
                const std::string& fmt, const fs::path& log) {
    const std::string vars = "out='" + out + "'; fmt='" + fmt + "'";
    const pid_t pid = fork();
    if (pid < 0)
        throw std::runtime_error(std::string("cannot start gnuplot: ") + std::strerror(errno));
    if (pid == 0) {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            ::dup2(fd, STDOUT_FILENO);
            ::dup2(fd, STDERR_FILENO);
        }
        if (::chdir(dir.c_str()) != 0) _exit(126);
        ::execlp("gnuplot", "gnuplot", "-e", vars.c_str(), script.c_str(),
                 static_cast<char*>(nullptr));
        _exit(127);
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

std::string first_line(const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
        if (!line.empty() && line.find_first_not_of(" \t^") != std::string::npos) return line;
    return "no message";
}

} // namespace

std::string script_preamble(int svg_width, int svg_height) {
    const int png_width = svg_width * 14 / 11, png_height = svg_height * 14 / 11;
    return "set encoding utf8\n"
           "if (fmt eq 'svg') {\n"
           "  set terminal svg size " +
           std::to_string(svg_width) + "," + std::to_string(svg_height) +
           " dynamic enhanced font 'DejaVu Sans,13' background rgb 'white'\n"
           "} else {\n"
           "  set terminal pngcairo size " +
           std::to_string(png_width) + "," + std::to_string(png_height) +
           " enhanced font 'DejaVu Sans,13' background rgb 'white'\n"
           "}\n"
           "set output out\n"
           "set datafile separator ','\n"
           "set grid lc rgb '#dddddd'\n";
}

void check_pictures(const std::vector<std::string>& outputs) {
    if (outputs.empty()) throw usage_error("no --output picture given");
    const fs::path first = fs::absolute(outputs.front());
    for (const auto& o : outputs) {
        const fs::path p = fs::absolute(o);
        const std::string ext = p.extension().string();
        if (ext != ".png" && ext != ".svg")
            throw usage_error("cannot draw '" + o + "': use a .png or .svg file name");
        if (p.parent_path() != first.parent_path() || p.stem() != first.stem())
            throw usage_error("all pictures of one figure must share folder and name, "
                              "differing only in extension (got '" +
                              o + "')");
        if (o.find_first_of("'\"") != std::string::npos)
            throw usage_error("cannot draw '" + o + "': quotes in file names are not supported");
    }
    if (!fs::is_directory(first.parent_path()))
        throw std::runtime_error("cannot write '" + outputs.front() + "': folder '" +
                                 first.parent_path().string() + "' does not exist");
}

void render_figure(const figure& fig, const std::vector<std::string>& outputs) {
    check_pictures(outputs);
    const fs::path first = fs::absolute(outputs.front());
    const fs::path dir = first.parent_path();
    const std::string stem = first.stem().string();
    for (const auto& [suffix, content] : fig.data)
        write_file(dir / (stem + suffix), content);
    const std::string script = stem + ".gp";
    const std::string picture = first.filename().string();
    write_file(dir / script,
               "# " + script + ": run  gnuplot " + script + "  in this folder to redraw " +
                   picture + ";\n# gnuplot -e \"out='other.svg'\" " + script +
                   " draws elsewhere (.png or .svg).\n" + "if (!exists(\"out\")) out = '" +
                   picture + "'\n" + "if (!exists(\"fmt\")) fmt = out[strlen(out)-2:]\n" +
                   "stem = '" + stem + "'\n" + fig.script);
    for (const auto& o : outputs) {
        const fs::path p = fs::absolute(o);
        const std::string name = p.filename().string();
        const std::string part = name + ".part";
        const fs::path log = dir / (stem + ".gnuplot.log");
        const int rc = run_gnuplot(dir, script, part, p.extension().string().substr(1), log);
        if (rc != 0) {
            std::error_code ec;
            fs::remove(dir / part, ec);
            const std::string why = rc == 127
                                        ? "gnuplot not found; install gnuplot-nox (make run does)"
                                        : "gnuplot failed: " + first_line(log);
            fs::remove(log, ec);
            throw std::runtime_error("cannot draw '" + o + "': " + why);
        }
        std::error_code ec;
        fs::remove(log, ec);
        fs::rename(dir / part, p);
    }
}

} // namespace varsym::cli
