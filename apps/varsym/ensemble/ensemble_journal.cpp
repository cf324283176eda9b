// apps/varsym/ensemble/ensemble_journal.cpp: locking, reading, continuing and merging the
// journals of an ensemble.
#include "ensemble/ensemble_journal.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <queue>
#include <stdexcept>
#include <string_view>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <boost/crc.hpp>

#include "options/cli_common.hpp"
#include "output/files.hpp"

namespace varsym::cli {

namespace fs = std::filesystem;

namespace {

/// The journals of `output`: OUTPUT.journal and OUTPUT.journal.N.
std::vector<fs::path> journals_of(const std::string& output) {
    const fs::path out(output);
    const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
    const std::string stem = out.filename().string() + ".journal";
    std::vector<fs::path> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        if (!name.starts_with(stem)) continue;
        const std::string_view rest = std::string_view(name).substr(stem.size());
        const bool numbered =
            rest.size() > 1 && rest[0] == '.' &&
            std::all_of(rest.begin() + 1, rest.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (rest.empty() || numbered) found.push_back(e.path());
    }
    std::sort(found.begin(), found.end());
    return found;
}

/// The first line of this version's journals, and of the versions before row checksums.
constexpr std::string_view header_prefix = "# varsym ensemble journal 2: ";
constexpr std::string_view old_header_prefix = "# varsym ensemble: ";

/// A row's checksum, " #" and the CRC-32 of the row's text (without its '\n') in 8 hex digits.
constexpr std::size_t checksum_size = 10;

std::string checksum_of(std::string_view row) {
    boost::crc_32_type crc;
    crc.process_bytes(row.data(), row.size());
    char buf[16];
    std::snprintf(buf, sizeof buf, " #%08x", static_cast<unsigned>(crc.checksum()));
    return {buf, checksum_size};
}

/// A file's lines in order, read through a buffer of fixed size (memory independent of the
/// file's size). Several readers may share one descriptor (pread).
class line_reader {
  public:
    line_reader(int fd, std::uint64_t at, std::size_t buffer = std::size_t{1} << 16)
        : fd_(fd), base_(at), buf_(buffer) {}
    /// The next complete line, without its '\n', and the offset where it starts; false at the
    /// end of the file (`line` then holds a last line without '\n', if any).
    bool next(std::string& line, std::uint64_t& start) {
        line.clear();
        start = offset();
        for (;;) {
            if (at_ == have_) {
                base_ += have_;
                at_ = have_ = 0;
                ssize_t n = 0;
                do
                    n = ::pread(fd_, buf_.data(), buf_.size(), static_cast<off_t>(base_));
                while (n < 0 && errno == EINTR);
                if (n < 0)
                    throw std::runtime_error(std::string("cannot read a journal: ") +
                                             std::strerror(errno));
                if (n == 0) return false;
                have_ = static_cast<std::size_t>(n);
            }
            const char* b = buf_.data() + at_;
            const char* e = buf_.data() + have_;
            const char* nl = std::find(b, e, '\n');
            line.append(b, nl);
            at_ = static_cast<std::size_t>(nl - buf_.data());
            if (nl != e) {
                ++at_;
                return true;
            }
        }
    }
    /// The offset just after the last line read.
    [[nodiscard]] std::uint64_t offset() const { return base_ + at_; }

  private:
    int fd_;
    std::uint64_t base_; ///< the file offset of buf_[0]
    std::vector<char> buf_;
    std::size_t have_ = 0, at_ = 0;
};

/// An open journal, read-only, closed with the object.
struct journal_file {
    explicit journal_file(const fs::path& p) : path(p.string()) {
        fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
        struct stat st {};
        if (fd < 0 || ::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
            const int err = errno;
            if (fd >= 0) ::close(fd);
            throw usage_error("cannot read journal '" + path +
                              "': " + (fd < 0 ? std::strerror(err) : "not a regular file"));
        }
        size = static_cast<std::uint64_t>(st.st_size);
    }
    journal_file(const journal_file&) = delete;
    journal_file& operator=(const journal_file&) = delete;
    ~journal_file() { ::close(fd); }
    std::string path;
    int fd = -1;
    std::uint64_t size = 0;
};

/// Whether a journal whose first line is `first` (`complete`: it ends in '\n') belongs to the
/// ensemble of `header` (one line with its '\n'): yes; a header cut short: yes, without rows;
/// another ensemble's or an older varsym's: usage_error saying what to do.
void check_header(const std::string& first, bool complete, const std::string& header,
                  const std::string& name) {
    if (complete ? first.size() + 1 == header.size() && header.starts_with(first)
                 : header.starts_with(first))
        return;
    if (first.starts_with(old_header_prefix))
        throw usage_error(name + " was written by an older varsym, without row checksums: "
                                 "finish that ensemble with that version, or remove it to "
                                 "compute its members again");
    throw usage_error(name + " belongs to another ensemble (its first line differs from this "
                             "command's): rerun the command that made it to finish that "
                             "ensemble, or remove it to start this one");
}

constexpr std::size_t no_member = std::numeric_limits<std::size_t>::max();

/// The member of a journal row whose checksum and fields check, else no_member.
std::size_t member_of(std::string_view line, std::size_t members, std::size_t fields) {
    if (line.size() <= checksum_size) return no_member;
    const std::string_view body = line.substr(0, line.size() - checksum_size);
    std::size_t m = 0;
    const auto [p, ec] = std::from_chars(body.data(), body.data() + body.size(), m);
    if (checksum_of(body) != line.substr(body.size()) || ec != std::errc() || *p != ',' ||
        m >= members ||
        static_cast<std::size_t>(std::count(body.begin(), body.end(), ',')) + 1 != fields)
        return no_member;
    return m;
}

/// Calls row(member, line) for each row of journal f whose checksum and fields check, and
/// counts the others in `rejected`. Returns the offset after its last complete line (0 for a
/// journal without a complete first line), or throws usage_error for another ensemble's.
template <class Row>
std::uint64_t scan(const journal_file& f, const std::string& header, std::size_t members,
                   std::size_t fields, std::size_t& rejected, Row&& row) {
    line_reader in(f.fd, 0);
    std::string line;
    std::uint64_t start = 0;
    const bool complete = in.next(line, start);
    if (!complete && line.empty()) return 0; // empty
    check_header(line, complete, header, f.path);
    if (!complete) return 0;
    std::uint64_t keep = in.offset();
    while (in.next(line, start)) {
        keep = in.offset();
        const std::size_t m = member_of(line, members, fields);
        if (m == no_member)
            ++rejected;
        else
            row(m, line, start);
    }
    return keep;
}

} // namespace

ensemble_journal::ensemble_journal(std::string output, const std::string& identity,
                                   std::size_t members, std::size_t fields)
    : output_(std::move(output)), identity_(std::string(header_prefix) + identity + "\n"),
      members_(members), fields_(fields) {
    if (identity.find('\n') != std::string::npos)
        throw std::logic_error("an ensemble's identity is one line");
}

void ensemble_journal::read() {
    for (const fs::path& j : journals_of(output_)) {
        const journal_file f(j);
        if (f.size == 0) continue; // a journal just created (or a lock)
        scan(f, identity_, members_, fields_, rejected_,
             [&](std::size_t m, const std::string&, std::uint64_t) {
                 if (done_.empty()) done_.resize(members_); // a bit per member, if any is done
                 if (!done_[m]) ++done_count_;
                 done_[m] = true;
             });
        found_ = true;
    }
}

ensemble_journal::~ensemble_journal() {
    if (fd_ < 0) return;
    // A journal this process created and never wrote (a refusal before the work) is removed,
    // under its lock; a starter that opened it meanwhile sees its inode gone and retries.
    struct stat st {};
    if (::fstat(fd_, &st) == 0 && st.st_size == 0) ::unlink(path_.c_str());
    ::close(fd_); // releases the lock
}

void ensemble_journal::lock(const std::string& suffix) {
    path_ = output_ + suffix;
    // The file locked must still be the one at path_: an ensemble finishing removes its
    // journals, and a lock taken on a removed file would exclude nobody.
    for (int attempt = 0;; ++attempt) {
        fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0) throw std::runtime_error("cannot open " + path_ + ": " + std::strerror(errno));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            ::close(fd_);
            fd_ = -1;
            throw usage_error(path_ + " is in use by another running ensemble of the same output");
        }
        struct stat held {
        }, now{};
        if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &now) == 0 &&
            held.st_dev == now.st_dev && held.st_ino == now.st_ino)
            return;
        ::close(fd_);
        fd_ = -1;
        if (attempt == 100)
            throw std::runtime_error("cannot lock " + path_ + ": it is replaced continually");
    }
}

void ensemble_journal::start() {
    std::size_t ignored = 0;
    const std::uint64_t keep = scan(journal_file(path_), identity_, members_, fields_, ignored,
                                    [](std::size_t, const std::string&, std::uint64_t) {});
    if (::ftruncate(fd_, static_cast<off_t>(keep)) != 0 ||
        ::lseek(fd_, static_cast<off_t>(keep), SEEK_SET) < 0)
        throw std::runtime_error("cannot cut " + path_ + ": " + std::strerror(errno));
    if (keep == 0) write_all(identity_);
}

void ensemble_journal::append(const std::string& rows) {
    std::string checked;
    checked.reserve(rows.size() + rows.size() / 8);
    for (std::size_t at = 0; at < rows.size();) {
        const std::size_t end = rows.find('\n', at);
        if (end == std::string::npos) throw std::logic_error("a journal row without its '\\n'");
        const std::string_view row(rows.data() + at, end - at);
        checked.append(row).append(checksum_of(row)).push_back('\n');
        at = end + 1;
    }
    write_all(checked);
}

void ensemble_journal::write_all(const std::string& text) {
    std::size_t at = 0;
    while (at < text.size()) {
        const ssize_t n = ::write(fd_, text.data() + at, text.size() - at);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
        at += static_cast<std::size_t>(n);
    }
}

void ensemble_journal::merge(const std::function<void(std::string_view)>& emit) const {
    // Each journal is a few runs of rows in increasing member order (the writers flush rows in
    // order; a restart or a member far slower than the rest begins a new run). A heap merges
    // the runs, each read through its own small buffer: memory independent of the output.
    std::vector<std::unique_ptr<journal_file>> files;
    struct run {
        std::size_t file;
        std::uint64_t at;
    };
    std::vector<run> runs;
    for (const fs::path& j : journals_of(output_)) {
        files.push_back(std::make_unique<journal_file>(j));
        if (files.back()->size == 0) continue;
        std::size_t previous = no_member, ignored = 0;
        scan(*files.back(), identity_, members_, fields_, ignored,
             [&](std::size_t m, const std::string&, std::uint64_t start) {
                 if (previous == no_member || m <= previous)
                     runs.push_back({files.size() - 1, start});
                 previous = m;
             });
    }
    struct cursor {
        line_reader in;
        std::size_t member = no_member;
        std::string row, line;
        /// The run's next valid row; false where the run ends (at the next run's first row).
        bool advance(std::size_t members, std::size_t fields) {
            std::uint64_t start = 0;
            while (in.next(line, start)) {
                const std::size_t m = member_of(line, members, fields);
                if (m == no_member) continue;
                if (member != no_member && m <= member) return false;
                member = m;
                row.assign(line, 0, line.size() - checksum_size);
                return true;
            }
            return false;
        }
    };
    const std::size_t buffer =
        std::clamp<std::size_t>((std::size_t{32} << 20) / std::max<std::size_t>(runs.size(), 1),
                                std::size_t{4} << 10, std::size_t{64} << 10);
    std::vector<cursor> cursors;
    cursors.reserve(runs.size());
    using entry = std::pair<std::size_t, std::size_t>; // member, cursor
    std::priority_queue<entry, std::vector<entry>, std::greater<>> heap;
    for (const run& r : runs) {
        cursors.push_back({line_reader(files[r.file]->fd, r.at, buffer), no_member, {}, {}});
        if (cursors.back().advance(members_, fields_))
            heap.emplace(cursors.back().member, cursors.size() - 1);
    }
    std::size_t expected = 0;
    while (!heap.empty()) {
        const auto [m, k] = heap.top();
        heap.pop();
        if (m == expected) { // else a member's second row (a rerun's): the first one counts
            emit(cursors[k].row);
            ++expected;
        } else if (m > expected) {
            break;
        }
        if (cursors[k].advance(members_, fields_)) heap.emplace(cursors[k].member, k);
    }
    if (expected != members_)
        throw std::runtime_error("member " + std::to_string(expected) +
                                 " has no row in the journals of " + output_);
}

void ensemble_journal::remove_all() {
    for (const fs::path& j : journals_of(output_)) {
        std::error_code ec;
        fs::remove(j, ec);
    }
}

} // namespace varsym::cli
