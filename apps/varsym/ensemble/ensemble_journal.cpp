// apps/varsym/ensemble/ensemble_journal.cpp: locking, reading, continuing and merging the
// journals of an ensemble.
#include "ensemble_journal.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <boost/crc.hpp>

#include "cli_common.hpp"
#include "files.hpp"

namespace varsym::cli {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t max_journal_bytes = std::uint64_t{1} << 36; // 64 GiB

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

/// Calls row(member, the row's text without its checksum and '\n') for each complete
/// row of a journal's text after its header whose checksum and fields check; counts the others
/// in `rejected`. Returns the length of the text up to its last '\n' (a row being written when
/// the run stopped is cut off).
template <class Row>
std::size_t scan(const std::string& text, const std::string& header, std::size_t members,
                 std::size_t fields, const std::string& name, std::size_t& rejected, Row&& row) {
    if (text.size() < header.size()) {
        if (header.compare(0, text.size(), text) == 0) return 0; // a header cut short
    } else if (text.compare(0, header.size(), header) == 0) {
        std::size_t at = header.size();
        while (at < text.size()) {
            const std::size_t end = text.find('\n', at);
            if (end == std::string::npos) break; // the row being written when the run stopped
            const std::string_view line(text.data() + at, end - at);
            at = end + 1;
            const std::string_view body =
                line.substr(0, line.size() - std::min(line.size(), checksum_size));
            std::size_t m = 0;
            const auto [p, ec] = std::from_chars(body.data(), body.data() + body.size(), m);
            if (line.size() <= checksum_size || checksum_of(body) != line.substr(body.size()) ||
                ec != std::errc() || *p != ',' || m >= members ||
                static_cast<std::size_t>(std::count(body.begin(), body.end(), ',')) + 1 != fields) {
                ++rejected;
                continue;
            }
            row(m, body);
        }
        return text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
    }
    if (text.starts_with(old_header_prefix))
        throw usage_error(name + " was written by an older varsym, without row checksums: "
                                 "finish that ensemble with that version, or remove it to "
                                 "compute its members again");
    throw usage_error(name + " belongs to another ensemble (its first line differs from this "
                             "command's): rerun the command that made it to finish that "
                             "ensemble, or remove it to start this one");
}

} // namespace

ensemble_journal::ensemble_journal(std::string output, const std::string& identity,
                                   std::size_t members, std::size_t fields)
    : output_(std::move(output)), identity_(std::string(header_prefix) + identity + "\n"),
      members_(members), fields_(fields), done_(members, 0) {
    if (identity.find('\n') != std::string::npos)
        throw std::logic_error("an ensemble's identity is one line");
}

void ensemble_journal::read() {
    for (const fs::path& j : journals_of(output_)) {
        const std::string text = read_regular_file(j.string(), max_journal_bytes, "journal");
        if (text.empty()) continue; // a journal just created (or a lock)
        scan(text, identity_, members_, fields_, j.string(), rejected_,
             [&](std::size_t m, std::string_view) {
                 if (done_[m] == 0) ++done_count_;
                 done_[m] = 1;
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
        if (fd_ < 0)
            throw std::runtime_error("cannot open " + path_ + ": " + std::strerror(errno));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            ::close(fd_);
            fd_ = -1;
            throw usage_error(path_ + " is in use by another running ensemble of the same output");
        }
        struct stat held {}, now {};
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
    const std::string text = read_regular_file(path_, max_journal_bytes, "journal");
    std::size_t ignored = 0;
    const std::size_t keep = scan(text, identity_, members_, fields_, path_, ignored,
                                  [](std::size_t, std::string_view) {});
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

std::string ensemble_journal::merged_rows() const {
    std::vector<std::string> texts;
    std::vector<std::string_view> rows(members_);
    const auto journals = journals_of(output_);
    texts.reserve(journals.size());
    for (const fs::path& j : journals) {
        texts.push_back(read_regular_file(j.string(), max_journal_bytes, "journal"));
        if (texts.back().empty()) continue;
        std::size_t ignored = 0;
        scan(texts.back(), identity_, members_, fields_, j.string(), ignored,
             [&](std::size_t m, std::string_view row) {
                 if (rows[m].empty()) rows[m] = row;
             });
    }
    std::size_t bytes = 0;
    for (std::size_t m = 0; m < members_; ++m) {
        if (rows[m].empty())
            throw std::runtime_error("member " + std::to_string(m) +
                                     " has no row in the journals of " + output_);
        bytes += rows[m].size() + 1;
    }
    std::string body;
    body.reserve(bytes);
    for (const auto& r : rows)
        body.append(r).push_back('\n');
    return body;
}

void ensemble_journal::remove_all() {
    for (const fs::path& j : journals_of(output_)) {
        std::error_code ec;
        fs::remove(j, ec);
    }
}

} // namespace varsym::cli
