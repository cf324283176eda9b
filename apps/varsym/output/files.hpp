// apps/varsym/output/files.hpp: every file the tool writes or reads goes through here. Regular
// files are replaced atomically (FILE.part, renamed); FIFOs, devices and links to them are written
// through; partial files are created exclusively and locked for the whole run; reads are bounded
// by what a valid file can be; the files of one command are checked against each other before
// anything is written.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <boost/crc.hpp>

namespace varsym::cli {

/// How a path is written: absent or a regular file (atomically through PATH.part), a directory
/// (refused), or anything else (a FIFO, a character or block device, a socket, /dev/stdout):
/// written through in place, never renamed over.
enum class file_kind { absent, regular, directory, special };
[[nodiscard]] file_kind kind_of(const std::string& path);

/// The whole content of a regular file, refusing anything else (a directory, a FIFO, a device)
/// and a file longer than max_bytes, with one line naming `role` ("checkpoint", "config file").
/// Throws usage_error.
[[nodiscard]] std::string read_regular_file(const std::string& path, std::uint64_t max_bytes,
                                            const std::string& role);

/// The files one command will touch, each with its role; check() refuses two roles naming the
/// same file (same path after resolving links, dangling ones included, and "..", or the same
/// inode), naming both roles. A terminal or /dev/null (character devices) may take any number
/// of roles: nothing written there is lost by another role's write.
class file_roles {
  public:
    /// A file the command reads or writes; "" and "-" (none given) are skipped.
    void add(std::string role, const std::string& path);
    /// Where the command writes its main output: "" and "-" mean standard output, which is
    /// then a role too (`--controls /dev/stdout`, or a file that standard output is redirected
    /// to, is then the same file).
    void add_output(std::string role, const std::string& path);
    void check() const;

  private:
    struct entry {
        std::string role, path;
    };
    std::vector<entry> entries_;
};

/// Before any work on FILE: its partial file FILE.part, if there is one, is removed where it
/// is `ours` (the interrupted final write of this very command, say an ensemble whose journals
/// are this one's) and no run holds it; else it is refused as output_file would refuse it.
void claim_partial(const std::string& file, bool ours);

/// An output destination: standard output for "" or "-"; a FIFO, device or other special file
/// written through; else FILE written as FILE.part and renamed to FILE by commit().
///
/// FILE.part is created exclusively (an existing one is never truncated: it is another run's,
/// or the rows of a stopped run) and locked (flock) until the object dies, so a second run
/// writing the same FILE is refused. Without commit() FILE.part is removed, unless keep_partial()
/// was called (a run that failed mid-way keeps its rows for inspection or resume).
/// An existing FILE is untouched until commit().
class output_file {
  public:
    explicit output_file(const std::string& path);
    /// Continues FILE.part of an interrupted run: locks it, checks that its first `keep` bytes
    /// are the ones the checkpoint saw (CRC-32 `crc`), truncates it there and appends. Refuses
    /// a missing, locked, shorter or different file with one line naming it.
    output_file(const std::string& path, std::uint64_t keep, std::uint32_t crc);
    output_file(const output_file&) = delete;
    output_file& operator=(const output_file&) = delete;
    ~output_file();

    [[nodiscard]] bool is_stdout() const { return path_.empty(); }
    /// Written in place (standard output or a special file): no FILE.part, no rename, no resume.
    [[nodiscard]] bool is_through() const { return through_; }
    [[nodiscard]] std::string partial_path() const { return path_.string() + ".part"; }
    void write(const std::string& s);
    /// Bytes written so far (for a resumed file, counting the kept ones) and their CRC-32.
    [[nodiscard]] std::uint64_t bytes() const { return bytes_; }
    [[nodiscard]] std::uint32_t crc() const { return crc_.checksum(); }
    /// Flushes and fsyncs what was written (before a checkpoint that counts these bytes).
    void sync();
    void commit();
    void keep_partial();

  private:
    [[noreturn]] void fail_write(int err) const;
    std::filesystem::path path_;
    std::FILE* f_ = nullptr;
    bool through_ = false;
    bool committed_ = false;
    bool keep_ = false;
    std::uint64_t bytes_ = 0;
    boost::crc_32_type crc_;
};

/// fsyncs the directory holding `file` (best effort), so that a rename in it is durable.
void fsync_directory(const std::filesystem::path& file);

/// Writes body to `path` atomically through PATH.tmp, which must not exist (it is created
/// exclusively, fsync'ed, then renamed over path if `replace`, else linked to path, which must
/// not exist either). A crash at any instant leaves the old file or the new one. Throws
/// std::runtime_error naming `role` on any failure, removing PATH.tmp.
void write_exclusively(const std::string& path, const std::string& body, bool replace,
                       const std::string& role);

} // namespace varsym::cli
