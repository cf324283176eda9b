// apps/varsym/output/snapshot.cpp: a PNG picture of an animation page, taken by headless
// Chromium (`varsym animate --snapshot`): the page is what the picture shows, so one renderer
// serves both. Chromium is run directly (no shell), with a scratch profile, and stopped after
// two minutes.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "models/models.hpp"

extern char** environ;

namespace varsym::cli {

namespace fs = std::filesystem;

std::string find_chromium() {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
        std::size_t at = 0;
        while (at <= dirs.size()) {
            const std::size_t end = std::min(dirs.find(':', at), dirs.size());
            const fs::path p = fs::path(dirs.substr(at, end - at)) / name;
            if (::access(p.c_str(), X_OK) == 0) return p.string();
            at = end + 1;
        }
    }
    throw usage_error("--snapshot takes the picture with headless Chromium, which is not on "
                      "PATH: apt-get install chromium");
}

/// file:// and the absolute path, percent-encoded but for unreserved characters and '/'.
std::string file_url(const std::string& path) {
    std::string out = "file://";
    for (const unsigned char c : fs::absolute(path).lexically_normal().string()) {
        if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
            out += static_cast<char>(c);
        } else {
            char buf[4];
            std::snprintf(buf, sizeof buf, "%%%02X", c);
            out += buf;
        }
    }
    return out;
}

void take_snapshot(const std::string& page, const std::string& png,
                   const std::vector<double>& times) {
    const std::string exe = find_chromium();
    std::string hash = "#ui=0&t=" + std::to_string(times.back());
    if (times.size() > 1) {
        hash += "&ghosts=";
        for (std::size_t i = 0; i + 1 < times.size(); ++i)
            hash.append(i ? "," : "").append(std::to_string(times[i]));
    }
    char profile[] = "/tmp/varsym-chromium-XXXXXX";
    if (::mkdtemp(profile) == nullptr)
        throw std::runtime_error(std::string("--snapshot: cannot make a scratch directory: ") +
                                 std::strerror(errno));
    // Chromium writes into the scratch directory; the picture is then copied to PNG.tmp.png,
    // created exclusively, and renamed.
    const std::string shot = std::string(profile) + "/shot.png";
    const std::string tmp = png + ".tmp.png";
    std::vector<std::string> args = {exe,
                                     "--headless=new",
                                     "--no-sandbox",
                                     "--disable-gpu",
                                     "--use-angle=swiftshader",
                                     "--enable-unsafe-swiftshader",
                                     "--hide-scrollbars",
                                     "--force-device-scale-factor=1",
                                     "--no-first-run",
                                     "--disable-extensions",
                                     std::string("--user-data-dir=") + profile,
                                     "--window-size=1200,800",
                                     "--virtual-time-budget=5000",
                                     "--screenshot=" + shot,
                                     file_url(page) + hash};
    std::vector<char*> argv;
    for (std::string& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t quiet; // Chromium's chatter to /dev/null
    posix_spawn_file_actions_init(&quiet);
    posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    const int rc = ::posix_spawn(&pid, exe.c_str(), &quiet, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&quiet);
    int status = 0;
    bool done = false;
    if (rc == 0) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::minutes(2);
        while (!(done = ::waitpid(pid, &status, WNOHANG) == pid) &&
               std::chrono::steady_clock::now() < end)
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (!done) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
        }
    }
    std::error_code ec;
    const bool drawn = rc == 0 && done && fs::is_regular_file(shot) && fs::file_size(shot, ec) > 0;
    const bool copied = drawn && fs::copy_file(shot, tmp, fs::copy_options::skip_existing, ec);
    fs::remove_all(profile, ec);
    if (!drawn)
        throw std::runtime_error("--snapshot: Chromium (" + exe + ") " +
                                 (rc != 0 ? "could not be started"
                                  : !done ? "took more than two minutes"
                                          : "wrote no picture") +
                                 "; the page " + page + " is written");
    if (!copied)
        throw std::runtime_error("--snapshot: cannot write '" + tmp + "'" +
                                 (fs::exists(tmp, ec) ? ": it exists (move it away)" : ""));
    fs::rename(tmp, png, ec);
    if (ec) throw std::runtime_error("--snapshot: cannot write '" + png + "': " + ec.message());
}

} // namespace varsym::cli
