// apps/varsym/output/files.cpp: output files (atomic, written through, exclusive and locked),
// bounded reads, and the collision check of a command's files (files.hpp).
#include "output/files.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "options/cli_common.hpp"
#include "output/signals.hpp"
#include "varsym/models/input_file.hpp"

namespace varsym::cli {

namespace fs = std::filesystem;

namespace {

std::string error_text(int err) {
    return std::strerror(err);
}

/// Names of the calling process's own descriptors: always written through, never resolved.
bool names_a_descriptor(const std::string& path) {
    return path.starts_with("/dev/std") || path.starts_with("/dev/fd/") ||
           path.starts_with("/proc/");
}

/// Where the dangling link `path` (and the links it leads to, up to 40) ends: a path that does
/// not exist in a directory that does, or "" (a loop, a missing directory, an unreadable link).
/// Writing there creates the file the link names, as writing through the link would.
std::string dangling_target(const std::string& path) {
    fs::path at = fs::absolute(path);
    for (int hops = 0; hops < 40; ++hops) {
        std::error_code ec;
        const auto status = fs::symlink_status(at, ec);
        if (ec || status.type() == fs::file_type::not_found) {
            std::error_code dir;
            return fs::is_directory(at.parent_path(), dir) ? at.lexically_normal().string() : "";
        }
        if (status.type() != fs::file_type::symlink) return "";
        const fs::path next = fs::read_symlink(at, ec);
        if (ec) return "";
        at = next.is_absolute() ? next : at.parent_path() / next;
    }
    return "";
}

/// The kind of `path` and the path to write: a symbolic link to a regular file is replaced at
/// its target (the link stays a link); a dangling one creates its target, atomically too.
std::pair<file_kind, std::string> resolve(const std::string& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) return {file_kind::absent, path};
    if (S_ISREG(st.st_mode)) return {file_kind::regular, path};
    if (S_ISDIR(st.st_mode)) return {file_kind::directory, path};
    if (!S_ISLNK(st.st_mode) || names_a_descriptor(path)) return {file_kind::special, path};
    if (::stat(path.c_str(), &st) != 0) { // dangling: the file the chain of links would create
        const std::string end = dangling_target(path);
        return {end.empty() ? file_kind::special : file_kind::absent, end.empty() ? path : end};
    }
    if (S_ISDIR(st.st_mode)) return {file_kind::directory, path};
    if (!S_ISREG(st.st_mode)) return {file_kind::special, path};
    std::error_code ec;
    const fs::path target = fs::canonical(path, ec);
    if (ec) return {file_kind::special, path};
    return {file_kind::regular, target.string()};
}

/// Why PART, the partial file of FILE, cannot be created: it exists. Never touches it.
[[noreturn]] void refuse_existing_part(const std::string& file, const std::string& part) {
    const int fd = ::open(part.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat st {};
    if (fd >= 0 && ::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
        ::close(fd);
        throw usage_error("cannot write '" + file + "': its partial file '" + part +
                          "' is a directory");
    }
    const bool locked = fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
    if (fd >= 0) ::close(fd);
    if (locked)
        throw usage_error("another varsym run is writing '" + file + "' (its partial file '" +
                          part + "' is locked); wait for it, or choose another output");
    std::error_code ec;
    if (fs::exists(file + ".ckpt", ec))
        throw usage_error("cannot write '" + file + "': '" + part +
                          "' exists, the rows of a run that stopped with its checkpoint '" + file +
                          ".ckpt': resume that run with 'varsym run --resume " + file +
                          ".ckpt', or move both away");
    throw usage_error("cannot write '" + file + "': '" + part +
                      "' exists (the rows of a run that stopped, or a file of yours): move it "
                      "away or remove it");
}

} // namespace

void claim_partial(const std::string& file, bool ours) {
    const auto [kind, target] = resolve(file);
    if (kind != file_kind::absent && kind != file_kind::regular) return; // written through
    const std::string part = target + ".part";
    struct stat st {};
    if (::lstat(part.c_str(), &st) != 0) return;
    if (ours && S_ISREG(st.st_mode)) {
        const int fd = ::open(part.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
        const bool free = fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0;
        if (free) ::unlink(part.c_str()); // under the lock: no run is writing it
        if (fd >= 0) ::close(fd);
        if (free) return;
    }
    refuse_existing_part(file, part);
}

file_kind kind_of(const std::string& path) {
    return resolve(path).first;
}

std::string read_regular_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& role) {
    try {
        return models::read_input_file(path, max_bytes, role);
    } catch (const models::input_error& e) {
        throw usage_error(e.what());
    }
}

void file_roles::add(std::string role, const std::string& path) {
    if (path.empty() || path == "-") return;
    entries_.push_back({std::move(role), path});
}

void file_roles::add_output(std::string role, const std::string& path) {
    if (path.empty() || path == "-")
        entries_.push_back({role + " (standard output)", "/dev/stdout"});
    else
        add(std::move(role), path);
}

void file_roles::check() const {
    const auto device = [](const std::string& p) {
        struct stat st {};
        return ::stat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
    };
    // The file a write to p reaches: links followed, dangling ones to the file they would
    // create; a name of one of our descriptors as it is (its inode compares below).
    const auto target = [](const std::string& p) {
        const auto [kind, path] = resolve(p);
        std::error_code ec;
        const fs::path c = fs::weakly_canonical(fs::absolute(path), ec);
        return ec ? fs::absolute(path).lexically_normal() : c;
    };
    auto same = [&](const std::string& a, const std::string& b) {
        if (device(a) || device(b)) return false;
        if (target(a) == target(b)) return true;
        struct stat sa {
        }, sb{};
        return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 &&
               sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    };
    for (std::size_t i = 0; i < entries_.size(); ++i)
        for (std::size_t j = i + 1; j < entries_.size(); ++j)
            if (same(entries_[i].path, entries_[j].path))
                throw usage_error(entries_[i].role + " '" + entries_[i].path + "' and " +
                                  entries_[j].role + " '" + entries_[j].path +
                                  "' are the same file; give one of them another name");
}

output_file::output_file(const std::string& path) {
    if (path.empty() || path == "-") {
        f_ = stdout;
        return;
    }
    const auto [kind, target] = resolve(path);
    if (kind == file_kind::directory)
        throw usage_error("cannot write '" + path + "': it is a directory");
    path_ = target;
    if (kind == file_kind::special) {
        through_ = true;
        path_ = path;
        const int fd = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC | O_CREAT, 0666);
        if (fd < 0 || (f_ = ::fdopen(fd, "w")) == nullptr)
            throw std::runtime_error("cannot write '" + path + "': " + error_text(errno));
        return;
    }
    const std::string part = partial_path();
    const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno == EEXIST) refuse_existing_part(path, part);
    if (fd < 0) throw std::runtime_error("cannot write '" + part + "': " + error_text(errno));
    remove_at_signal(part);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0 || (f_ = ::fdopen(fd, "w")) == nullptr) {
        const int err = errno;
        ::unlink(part.c_str());
        forget_at_signal(part);
        ::close(fd);
        throw std::runtime_error("cannot lock '" + part + "': " + error_text(err));
    }
}

output_file::output_file(const std::string& path, std::uint64_t keep, std::uint32_t crc) {
    const auto [kind, target] = resolve(path);
    if (kind == file_kind::directory || kind == file_kind::special)
        throw usage_error("cannot resume: its output '" + path + "' is no longer a regular file");
    path_ = target;
    const std::string part = partial_path();
    const int fd = ::open(part.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0)
        throw usage_error("cannot resume: '" + part + "', the rows of the interrupted run, " +
                          (errno == ENOENT ? std::string("is missing")
                                           : "cannot be opened (" + error_text(errno) + ")"));
    auto refuse = [&](const std::string& why) {
        ::close(fd);
        throw usage_error("cannot resume: '" + part + "' " + why);
    };
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) refuse("is not a regular file");
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
        refuse("is locked by another varsym run (is this checkpoint being resumed already?)");
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (size < keep)
        refuse("has " + std::to_string(size) + " bytes, fewer than the " + std::to_string(keep) +
               " its checkpoint covers; it was changed after the run stopped");
    std::vector<char> buf(1 << 20);
    for (std::uint64_t at = 0; at < keep;) {
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(buf.size(), keep - at));
        const ssize_t n = ::pread(fd, buf.data(), want, static_cast<off_t>(at));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) refuse("cannot be read: " + error_text(n < 0 ? errno : EIO));
        crc_.process_bytes(buf.data(), static_cast<std::size_t>(n));
        at += static_cast<std::uint64_t>(n);
    }
    if (crc_.checksum() != crc)
        refuse("is not the file its checkpoint's run wrote (the CRC-32 of its first " +
               std::to_string(keep) + " bytes differs): it was changed or reused after the run " +
               "stopped");
    if (::ftruncate(fd, static_cast<off_t>(keep)) != 0 || ::lseek(fd, 0, SEEK_END) < 0 ||
        (f_ = ::fdopen(fd, "a")) == nullptr)
        refuse("cannot be truncated: " + error_text(errno));
    bytes_ = keep;
    keep_ = true; // an interrupted resumed run keeps its rows for the next resume
}

void output_file::fail_write(int err) const {
    throw std::runtime_error("cannot write '" +
                             (is_stdout() ? std::string("standard output") : path_.string()) +
                             "': " + error_text(err));
}

void output_file::sync() {
    if (std::fflush(f_) != 0 || (!is_stdout() && !through_ && ::fsync(::fileno(f_)) != 0))
        fail_write(errno);
}

output_file::~output_file() {
    if (is_stdout() || committed_) return;
    if (!keep_ && !through_) {
        ::unlink(partial_path().c_str()); // ours, created exclusively; still locked by us
        forget_at_signal(partial_path());
    }
    std::fclose(f_);
}

void output_file::write(const std::string& s) {
    bytes_ += s.size();
    crc_.process_bytes(s.data(), s.size());
    if (std::fwrite(s.data(), 1, s.size(), f_) != s.size() || std::fflush(f_) != 0)
        fail_write(errno);
}

void output_file::keep_partial() {
    keep_ = true;
    if (!is_stdout() && !through_) forget_at_signal(partial_path());
}

void output_file::commit() {
    if (is_stdout()) {
        if (std::fflush(f_) != 0) fail_write(errno);
        return;
    }
    committed_ = true; // the stream is closed below: the destructor must not touch it
    if (through_) {
        if (std::fclose(f_) != 0) fail_write(errno);
        return;
    }
    const std::string part = partial_path();
    const bool ok = std::fflush(f_) == 0 && ::fsync(::fileno(f_)) == 0;
    const int err = errno;
    if (!ok || std::rename(part.c_str(), path_.c_str()) != 0) {
        const int e = ok ? errno : err;
        if (!keep_) ::unlink(part.c_str());
        forget_at_signal(part);
        std::fclose(f_);
        fail_write(e);
    }
    forget_at_signal(part);
    fsync_directory(path_);
    if (std::fclose(f_) != 0) fail_write(errno); // releases the lock, after the rename
}

void fsync_directory(const fs::path& file) {
    const auto dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return; // best effort: the rename itself is atomic
    ::fsync(fd);
    ::close(fd);
}

void write_exclusively(const std::string& path, const std::string& body, bool replace,
                       const std::string& role) {
    const std::string tmp = path + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0)
        throw std::runtime_error(
            "cannot write " + role + " '" + path + "': '" + tmp + "': " +
            (errno == EEXIST ? std::string("exists, not written by this run") : error_text(errno)));
    remove_at_signal(tmp);
    auto fail = [&](const std::string& what, int err) {
        ::close(fd);
        ::unlink(tmp.c_str());
        forget_at_signal(tmp);
        throw std::runtime_error("cannot write " + role + " '" + what + "': " + error_text(err));
    };
    std::size_t done = 0;
    while (done < body.size()) {
        const ssize_t n = ::write(fd, body.data() + done, body.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail(tmp, n < 0 ? errno : EIO);
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0) fail(tmp, errno);
    if (replace ? std::rename(tmp.c_str(), path.c_str()) != 0
                : ::link(tmp.c_str(), path.c_str()) != 0)
        fail(path, errno);
    if (!replace) ::unlink(tmp.c_str());
    forget_at_signal(tmp);
    ::close(fd);
    fsync_directory(path);
}

} // namespace varsym::cli
