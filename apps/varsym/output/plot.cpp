// apps/varsym/output/plot.cpp: writes a figure's data and gnuplot script, and runs gnuplot.
#include "output/plot.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "options/cli_common.hpp"
#include "output/signals.hpp"

namespace varsym::cli {

namespace fs = std::filesystem;

namespace {

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

/// gnuplot's message in its log: the last line that says something (it echoes the command
/// and a caret line before its '"FILE", line N: what' message).
std::string last_message(const fs::path& file) {
    std::ifstream in(file);
    std::string line, last;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t^") != std::string::npos) last = line;
    return last.empty() ? "no message" : last;
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

void add_figure_files(file_roles& roles, const std::vector<std::string>& suffixes,
                      const std::vector<std::string>& outputs) {
    if (outputs.empty()) return;
    const fs::path first = fs::absolute(outputs.front());
    const fs::path dir = first.parent_path();
    const std::string stem = first.stem().string();
    for (const auto& o : outputs) {
        roles.add("picture", o);
        if (kind_of(o) != file_kind::special) roles.add("the picture's partial file", o + ".part");
    }
    for (const auto& suffix : suffixes) {
        const std::string path = (dir / (stem + suffix)).string();
        roles.add("the figure's data", path);
        if (kind_of(path) != file_kind::special) roles.add("its partial file", path + ".part");
    }
    const std::string script = (dir / (stem + ".gp")).string();
    roles.add("the figure's gnuplot script", script);
    if (kind_of(script) != file_kind::special) roles.add("its partial file", script + ".part");
}

namespace {

/// A temporary file of ours in `dir` (created exclusively), removed when this dies.
class temporary_file {
  public:
    explicit temporary_file(const fs::path& dir) {
        std::string name = (dir / ".varsym-XXXXXX").string();
        const int fd = ::mkstemp(name.data());
        if (fd < 0)
            throw std::runtime_error("cannot create a temporary file in '" + dir.string() +
                                     "': " + std::strerror(errno));
        ::close(fd);
        path_ = name;
        remove_at_signal(path_);
    }
    temporary_file(const temporary_file&) = delete;
    temporary_file& operator=(const temporary_file&) = delete;
    ~temporary_file() {
        ::unlink(path_.c_str());
        forget_at_signal(path_);
    }
    [[nodiscard]] const std::string& path() const { return path_; }

  private:
    std::string path_;
};

} // namespace

void render_figure(const figure& fig, const std::vector<std::string>& outputs, file_roles roles) {
    check_pictures(outputs);
    std::vector<std::string> suffixes;
    for (const auto& d : fig.data)
        suffixes.push_back(d.first);
    add_figure_files(roles, suffixes, outputs);
    roles.check();
    const fs::path first = fs::absolute(outputs.front());
    const fs::path dir = first.parent_path();
    const std::string stem = first.stem().string();
    // Every file is opened (FILE.part created and locked) before any is written, and all are
    // committed at the end: a failure anywhere leaves none behind.
    std::vector<std::unique_ptr<output_file>> files;
    for (const auto& [suffix, content] : fig.data) {
        files.push_back(std::make_unique<output_file>((dir / (stem + suffix)).string()));
        files.back()->write(content);
    }
    const std::string script = stem + ".gp";
    const std::string picture = first.filename().string();
    files.push_back(std::make_unique<output_file>((dir / script).string()));
    files.back()->write("# " + script + ": run  gnuplot " + script + "  in this folder to redraw " +
                        picture + ";\n# gnuplot -e " + "\"out='other.svg'\" " + script +
                        " draws elsewhere (.png or .svg).\n" + "if (!exists(\"out\")) out = '" +
                        picture + "'\n" + "if (!exists(\"fmt\")) fmt = out[strlen(out)-2:]\n" +
                        "stem = '" + stem + "'\n" + fig.script);
    for (const auto& f : files)
        f->sync(); // gnuplot reads them by name
    // The script reads stem.SUFFIX: while they are partial files, let it read those.
    std::vector<std::unique_ptr<output_file>> pictures;
    for (const auto& o : outputs)
        pictures.push_back(std::make_unique<output_file>(o));
    const temporary_file gp(dir);
    {
        std::string body = "stem = '" + stem + "'\n" + fig.script;
        for (const auto& [suffix, content] : fig.data) {
            const std::string name = stem + suffix;
            const std::string part =
                kind_of((dir / name).string()) == file_kind::special ? name : name + ".part";
            for (std::size_t at = body.find("stem.'" + suffix + "'"); at != std::string::npos;
                 at = body.find("stem.'" + suffix + "'", at + 1))
                body.replace(at, suffix.size() + 7, "'" + part + "'");
        }
        std::ofstream(gp.path()) << body;
    }
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const std::string& o = outputs[i];
        const temporary_file drawn(dir), log(dir);
        const std::string fmt = fs::path(o).extension().string().substr(1);
        const int rc = run_gnuplot(dir, fs::path(gp.path()).filename().string(),
                                   fs::path(drawn.path()).filename().string(), fmt, log.path());
        if (rc != 0)
            throw std::runtime_error(
                "cannot draw '" + o + "': " +
                (rc == 127 ? std::string("gnuplot not found; install gnuplot-nox (make run does)")
                           : "gnuplot failed: " + last_message(log.path())));
        pictures[i]->write(read_regular_file(
            drawn.path(), std::numeric_limits<std::uint64_t>::max(), "picture drawn by gnuplot"));
    }
    for (const auto& f : files)
        f->commit();
    for (const auto& p : pictures)
        p->commit();
}

} // namespace varsym::cli
