// models/src/input_file.cpp: the digest of an input file's content (input_file.hpp).
#include "varsym/models/input_file.hpp"

#include <cstdio>

#include <boost/crc.hpp>

namespace varsym::models {

std::string content_digest(std::string_view content) {
    boost::crc_32_type crc;
    crc.process_bytes(content.data(), content.size());
    char buf[64];
    std::snprintf(buf, sizeof buf, "crc32:%08x,bytes:%zu", static_cast<unsigned>(crc.checksum()),
                  content.size());
    return buf;
}

} // namespace varsym::models
