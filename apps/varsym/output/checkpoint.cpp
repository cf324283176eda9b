// apps/varsym/output/checkpoint.cpp: checkpoint files: the models layer's format
// (models::checkpoint_text, parse_checkpoint) through the tool's file safety.
#include "output/checkpoint.hpp"

#include <cstdio>

#include "options/cli_common.hpp"
#include "output/files.hpp"

namespace varsym::cli {

void write_checkpoint(const std::string& path, const checkpoint& ck, bool replace) {
    write_exclusively(path, models::checkpoint_text(ck), replace, "checkpoint");
}

bool looks_like_checkpoint(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) return false;
    std::string head(64, '\0');
    head.resize(std::fread(head.data(), 1, head.size(), f));
    std::fclose(f);
    return models::looks_like_checkpoint_start(head);
}

checkpoint read_checkpoint(const std::string& path) {
    const std::string text = read_regular_file(path, max_checkpoint_bytes, "checkpoint");
    try {
        return models::parse_checkpoint(text, path);
    } catch (const models::checkpoint_error& e) {
        throw usage_error(e.what());
    }
}

} // namespace varsym::cli
