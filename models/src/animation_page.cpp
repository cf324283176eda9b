// models/src/animation_page.cpp: the HTML page of an animation (animation_data.hpp): the page's
// style and controls, three.js, its orbit controls and the mesh loaders the meshes need (inlined
// from Debian's libjs-three), the motion as JSON (numbers as base64 arrays), and the viewer
// script (animation_script.cpp).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "animation_data.hpp"
#include "varsym/version.hpp"

namespace varsym::models::animation_detail {

const char* viewer_script(); // animation_script.cpp
const char* viewer_style();

namespace {

std::string base64(const void* data, std::size_t n) {
    static constexpr char digits[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* p = static_cast<const unsigned char*>(data);
    std::string out;
    out.reserve((n + 2) / 3 * 4);
    for (std::size_t i = 0; i < n; i += 3) {
        const std::uint32_t v = (std::uint32_t{p[i]} << 16) |
                                (i + 1 < n ? std::uint32_t{p[i + 1]} << 8 : 0u) |
                                (i + 2 < n ? std::uint32_t{p[i + 2]} : 0u);
        out += digits[(v >> 18) & 63];
        out += digits[(v >> 12) & 63];
        out += i + 1 < n ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < n ? digits[v & 63] : '=';
    }
    return out;
}

/// A JSON string; '<' escaped so that no "</script>" can end the page's data early.
std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || c == '<' || c == '>' || c == '&') {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            out += buf;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

template <class V>
std::string numbers(const V& v) {
    // Appended piece by piece: GCC 12 sees a false -Wstringop-overflow in "," + number(…).
    std::string out = "[";
    for (int i = 0; i < static_cast<int>(v.size()); ++i) {
        if (i > 0) out += ',';
        out += number(v[static_cast<std::size_t>(i)]);
    }
    out += ']';
    return out;
}

std::string html_text(const std::string& s) {
    std::string out;
    for (const char c : s)
        out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
    return out;
}

/// The script `file`, marked data-varsym="NAME" (its file name's stem).
void inline_script(std::ostream& out, const std::filesystem::path& file) {
    std::ifstream f(file, std::ios::binary);
    if (!f) throw animation_error("cannot read three.js's '" + file.string() + "'");
    out << "<script data-varsym=\"" << file.stem().string() << "\">\n"
        << f.rdbuf() << "\n</script>\n";
}

} // namespace

void write_page(std::ostream& out, const page_data& page, const std::string& three) {
    namespace fs = std::filesystem;
    const fs::path dir(three);
    const fs::path lib = fs::is_regular_file(dir / "three.min.js") ? dir / "three.min.js"
                                                                   : dir / "build" / "three.min.js";
    std::string note; // appended piece by piece: GCC 12 -O2 warns on "…" + std::string
    if (!page.note.empty()) {
        note += "<div id=\"note\">";
        note += html_text(page.note);
        note += "</div>";
    }
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        << "<meta name=\"generator\" content=\"varsym " << VARSYM_VERSION_MAJOR << '.'
        << VARSYM_VERSION_MINOR << '.' << VARSYM_VERSION_PATCH << "\">\n"
        << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        << "<title>" << html_text(page.title) << "</title>\n<style>" << viewer_style()
        << "</style>\n</head>\n<body>\n"
        << "<div id=\"view\"></div>\n"
        << "<div id=\"panel\"><div id=\"title\">" << html_text(page.title) << "</div>" << note
        << "<div id=\"time\"></div><table id=\"joints\"></table></div>\n"
        << "<div id=\"warnings\"></div>\n"
        << "<div id=\"bar\"><button id=\"play\" title=\"play or pause (space)\">pause</button>"
        << "<input id=\"slider\" type=\"range\" min=\"0\" max=\"1000\" step=\"1\" value=\"0\">"
        << "<label>speed <select id=\"speed\"><option>0.1</option><option>0.25</option>"
        << "<option>0.5</option><option selected>1</option><option>2</option><option>4</option>"
        << "</select></label><label><input id=\"loop\" type=\"checkbox\" checked> loop</label>"
        << "<button id=\"home\" title=\"the first view (h)\">view</button></div>\n"
        << "<noscript>This page draws a 3-D animation with JavaScript and WebGL.</noscript>\n";
    inline_script(out, lib);
    inline_script(out, dir / "examples" / "js" / "controls" / "OrbitControls.js");
    bool stl = false, obj = false, dae = false;
    for (const mesh_record& m : page.shapes.meshes) {
        stl = stl || m.format == "stl";
        obj = obj || m.format == "obj";
        dae = dae || m.format == "dae";
    }
    const fs::path loaders = dir / "examples" / "js" / "loaders";
    if (stl) inline_script(out, loaders / "STLLoader.js");
    if (obj) inline_script(out, loaders / "OBJLoader.js");
    if (dae) inline_script(out, loaders / "ColladaLoader.js");

    out << "<script id=\"varsym-motion\" type=\"application/json\">\n{\"title\":"
        << quoted(page.title) << ",\n\"names\":[";
    for (std::size_t i = 0; i < page.names.size(); ++i)
        out << (i ? "," : "") << quoted(page.names[i]);
    out << "],\n\"bodies\":" << page.bodies << ",\n\"frames\":" << page.times.size()
        << ",\n\"centre\":" << numbers(page.centre) << ",\"radius\":" << number(page.radius)
        << ",\"floor\":" << number(page.floor) << ",\n\"warnings\":[";
    for (std::size_t i = 0; i < page.warnings.size(); ++i)
        out << (i ? ",\n" : "") << quoted(page.warnings[i]);
    out << "],\n\"shapes\":[";
    for (std::size_t i = 0; i < page.shapes.shapes.size(); ++i) {
        const shape_record& s = page.shapes.shapes[i];
        const Eigen::Quaterniond u(s.offset.rotation);
        out << (i ? ",\n" : "") << "{\"b\":" << s.page_body << ",\"k\":\"" << s.kind
            << "\",\"s\":" << numbers(s.size) << ",\"p\":" << numbers(s.offset.origin)
            << ",\"r\":" << numbers(Eigen::Vector4d(u.x(), u.y(), u.z(), u.w()))
            << ",\"c\":" << numbers(s.rgba) << ",\"m\":" << s.mesh << "}";
    }
    out << "],\n\"meshes\":[";
    for (std::size_t i = 0; i < page.shapes.meshes.size(); ++i) {
        const mesh_record& m = page.shapes.meshes[i];
        out << (i ? ",\n" : "") << "{\"f\":\"" << m.format << "\",\"d\":\""
            << base64(m.bytes.data(), m.bytes.size()) << "\"}";
    }
    out << "],\n\"obstacles\":[";
    for (std::size_t i = 0; i < page.world.size(); ++i) {
        const contact::obstacle& w = page.world[i];
        out << (i ? "," : "");
        if (w.kind == contact::obstacle::shape::half_space)
            out << "{\"k\":\"plane\",\"n\":" << numbers(w.normal) << ",\"d\":" << number(w.offset)
                << "}";
        else
            out << "{\"k\":\"box\",\"c\":" << numbers(w.centre)
                << ",\"s\":" << numbers(Eigen::Vector3d(2 * w.half)) << "}";
    }
    out << "],\n\"touch\":\"" << base64(page.touch.data(), page.touch.size() * sizeof(float))
        << "\",\n\"touches\":\""
        << base64(page.touches.data(), page.touches.size() * sizeof(std::uint32_t))
        << "\",\n\"arrowScale\":" << number(page.arrow_scale) << ",\n\"arrows\":\""
        << base64(page.arrows.data(), page.arrows.size() * sizeof(float))
        << "\",\n\"arrowCounts\":\""
        << base64(page.arrow_counts.data(), page.arrow_counts.size() * sizeof(std::uint32_t));
    out << "\",\n\"t\":\"" << base64(page.times.data(), page.times.size() * sizeof(double))
        << "\",\n\"poses\":\"" << base64(page.poses.data(), page.poses.size() * sizeof(float))
        << "\",\n\"q\":\"" << base64(page.values.data(), page.values.size() * sizeof(float))
        << "\"}\n</script>\n<script>\n"
        << viewer_script() << "\n</script>\n</body>\n</html>\n";
}

} // namespace varsym::models::animation_detail
