// models/src/urdf.cpp: URDF → multibody model. The XML is read by TinyXML-2 (Debian's
// libtinyxml2-dev): it reports the line of every element, so each refusal names the element and
// its line, and it prints nothing itself (urdfdom logs its own errors through console_bridge and
// builds a model varsym would then have to walk again). Only <robot>'s direct <link> and <joint>
// children are read: <transmission> (whose <joint> elements are not joints), <gazebo>, <material>,
// visuals, collisions and unknown tags are ignored. What is refused: docs/robots.md.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

#include <Eigen/Eigenvalues>
#include <tinyxml2.h>

#include "varsym/models/robot.hpp"

namespace varsym::models {

namespace {

using multibody::mat3;
using multibody::mat6;
using multibody::vec3;
using tinyxml2::XMLElement;

struct link_data {
    const XMLElement* element = nullptr;
    bool has_inertial = false;
    mat6 inertia = mat6::Zero(); ///< spatial inertia in the link frame (merged children added)
};

struct joint_data {
    const XMLElement* element = nullptr;
    std::string name, type, parent, child;
};

class reader {
  public:
    explicit reader(std::string source) : source_(std::move(source)) {}

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
            while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
            const auto r = std::from_chars(p + (p < end && *p == '+' ? 1 : 0), end, out(i));
            if (r.ec != std::errc() || !std::isfinite(out(i)))
                fail(e, std::string("attribute ") + name + "=\"" + text + "\" needs " +
                            std::to_string(count) + " finite number" + (count > 1 ? "s" : ""));
            p = r.ptr;
        }
        while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
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

    /// A link's <inertial> as a spatial inertia in the link frame, checked: mass ≥ 0, the
    /// inertia tensor symmetric positive definite (or all zero with zero mass), its principal
    /// moments meeting the triangle inequality.
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
        l.inertia = multibody::spatial_inertia(m, o.origin, o.rotation * ic * o.rotation.transpose());
    }

    void check_inertia(const XMLElement* e, const std::string& name, double m,
                       const mat3& ic) const {
        const Eigen::SelfAdjointEigenSolver<mat3> es(ic);
        const vec3 k = es.eigenvalues(); // ascending
        char buf[256];
        if (!(m > 0.0)) fail(e, "link " + name + ": an inertia tensor without mass");
        if (!(k(0) > 0.0)) {
            std::snprintf(buf, sizeof buf,
                          "link %s: the inertia tensor is not positive definite (principal "
                          "moments %.6g, %.6g, %.6g kg m^2)",
                          name.c_str(), k(0), k(1), k(2));
            fail(e, buf);
        }
        // A rigid body's moments satisfy I_3 <= I_1 + I_2 (equality: a flat body); printed
        // digits may round a flat body's over it by a few parts in a million.
        const double excess = k(2) - (k(0) + k(1));
        if (excess > 1e-6 * k(2)) {
            std::snprintf(buf, sizeof buf,
                          "link %s: principal moments %.6g, %.6g, %.6g kg m^2 break the triangle "
                          "inequality (the largest exceeds the sum of the others by %.3g, %.2g %%)",
                          name.c_str(), k(0), k(1), k(2), excess, 100.0 * excess / k(2));
            fail(e, buf);
        }
    }

  private:
    std::string source_;
};

/// The mass, centre and rotational inertia about the centre of a spatial inertia.
void unpack(const mat6& i, multibody::body& b) {
    b.mass = i(5, 5);
    if (b.mass <= 0.0) return;
    const mat3 mcx = i.topRightCorner<3, 3>(); // m c×
    b.com = vec3(mcx(2, 1), mcx(0, 2), mcx(1, 0)) / b.mass;
    const mat3 cx = multibody::skew(b.com);
    b.inertia = i.topLeftCorner<3, 3>() - b.mass * cx * cx.transpose();
}

/// The spatial inertia `i` given in a frame at pose `x` of another frame, in that other frame.
mat6 moved(const mat6& i, const multibody::pose& x) {
    const double m = i(5, 5);
    if (m <= 0.0) return mat6::Zero();
    multibody::body b;
    unpack(i, b);
    return multibody::spatial_inertia(m, x.point(b.com),
                                      x.rotation * b.inertia * x.rotation.transpose());
}

} // namespace

std::shared_ptr<const multibody::model> parse_urdf(std::string_view xml, const std::string& source) {
    reader rd(source);
    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
        throw urdf_error(source + ":" + std::to_string(doc.ErrorLineNum()) +
                         ": malformed XML: " + doc.ErrorName());
    const XMLElement* robot = doc.RootElement();
    if (!robot || std::string(robot->Name()) != "robot")
        rd.fail(robot, "the root element must be <robot>");

    std::map<std::string, link_data> links;
    std::vector<std::string> link_order;
    for (const XMLElement* e = robot->FirstChildElement("link"); e;
         e = e->NextSiblingElement("link")) {
        const std::string name = rd.attribute(e, "name");
        if (links.contains(name)) rd.fail(e, "link " + name + " is defined twice");
        link_data& l = links[name];
        l.element = e;
        rd.inertial(l, name);
        link_order.push_back(name);
    }
    if (links.empty()) rd.fail(robot, "no <link>");

    std::vector<joint_data> joints;
    std::map<std::string, std::size_t> parent_joint; // child link -> its joint
    std::map<std::string, std::vector<std::size_t>> children;
    for (const XMLElement* e = robot->FirstChildElement("joint"); e;
         e = e->NextSiblingElement("joint")) {
        joint_data j{e, rd.attribute(e, "name"), rd.attribute(e, "type"), "", ""};
        const XMLElement* p = e->FirstChildElement("parent");
        const XMLElement* c = e->FirstChildElement("child");
        if (!p || !c) rd.fail(e, "joint " + j.name + " needs <parent link> and <child link>");
        j.parent = rd.attribute(p, "link");
        j.child = rd.attribute(c, "link");
        if (j.type == "floating" || j.type == "planar")
            rd.fail(e, "joint " + j.name + ": " + j.type +
                           " joints are not supported (revolute, continuous, prismatic and "
                           "fixed are)");
        if (j.type != "revolute" && j.type != "continuous" && j.type != "prismatic" &&
            j.type != "fixed")
            rd.fail(e, "joint " + j.name + ": unknown type '" + j.type + "'");
        if (const XMLElement* mimic = e->FirstChildElement("mimic"))
            rd.fail(mimic, "joint " + j.name +
                               ": <mimic> joints are not supported (remove the <mimic> element "
                               "to make the joint independent)");
        for (const std::string& l : {j.parent, j.child})
            if (!links.contains(l))
                rd.fail(e, "joint " + j.name + " names link " + l + ", which is not defined");
        if (parent_joint.contains(j.child))
            rd.fail(e, "joint " + j.name + ": link " + j.child + " is already the child of joint " +
                           joints[parent_joint[j.child]].name +
                           " (a closed loop; URDF describes trees)");
        parent_joint[j.child] = joints.size();
        children[j.parent].push_back(joints.size());
        joints.push_back(j);
    }

    std::vector<std::string> roots;
    for (const std::string& l : link_order)
        if (!parent_joint.contains(l)) roots.push_back(l);
    if (roots.size() != 1)
        rd.fail(robot, roots.empty()
                           ? std::string("every link has a parent: the joints form a closed loop")
                           : "links " + roots[0] + " and " + roots[1] +
                                 " both have no parent: the URDF must be one tree");

    auto m = std::make_shared<multibody::model>();
    m->name = rd.attribute(robot, "name", false);
    std::vector<mat6> inertia; // per body, in its frame: its link's and those fixed to it
    std::size_t visited = 0;
    // Depth first from the root; `body` is the body the link is fixed to (−1: the ground) and
    // `offset` the link's frame in that body's frame.
    auto visit = [&](auto& self, const std::string& link, int body,
                     const multibody::pose& offset) -> void {
        ++visited;
        m->frames.push_back({link, body, offset});
        if (body >= 0) inertia[static_cast<std::size_t>(body)] += moved(links[link].inertia, offset);
        for (const std::size_t k : children[link]) {
            const joint_data& j = joints[k];
            const multibody::pose placement = offset * rd.origin(j.element);
            if (j.type == "fixed") {
                self(self, j.child, body, placement);
                continue;
            }
            if (!links[j.child].has_inertial)
                rd.fail(links[j.child].element, "link " + j.child + " moves (joint " + j.name +
                                                    ") but has no <inertial>");
            multibody::body b;
            b.name = j.name;
            b.link = j.child;
            b.parent = body;
            b.kind = j.type == "prismatic" ? multibody::joint_kind::prismatic
                                           : multibody::joint_kind::revolute;
            b.placement = placement;
            const XMLElement* axis = j.element->FirstChildElement("axis");
            const vec3 a = rd.numbers(axis, "xyz", 3, vec3::UnitX());
            if (!(a.norm() > 1e-12)) rd.fail(axis, "joint " + j.name + ": zero axis");
            b.axis = a.normalized();
            if (const XMLElement* lim = j.element->FirstChildElement("limit")) {
                if (j.type != "continuous") {
                    b.limits.lower = rd.number(lim, "lower", b.limits.lower);
                    b.limits.upper = rd.number(lim, "upper", b.limits.upper);
                    if (b.limits.lower > b.limits.upper)
                        rd.fail(lim, "joint " + j.name + ": lower limit above the upper");
                }
                b.limits.effort = rd.number(lim, "effort", b.limits.effort);
                b.limits.velocity = rd.number(lim, "velocity", b.limits.velocity);
            }
            if (const XMLElement* dyn = j.element->FirstChildElement("dynamics")) {
                b.limits.damping = rd.number(dyn, "damping", 0.0);
                if (b.limits.damping < 0.0)
                    rd.fail(dyn, "joint " + j.name + ": negative damping");
            }
            m->bodies.push_back(b);
            inertia.push_back(mat6::Zero());
            self(self, j.child, static_cast<int>(m->bodies.size()) - 1, multibody::pose{});
        }
    };
    visit(visit, roots[0], -1, multibody::pose{});
    if (visited != links.size())
        rd.fail(robot, std::to_string(links.size() - visited) +
                           " links are not reachable from the root link " + roots[0] +
                           " (a closed loop)");
    if (m->bodies.empty())
        rd.fail(robot, "no revolute, continuous or prismatic joint: nothing moves");
    for (std::size_t i = 0; i < m->bodies.size(); ++i) {
        multibody::body& b = m->bodies[i];
        unpack(inertia[i], b);
        if (!(b.mass > 0.0))
            rd.fail(links[b.link].element,
                    "link " + b.link + " moves (joint " + b.name + ") but carries no mass");
    }
    m->check();
    return m;
}

std::shared_ptr<const multibody::model> load_urdf(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw urdf_error(path + ": cannot open the URDF file (" + std::strerror(errno) + ")");
    std::string text;
    char buf[65536];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;)
        text.append(buf, n);
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) throw urdf_error(path + ": cannot read the URDF file");
    return parse_urdf(text, path);
}

} // namespace varsym::models
