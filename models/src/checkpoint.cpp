// models/src/checkpoint.cpp: the checkpoint format (varsym/models/checkpoint.hpp): text, one
// "key value" line each, doubles as C99 hexadecimal floats (exact), a CRC-32 of everything
// before the last line.
#include "varsym/models/checkpoint.hpp"

#include <charconv>
#include <cstdio>
#include <map>
#include <sstream>

#include <boost/crc.hpp>

namespace varsym::models {

namespace {

constexpr const char* magic = "varsym-checkpoint 2";

std::string hex(double v) {
    char buf[40];
    auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::hex);
    return std::string(buf, end);
}

std::string crc_of(const std::string& body) {
    boost::crc_32_type crc;
    crc.process_bytes(body.data(), body.size());
    char buf[16];
    std::snprintf(buf, sizeof buf, "%08x", static_cast<unsigned>(crc.checksum()));
    return buf;
}

/// Arguments may hold any byte but a newline ends a line: escape '\' and '\n'.
std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '\\')
            out += "\\\\";
        else if (c == '\n')
            out += "\\n";
        else
            out += c;
    }
    return out;
}

std::string unescape(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '\\' && i + 1 < s.size()) {
            out += s[i + 1] == 'n' ? '\n' : s[i + 1];
            ++i;
        } else {
            out += s[i];
        }
    }
    return out;
}

void put_vector(std::string& body, const char* key, const std::vector<double>& v) {
    body += key;
    for (double x : v)
        body += ' ' + hex(x);
    body += '\n';
}

/// Reads "key value…" lines after the checksum was verified.
class fields {
  public:
    fields(const std::string& name, const std::string& body) : name_(name) {
        std::istringstream in(body);
        std::string line;
        while (std::getline(in, line)) {
            const auto space = line.find(' ');
            const std::string key = line.substr(0, space);
            const std::string value = space == std::string::npos ? "" : line.substr(space + 1);
            if (key == "arg")
                args.push_back(unescape(value));
            else if (key == "input")
                inputs.push_back(value);
            else
                map_[key] = value;
        }
    }
    std::vector<std::string> args;
    std::vector<std::string> inputs; ///< "DIGEST PATH" lines

    [[nodiscard]] bool has(const std::string& key) const { return map_.count(key) != 0; }
    [[nodiscard]] const std::string& text(const std::string& key) const {
        const auto it = map_.find(key);
        if (it == map_.end()) damaged("no '" + key + "' line");
        return it->second;
    }
    template <class Int>
    Int integer(const std::string& key) const {
        const std::string& s = text(key);
        Int v{};
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec != std::errc() || end != s.data() + s.size()) damaged("bad '" + key + "' value");
        return v;
    }
    [[nodiscard]] std::vector<double> numbers(const std::string& key) const {
        std::vector<double> out;
        std::istringstream in(text(key));
        std::string word;
        while (in >> word) {
            double v = 0.0;
            auto [end, ec] =
                std::from_chars(word.data(), word.data() + word.size(), v, std::chars_format::hex);
            if (ec != std::errc() || end != word.data() + word.size())
                damaged("bad '" + key + "' value");
            out.push_back(v);
        }
        return out;
    }
    [[noreturn]] void damaged(const std::string& what) const {
        throw checkpoint_error("checkpoint '" + name_ + "' is damaged (" + what + ")");
    }

  private:
    std::string name_;
    std::map<std::string, std::string> map_;
};

std::vector<double> list(const vec<dynamic>& v) {
    return {v.data(), v.data() + v.size()};
}

} // namespace

run_state<dynamic> checkpoint::state() const {
    auto as_vec = [](const std::vector<double>& v) {
        return vec<dynamic>(Eigen::Map<const vec<dynamic>>(v.data(), std::ssize(v)));
    };
    run_state<dynamic> r;
    r.x = phase_state<dynamic>{as_vec(q), as_vec(p)};
    r.carry_q = as_vec(carry_q);
    r.carry_p = as_vec(carry_p);
    r.history = history;
    r.step = step;
    r.stats.steps = step;
    r.stats.newton_iterations = newton_iterations;
    r.stats.newton_iterations_max = newton_iterations_max;
    return r;
}

void checkpoint::set_state(const run_state<dynamic>& r) {
    q = list(r.x.q);
    p = list(r.x.p);
    carry_q = list(r.carry_q);
    carry_p = list(r.carry_p);
    history = r.history;
    step = r.step;
    newton_iterations = r.stats.newton_iterations;
    newton_iterations_max = r.stats.newton_iterations_max;
}

std::string checkpoint_text(const checkpoint& ck) {
    std::string body = std::string(magic) + "\nversion " + ck.version + "\n";
    for (const std::string& a : ck.args)
        body += "arg " + escape(a) + '\n';
    for (const checkpoint::input_file& in : ck.inputs)
        body += "input " + in.digest + ' ' + escape(in.path) + '\n';
    body += "output " + escape(ck.output) + '\n';
    body += "scheme " + ck.scheme + '\n';
    body += "steps " + std::to_string(ck.steps) + '\n';
    body += "step " + std::to_string(ck.step) + '\n';
    body += "h " + hex(ck.h) + '\n';
    body += "csv_bytes " + std::to_string(ck.csv_bytes) + '\n';
    body += "csv_crc32 " + std::to_string(ck.csv_crc32) + '\n';
    put_vector(body, "q", ck.q);
    put_vector(body, "p", ck.p);
    put_vector(body, "carry_q", ck.carry_q);
    put_vector(body, "carry_p", ck.carry_p);
    put_vector(body, "history", ck.history);
    body += "newton_iterations " + std::to_string(ck.newton_iterations) + '\n';
    body += "newton_iterations_max " + std::to_string(ck.newton_iterations_max) + '\n';
    body += "crc32 " + crc_of(body) + '\n';
    return body;
}

bool looks_like_checkpoint_start(const std::string& head) {
    const std::string m = magic;
    return m.starts_with(head.substr(0, m.size())); // a write killed early leaves a prefix
}

checkpoint parse_checkpoint(const std::string& text, const std::string& name) {
    if (text.rfind(std::string(magic) + "\n", 0) != 0)
        throw checkpoint_error("'" + name + "' is not a varsym checkpoint");
    // The version first: a file of another version gets that message, not a checksum error.
    const std::string version_key = std::string(magic) + "\nversion ";
    const auto vend = text.find('\n', version_key.size());
    const std::string version = text.rfind(version_key, 0) == 0 && vend != std::string::npos
                                    ? text.substr(version_key.size(), vend - version_key.size())
                                    : std::string();
    if (version != checkpoint_version)
        throw checkpoint_error("checkpoint '" + name + "' was written by varsym " +
                               (version.empty() ? std::string("of an unknown version") : version) +
                               ", this is varsym " + checkpoint_version +
                               "; resume it with that version");
    const auto crc_at = text.rfind("crc32 ");
    if (crc_at == std::string::npos || text.back() != '\n' || text.size() - crc_at != 15)
        throw checkpoint_error("checkpoint '" + name +
                               "' is damaged (no checksum at its end; truncated?)");
    const std::string body = text.substr(0, crc_at);
    if (text.substr(crc_at + 6, 8) != crc_of(body))
        throw checkpoint_error("checkpoint '" + name + "' is damaged (CRC-32 checksum mismatch)");

    const fields f(name, body);
    checkpoint ck;
    ck.version = version;
    ck.args = f.args;
    for (const std::string& line : f.inputs) {
        const auto space = line.find(' ');
        if (space == std::string::npos || space == 0 || space + 1 == line.size())
            f.damaged("bad 'input' line");
        ck.inputs.push_back({unescape(line.substr(space + 1)), line.substr(0, space)});
    }
    ck.output = unescape(f.text("output"));
    ck.scheme = f.text("scheme");
    ck.steps = f.integer<std::uint64_t>("steps");
    ck.step = f.integer<std::uint64_t>("step");
    const std::vector<double> h = f.numbers("h");
    ck.csv_bytes = f.integer<std::uint64_t>("csv_bytes");
    ck.csv_crc32 = f.integer<std::uint32_t>("csv_crc32");
    ck.q = f.numbers("q");
    ck.p = f.numbers("p");
    ck.carry_q = f.numbers("carry_q");
    ck.carry_p = f.numbers("carry_p");
    if (f.has("history")) ck.history = f.numbers("history"); // absent: written before it was kept
    ck.newton_iterations = f.integer<std::int64_t>("newton_iterations");
    ck.newton_iterations_max = f.integer<int>("newton_iterations_max");
    if (h.size() != 1 || ck.q.empty() || ck.p.empty() || ck.carry_q.size() != ck.q.size() ||
        ck.carry_p.size() != ck.p.size() || ck.step > ck.steps)
        f.damaged("inconsistent sizes");
    ck.h = h[0];
    return ck;
}

} // namespace varsym::models
