// varsym/run/input_file.hpp: the files varsym reads (a URDF, an IPOPT options file, a config, a
// checkpoint): regular files only, bounded in size, so that a directory, a FIFO or a device given
// by mistake is refused at once with one line, instead of hanging or reading without end.
#pragma once

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace varsym {

/// An input that cannot be read: missing, unreadable, not a regular file (a directory, a FIFO,
/// a device) or longer than its bound. The message names the role and the file.
class input_error : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

/// The whole content of the regular file `path`, refusing anything else and a file longer than
/// max_bytes, with one line naming `role` ("URDF file", "config file"). A FIFO is never waited
/// on (it is opened without blocking, then refused) and a device is never read. Throws
/// input_error.
inline std::string read_input_file(const std::string& path, std::uint64_t max_bytes,
                                   const std::string& role) {
    if (path.empty()) throw input_error("the " + role + " name is empty");
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        throw input_error("cannot read " + role + " '" + path + "': " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const bool dir = S_ISDIR(st.st_mode);
        ::close(fd);
        throw input_error("cannot read " + role + " '" + path + "': " +
                          (dir ? "it is a directory" : "not a regular file (a FIFO or a device)"));
    }
    if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
        ::close(fd);
        throw input_error("cannot read " + role + " '" + path + "': " + std::to_string(st.st_size) +
                          " bytes, more than a valid " + role + " can be (" +
                          std::to_string(max_bytes) + ")");
    }
    std::string text(static_cast<std::size_t>(st.st_size), '\0');
    std::size_t got = 0;
    while (got < text.size()) {
        const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int err = errno;
            ::close(fd);
            throw input_error("cannot read " + role + " '" + path + "': " + std::strerror(err));
        }
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    ::close(fd);
    text.resize(got); // a file that shrank while read: its parser reports what is missing
    return text;
}

} // namespace varsym
