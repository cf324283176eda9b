// models/src/urdf_reader.hpp: the two phases of the URDF reader and what passes between them.
// The read phase (urdf.cpp, read_urdf) checks the XML and gives a robot_data: links with their
// mass properties, joints with their kind, links, origin, axis, limits and mimic coupling. The
// build phase (urdf_build.cpp, build_tree) makes the multibody::tree of it. Below them, the
// checked reading of one element at a time: names, numbers, origins, axes and <inertial>. Every
// refusal names the file, the element's line and what is wrong (urdf_error); what is refused and
// why: docs/robots.md.
#pragma once

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <tinyxml2.h>

#include "varsym/models/robot.hpp"

namespace varsym::models::urdf_detail {

using multibody::mat3;
using multibody::mat6;
using multibody::vec3;
using tinyxml2::XMLElement;

/// A link as read: its element (for messages) and its mass properties.
struct link_data {
    const XMLElement* element = nullptr;
    bool has_inertial = false;
    mat6 inertia = mat6::Zero(); ///< spatial inertia in the link frame
};

/// A moving joint's <mimic> as read: θ = multiplier · q_master + offset.
struct mimic_data {
    const XMLElement* element = nullptr; ///< its <mimic>; null: the joint does not mimic
    std::size_t master = 0;              ///< the joint it follows (in robot_data::joints)
    double multiplier = 1.0;
    double offset = 0.0;
};

/// A joint as read: its element (for messages), name, type and links. Of a joint reached from
/// the root, its origin; of a moving one (type revolute, continuous or prismatic), its kind,
/// unit axis, limits and damping, and its mimic coupling (a fixed joint's <mimic> is ignored).
struct joint_data {
    const XMLElement* element = nullptr;
    std::string name, type, parent, child;
    multibody::pose origin; ///< the child link's frame in the parent link's
    multibody::joint_kind kind = multibody::joint_kind::revolute;
    vec3 axis = vec3::UnitX();
    multibody::joint_limits limits;
    mimic_data mimic;

    [[nodiscard]] bool moves() const { return type != "fixed"; }
};

/// A URDF robot as read and checked: one tree of links from `root`, every link reached, at
/// least one moving joint; the mimic couplings follow moving joints that do not mimic, and no
/// joint that does not mimic moves below one that does. Its elements point into the document
/// it was read from.
struct robot_data {
    const XMLElement* robot = nullptr; ///< the <robot> element
    std::string name;
    std::map<std::string, link_data> links;
    std::string root;               ///< the root link
    std::vector<joint_data> joints; ///< in file order
    /// The joints reached from the root, depth first, children in file order.
    std::vector<std::size_t> order;
};

/// `s` with control characters written as \xNN, for messages.
inline std::string printable(const std::string& s) {
    std::string out;
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x20 || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(c));
            out += buf;
        } else {
            out += ch;
        }
    }
    return out;
}

/// Reads one element at a time, checked; fail() throws urdf_error naming the source (a file or
/// "<urdf>"), the element and its line.
class reader {
  public:
    explicit reader(std::string source) : source_(std::move(source)) {}

    [[nodiscard]] const std::string& source() const { return source_; }

    [[noreturn]] void fail(const XMLElement* e, const std::string& what) const {
        std::string where = source_;
        if (e) where += ":" + std::to_string(e->GetLineNum()) + ": <" + e->Name() + ">";
        throw urdf_error(where + ": " + what);
    }

    std::string attribute(const XMLElement* e, const char* name, bool required = true) const {
        const char* v = e->Attribute(name);
        if (!v && required) fail(e, std::string("missing attribute '") + name + "'");
        return v ? v : "";
    }

    /// The name of a link or joint (`what`), checked: joint names become CSV columns (q_NAME)
    /// and keys (q0_NAME), link names frames, and both are listed with ", " between them. So a
    /// name is not empty, has no comma, double quote or control character (a newline, a tab),
    /// and does not begin or end with a space.
    std::string name(const XMLElement* e, const char* what) const {
        const std::string n = attribute(e, "name");
        const std::string quoted = std::string(what) + " name \"" + printable(n) + "\"";
        if (n.empty()) fail(e, std::string("a ") + what + " with an empty name");
        for (const char ch : n) {
            const auto c = static_cast<unsigned char>(ch);
            if (c < 0x20 || c == 0x7f)
                fail(e, quoted + " has a control character (names become CSV columns: give "
                                 "one without newlines or tabs)");
            if (c == ',' || c == '"')
                fail(e, quoted + " has a '" + ch +
                            "' (names become CSV columns and keys: give one without , and \")");
        }
        if (n.front() == ' ' || n.back() == ' ') fail(e, quoted + " begins or ends with a space");
        return n;
    }

    /// `count` numbers of attribute `name` (absent: `fallback`).
    Eigen::VectorXd numbers(const XMLElement* e, const char* name, int count,
                            const Eigen::VectorXd& fallback) const {
        const char* v = e ? e->Attribute(name) : nullptr;
        if (!v) return fallback;
        Eigen::VectorXd out(count);
        const std::string text(v);
        const char* p = text.data();
        const char* end = p + text.size();
        for (int i = 0; i < count; ++i) {
            while (p < end && std::isspace(static_cast<unsigned char>(*p)))
                ++p;
            const auto r = std::from_chars(p + (p < end && *p == '+' ? 1 : 0), end, out(i));
            if (r.ec != std::errc() || !std::isfinite(out(i)))
                fail(e, std::string("attribute ") + name + "=\"" + text + "\" needs " +
                            std::to_string(count) + " finite number" + (count > 1 ? "s" : ""));
            p = r.ptr;
        }
        while (p < end && std::isspace(static_cast<unsigned char>(*p)))
            ++p;
        if (p != end)
            fail(e, std::string("attribute ") + name + "=\"" + text + "\" has more than " +
                        std::to_string(count) + " number" + (count > 1 ? "s" : ""));
        return out;
    }
    double number(const XMLElement* e, const char* name, double fallback) const {
        return numbers(e, name, 1, Eigen::VectorXd::Constant(1, fallback))(0);
    }

    /// <origin xyz rpy> of element e (absent: the identity).
    multibody::pose origin(const XMLElement* e) const {
        const XMLElement* o = e->FirstChildElement("origin");
        const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
        return {multibody::roll_pitch_yaw(numbers(o, "rpy", 3, zero)), numbers(o, "xyz", 3, zero)};
    }

    /// A joint's <axis xyz> (absent: x) as a unit vector: a / |a| for any a ≠ 0, computed as
    /// b / |b| with b = a / max|a_i| so that no square overflows or underflows (1e200 0 0 and
    /// 0 2 0 are both normalised).
    vec3 axis(const XMLElement* joint, const std::string& joint_name) const {
        const XMLElement* e = joint->FirstChildElement("axis");
        const vec3 a = numbers(e, "xyz", 3, vec3::UnitX());
        const double largest = a.cwiseAbs().maxCoeff();
        if (!(largest > 0.0)) fail(e, "joint " + joint_name + ": zero axis");
        const vec3 b = a / largest;
        return b / b.norm();
    }

    /// A link's <inertial> as a spatial inertia in the link frame, checked: mass ≥ 0, the
    /// inertia tensor symmetric positive definite (or all zero with zero mass), its principal
    /// moments meeting the triangle inequality, and the spatial inertia (whose entries hold
    /// m c_i c_j) finite.
    void inertial(link_data& l, const std::string& name) const {
        const XMLElement* in = l.element->FirstChildElement("inertial");
        if (!in) return;
        l.has_inertial = true;
        const XMLElement* mass = in->FirstChildElement("mass");
        if (!mass) fail(in, "link " + name + ": <inertial> without <mass>");
        const double m = number(mass, "value", std::nan(""));
        if (std::isnan(m)) fail(mass, "link " + name + ": <mass> without value");
        if (m < 0.0) fail(mass, "link " + name + ": negative mass " + std::to_string(m));
        const XMLElement* t = in->FirstChildElement("inertia");
        mat3 ic = mat3::Zero();
        if (t) {
            auto at = [&](const char* k) { return number(t, k, 0.0); };
            ic << at("ixx"), at("ixy"), at("ixz"), at("ixy"), at("iyy"), at("iyz"), at("ixz"),
                at("iyz"), at("izz");
        }
        const multibody::pose o = origin(in);
        if (m > 0.0 || !ic.isZero(0.0)) check_inertia(t ? t : in, name, m, ic);
        // In the link frame: I_c rotated from the inertial frame, the centre at the origin.
        l.inertia =
            multibody::spatial_inertia(m, o.origin, o.rotation * ic * o.rotation.transpose());
        if (!l.inertia.allFinite())
            fail(in, "link " + name +
                         ": its mass properties overflow a double (the mass, its "
                         "moments or m c c at its <origin> exceed 1.8e308)");
    }

    /// A link's <collision> shapes in its frame. Read leniently: a shape the reader cannot take
    /// (no shape, an unknown one, a size that is not positive and finite) is kept with its
    /// `problem` (file, line, what), which contact refuses (contact/geometry.hpp); without
    /// contact, collisions are not used.
    std::vector<multibody::collision_shape> collisions(const XMLElement* link,
                                                       const std::string& name) const {
        std::vector<multibody::collision_shape> out;
        for (const XMLElement* c = link->FirstChildElement("collision"); c;
             c = c->NextSiblingElement("collision")) {
            multibody::collision_shape s;
            s.link = name;
            try {
                read_shape(c, name, s);
            } catch (const urdf_error& e) {
                s.problem = e.what();
            }
            out.push_back(std::move(s));
        }
        return out;
    }
    /// A link's <visual> shapes in its frame, read as leniently, with their colours: a
    /// <material> with its own <color rgba>, or one named at the top of the file (`named`).
    std::vector<multibody::visual_shape>
    visuals(const XMLElement* link, const std::string& name,
            const std::map<std::string, std::array<double, 4>>& named) const {
        std::vector<multibody::visual_shape> out;
        for (const XMLElement* c = link->FirstChildElement("visual"); c;
             c = c->NextSiblingElement("visual")) {
            multibody::visual_shape s;
            s.link = name;
            try {
                read_shape(c, name, s);
                if (const XMLElement* m = c->FirstChildElement("material")) {
                    const auto it = named.find(attribute(m, "name", false));
                    if (const auto rgba = colour(m))
                        s.rgba = *rgba;
                    else if (it != named.end())
                        s.rgba = it->second;
                }
            } catch (const urdf_error& e) {
                s.problem = e.what();
            }
            out.push_back(std::move(s));
        }
        return out;
    }
    /// The colours of the materials named under <robot>.
    std::map<std::string, std::array<double, 4>> materials(const XMLElement* robot) const {
        std::map<std::string, std::array<double, 4>> out;
        for (const XMLElement* m = robot->FirstChildElement("material"); m;
             m = m->NextSiblingElement("material"))
            if (const auto rgba = colour(m)) out[attribute(m, "name", false)] = *rgba;
        return out;
    }
    /// A <material>'s <color rgba="r g b a">, each clamped to [0, 1]; none without one.
    std::optional<std::array<double, 4>> colour(const XMLElement* m) const {
        const XMLElement* c = m->FirstChildElement("color");
        if (!c || !c->Attribute("rgba")) return std::nullopt;
        try { // a colour that cannot be read is no colour: drawn only
            const Eigen::VectorXd v = numbers(c, "rgba", 4, Eigen::VectorXd::Constant(4, 1.0));
            std::array<double, 4> out{};
            for (int i = 0; i < 4; ++i)
                out[static_cast<std::size_t>(i)] =
                    std::isfinite(v(i)) ? std::clamp(v(i), 0.0, 1.0) : 1.0;
            return out;
        } catch (const urdf_error&) {
            return std::nullopt;
        }
    }
    void read_shape(const XMLElement* c, const std::string& name,
                    multibody::collision_shape& s) const {
        const XMLElement* g = c->FirstChildElement("geometry");
        const XMLElement* e = g ? g->FirstChildElement() : nullptr;
        if (!e)
            fail(g ? g : c,
                 "link " + name + ": a <" + c->Name() + "> without a shape in <geometry>");
        s.offset = origin(c);
        const std::string kind = e->Name();
        auto positive = [&](const char* attr) {
            const double v = number(e, attr, std::nan(""));
            if (!(v > 0.0)) fail(e, "link " + name + ": <" + kind + "> needs a positive " + attr);
            return v;
        };
        if (kind == "sphere") {
            s.size(0) = positive("radius");
        } else if (kind == "box") {
            s.kind = multibody::shape_kind::box;
            s.size = numbers(e, "size", 3, vec3::Constant(std::nan("")));
            if (!(s.size.minCoeff() > 0.0))
                fail(e, "link " + name + ": <box> needs size=\"x y z\" with positive sides");
        } else if (kind == "cylinder" || kind == "capsule") {
            s.kind = kind == "capsule" ? multibody::shape_kind::capsule
                                       : multibody::shape_kind::cylinder;
            s.size(0) = positive("radius");
            s.size(1) = positive("length");
        } else if (kind == "mesh") {
            s.kind = multibody::shape_kind::mesh;
            s.mesh = attribute(e, "filename", false);
            s.size = numbers(e, "scale", 3, vec3::Ones()); // drawn only: its scale
        } else {
            fail(e, "link " + name + ": unknown collision shape <" + kind +
                        "> (sphere, box, cylinder, capsule or mesh)");
        }
    }

    void check_inertia(const XMLElement* e, const std::string& name, double m,
                       const mat3& ic) const {
        if (!(m > 0.0)) fail(e, "link " + name + ": an inertia tensor without mass");
        // Scaled to its largest entry first, so that no product inside the solver overflows.
        const double largest = ic.cwiseAbs().maxCoeff();
        const double scale = largest > 0.0 ? largest : 1.0;
        const Eigen::SelfAdjointEigenSolver<mat3> es(ic / scale, Eigen::EigenvaluesOnly);
        const vec3 k = scale * es.eigenvalues(); // ascending
        char buf[256];
        if (!(k(0) > 0.0)) {
            std::snprintf(buf, sizeof buf,
                          "link %s: the inertia tensor is not positive definite (principal "
                          "moments %.6g, %.6g, %.6g kg m^2)",
                          name.c_str(), k(0), k(1), k(2));
            fail(e, buf);
        }
        // A rigid body's moments satisfy I_3 <= I_1 + I_2 (equality: a flat body); printed
        // digits may round a flat body's over it by a few parts in a million. Halved, so that
        // the sum does not overflow.
        const double excess = k(2) / 2 - (k(0) / 2 + k(1) / 2);
        if (excess > 0.5e-6 * k(2)) {
            std::snprintf(buf, sizeof buf,
                          "link %s: principal moments %.6g, %.6g, %.6g kg m^2 break the triangle "
                          "inequality (the largest exceeds the sum of the others by %.3g, %.2g %%)",
                          name.c_str(), k(0), k(1), k(2), 2 * excess, 200.0 * excess / k(2));
            fail(e, buf);
        }
    }

  private:
    std::string source_;
};

/// The mass, centre and rotational inertia about the centre of a spatial inertia.
inline void unpack(const mat6& i, multibody::body& b) {
    b.mass = i(5, 5);
    if (b.mass <= 0.0) return;
    const mat3 mcx = i.topRightCorner<3, 3>(); // m c×
    b.com = vec3(mcx(2, 1), mcx(0, 2), mcx(1, 0)) / b.mass;
    const mat3 cx = multibody::skew(b.com);
    b.inertia = i.topLeftCorner<3, 3>() - b.mass * cx * cx.transpose();
}

/// The spatial inertia `i` given in a frame at pose `x` of another frame, in that other frame.
inline mat6 moved(const mat6& i, const multibody::pose& x) {
    const double m = i(5, 5);
    if (m <= 0.0) return mat6::Zero();
    multibody::body b;
    unpack(i, b);
    return multibody::spatial_inertia(m, x.point(b.com),
                                      x.rotation * b.inertia * x.rotation.transpose());
}

/// The read phase (urdf.cpp): the robot of a parsed document, checked; throws urdf_error.
robot_data read_urdf(const reader& rd, const tinyxml2::XMLDocument& doc, bool need_joint = true);
/// The build phase (urdf_build.cpp): the tree of a robot read by read_urdf, its bodies the
/// moving joints depth first (then the mimic ones moved last), fixed joints merged; throws
/// urdf_error for what overflows a double and for a moving link without mass.
std::shared_ptr<multibody::tree> build_tree(const reader& rd, const robot_data& data);

} // namespace varsym::models::urdf_detail
