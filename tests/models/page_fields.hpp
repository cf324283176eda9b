// tests/models/page_fields.hpp: reading an animation page back (models/animation.hpp): the
// file's text, and a JSON field's base64 data decoded.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace varsym::test {

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

/// The base64 text of JSON field `key` decoded.
inline std::vector<unsigned char> field(const std::string& page, const std::string& key) {
    const auto at = page.find("\"" + key + "\":\"");
    EXPECT_NE(at, std::string::npos) << key;
    const auto from = at + key.size() + 4, to = page.find('"', from);
    std::vector<unsigned char> out;
    unsigned v = 0;
    int bits = 0;
    for (std::size_t i = from; i < to; ++i) {
        const char c = page[i];
        if (c == '=') break;
        const auto d = static_cast<unsigned>(
            std::string("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/")
                .find(c));
        v = (v << 6) | d;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<unsigned char>((v >> bits) & 0xff));
        }
    }
    return out;
}

/// The page's float32 field `key` (poses, q) as numbers.
inline std::vector<float> floats(const std::string& page, const std::string& key) {
    const std::vector<unsigned char> raw = field(page, key);
    std::vector<float> out(raw.size() / sizeof(float));
    std::memcpy(out.data(), raw.data(), out.size() * sizeof(float));
    return out;
}

} // namespace varsym::test
