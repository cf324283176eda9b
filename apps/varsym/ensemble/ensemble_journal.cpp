// apps/varsym/ensemble/ensemble_journal.cpp: reading, continuing and merging the journals of an ensemble.
#include "ensemble_journal.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

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

/// Calls row(member, line with its '\n') for each complete row of a journal's text after its
/// header; returns the length of the valid prefix (header and complete rows).
template <class Row>
std::size_t scan(const std::string& text, const std::string& header, std::size_t members,
                 std::size_t fields, const std::string& name, Row&& row) {
    if (text.size() < header.size()) {
        if (header.compare(0, text.size(), text) == 0) return 0; // a header cut short
    } else if (text.compare(0, header.size(), header) == 0) {
        std::size_t at = header.size();
        while (at < text.size()) {
            const std::size_t end = text.find('\n', at);
            if (end == std::string::npos) break; // the row being written when the run stopped
            const std::string_view line(text.data() + at, end - at);
            std::size_t m = 0;
            const auto [p, ec] = std::from_chars(line.data(), line.data() + line.size(), m);
            if (ec != std::errc() || *p != ',' || m >= members ||
                static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1 != fields)
                break;
            row(m, std::string_view(text.data() + at, end + 1 - at));
            at = end + 1;
        }
        return at;
    }
    throw usage_error(name + " belongs to another ensemble (its first line differs from this "
                             "command's): rerun the command that made it to finish that "
                             "ensemble, or remove it to start this one");
}

} // namespace

ensemble_journal::ensemble_journal(const std::string& output, const std::string& identity,
                                   std::size_t members, std::size_t fields)
    : output_(output), identity_("# varsym ensemble: " + identity + "\n"), members_(members),
      fields_(fields), done_(members, 0) {
    if (identity.find('\n') != std::string::npos)
        throw std::logic_error("an ensemble's identity is one line");
    for (const fs::path& j : journals_of(output)) {
        const std::string text = read_regular_file(j.string(), max_journal_bytes, "journal");
        scan(text, identity_, members_, fields_, j.string(), [&](std::size_t m, std::string_view) {
            if (done_[m] == 0) ++done_count_;
            done_[m] = 1;
        });
    }
}

ensemble_journal::~ensemble_journal() {
    if (fd_ >= 0) ::close(fd_); // releases the lock
}

void ensemble_journal::open(const std::string& suffix) {
    path_ = output_ + suffix;
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error("cannot open " + path_ + ": " + std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0)
        throw usage_error(path_ + " is in use by another running ensemble of the same output");
    const std::string text = read_regular_file(path_, max_journal_bytes, "journal");
    const std::size_t keep =
        scan(text, identity_, members_, fields_, path_, [](std::size_t, std::string_view) {});
    if (::ftruncate(fd_, static_cast<off_t>(keep)) != 0 ||
        ::lseek(fd_, static_cast<off_t>(keep), SEEK_SET) < 0)
        throw std::runtime_error("cannot cut " + path_ + ": " + std::strerror(errno));
    if (keep == 0) append(identity_);
}

void ensemble_journal::append(const std::string& rows) {
    std::size_t at = 0;
    while (at < rows.size()) {
        const ssize_t n = ::write(fd_, rows.data() + at, rows.size() - at);
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
        scan(texts.back(), identity_, members_, fields_, j.string(),
             [&](std::size_t m, std::string_view line) {
                 if (rows[m].empty()) rows[m] = line;
             });
    }
    std::size_t bytes = 0;
    for (std::size_t m = 0; m < members_; ++m) {
        if (rows[m].empty())
            throw std::runtime_error("member " + std::to_string(m) +
                                     " has no row in the journals of " + output_);
        bytes += rows[m].size();
    }
    std::string body;
    body.reserve(bytes);
    for (const auto& r : rows)
        body += r;
    return body;
}

void ensemble_journal::remove_all() {
    for (const fs::path& j : journals_of(output_)) {
        std::error_code ec;
        fs::remove(j, ec);
    }
}

} // namespace varsym::cli
