// models/src/urdf.cpp: URDF → multibody model. The XML is read by TinyXML-2 (Debian's
// libtinyxml2-dev): it reports the line of every element, so each refusal names the element and
// its line, and it prints nothing itself (urdfdom logs its own errors through console_bridge and
// builds a model varsym would then have to walk again). Only <robot>'s direct <link> and <joint>
// children are read: <transmission> (whose <joint> elements are not joints), <gazebo>, <material>,
// visuals, collisions and unknown tags are ignored. What is refused: docs/robots.md.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

#include "urdf_reader.hpp"
#include "varsym/models/input_file.hpp"
#include "varsym/multibody/algorithms.hpp"

namespace varsym::models {

namespace {

using namespace urdf_detail;

/// Refuses a model whose poses or mass properties overflow a double at q = 0 (each number is
/// finite, but lengths of 1e200 m or masses of 1e308 kg make m c c or the subtree sums
/// infinite), naming the joint of the smallest subtree that overflows. `joint[i]` is body i's
/// joint element.
void check_finite(const reader& rd, const multibody::model& m,
                  const std::vector<const XMLElement*>& joint) {
    multibody::workspace w;
    multibody::kinematics(m, w, Eigen::VectorXd::Zero(m.dof()));
    auto finite = [&](std::size_t k) {
        return w.x[k].origin.allFinite() && w.x[k].rotation.allFinite() && w.s[k].allFinite() &&
               w.inertia[k].allFinite() && w.f[k].allFinite();
    };
    for (std::size_t k = 0; k < m.bodies.size(); ++k)
        if (!finite(k))
            rd.fail(joint[k], "joint " + m.bodies[k].name +
                                  ": the pose or the mass properties of its link overflow a "
                                  "double at q = 0 (lengths or masses too large)");
    multibody::subtree_sums(m, w, true);
    for (std::size_t k = m.bodies.size(); k-- > 0;) // leaves first: the smallest subtree
        if (!finite(k) || !std::isfinite(w.s[k].dot(w.inertia[k] * w.s[k])))
            rd.fail(joint[k], "joint " + m.bodies[k].name +
                                  ": the mass properties of the links it moves overflow a double "
                                  "at q = 0 (lengths or masses too large)");
}

/// Moves the bodies of mimic joints (a <mimic> element; on a fixed joint it is ignored: there
/// is no position to couple) after the coordinates' and couples them: θ = multiplier · q_master
/// + offset (URDF's defaults 1 and 0). The master is a moving joint without <mimic>; a moving
/// joint below a mimic joint must mimic too (else it would be a coordinate after the mimic
/// bodies, whose parents must come first). `inertia` and `joint` are per body, reordered too.
void couple_mimics(const reader& rd, multibody::model& m, std::vector<mat6>& inertia,
                   std::vector<const XMLElement*>& joint) {
    const std::size_t n = m.bodies.size();
    std::vector<const XMLElement*> mimic(n);
    std::map<std::string, std::size_t> body_of;
    for (std::size_t k = 0; k < n; ++k) {
        mimic[k] = joint[k]->FirstChildElement("mimic");
        body_of[m.bodies[k].name] = k;
    }
    std::vector<std::size_t> order; // new index -> old: coordinates, then mimic bodies
    for (const bool second : {false, true})
        for (std::size_t k = 0; k < n; ++k)
            if ((mimic[k] != nullptr) == second) order.push_back(k);
    if (std::none_of(mimic.begin(), mimic.end(), [](const XMLElement* e) { return e; })) return;
    std::vector<int> new_index(n);
    for (std::size_t i = 0; i < n; ++i)
        new_index[order[i]] = static_cast<int>(i);
    std::vector<multibody::body> bodies;
    std::vector<mat6> inertias;
    std::vector<const XMLElement*> joints;
    for (const std::size_t k : order) {
        multibody::body b = m.bodies[k];
        if (b.parent >= 0) {
            const auto p = static_cast<std::size_t>(b.parent);
            if (!mimic[k] && mimic[p])
                rd.fail(joint[k], "joint " + b.name + " moves below the mimic joint " +
                                      m.bodies[p].name +
                                      ": a joint below a mimic joint must mimic too");
            b.parent = new_index[p];
        }
        bodies.push_back(b);
        inertias.push_back(inertia[k]);
        joints.push_back(joint[k]);
    }
    for (const std::size_t k : order) {
        const XMLElement* e = mimic[k];
        if (!e) continue;
        const std::string master = rd.attribute(e, "joint");
        const auto at = body_of.find(master);
        if (at == body_of.end() || mimic[at->second])
            rd.fail(e, "joint " + m.bodies[k].name + " mimics " + master +
                           (at == body_of.end()
                                ? ", which is not a revolute, continuous or prismatic joint"
                                : ", which is a mimic joint itself (mimic its master instead)"));
        multibody::mimic c;
        c.master = new_index[at->second];
        c.multiplier = rd.number(e, "multiplier", 1.0);
        c.offset = rd.number(e, "offset", 0.0);
        m.mimics.push_back(c);
    }
    for (multibody::frame& f : m.frames)
        if (f.body >= 0) f.body = new_index[static_cast<std::size_t>(f.body)];
    m.bodies = std::move(bodies);
    inertia = std::move(inertias);
    joint = std::move(joints);
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
    if (const XMLElement* second = robot->NextSiblingElement())
        rd.fail(second, "a second root element after <robot>: a URDF file holds one robot");

    std::map<std::string, link_data> links;
    std::vector<std::string> link_order;
    for (const XMLElement* e = robot->FirstChildElement("link"); e;
         e = e->NextSiblingElement("link")) {
        const std::string name = rd.name(e, "link");
        if (links.contains(name))
            rd.fail(e, "link " + name + " is defined twice (first at line " +
                           std::to_string(links[name].element->GetLineNum()) + ")");
        link_data& l = links[name];
        l.element = e;
        rd.inertial(l, name);
        link_order.push_back(name);
    }
    if (links.empty()) rd.fail(robot, "no <link>");

    std::vector<joint_data> joints;
    std::map<std::string, std::size_t> parent_joint; // child link -> its joint
    std::map<std::string, std::size_t> joint_named;
    std::map<std::string, std::vector<std::size_t>> children;
    for (const XMLElement* e = robot->FirstChildElement("joint"); e;
         e = e->NextSiblingElement("joint")) {
        joint_data j{e, rd.name(e, "joint"), rd.attribute(e, "type"), "", ""};
        if (joint_named.contains(j.name))
            rd.fail(e, "joint " + j.name + " is defined twice (first at line " +
                           std::to_string(joints[joint_named[j.name]].element->GetLineNum()) +
                           "; joint names name the coordinates)");
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
        for (const std::string& l : {j.parent, j.child})
            if (!links.contains(l))
                rd.fail(e, "joint " + j.name + " names link " + l + ", which is not defined");
        if (parent_joint.contains(j.child))
            rd.fail(e, "joint " + j.name + ": link " + j.child + " is already the child of joint " +
                           joints[parent_joint[j.child]].name +
                           " (a closed loop; URDF describes trees)");
        joint_named[j.name] = joints.size();
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
    std::vector<mat6> inertia;                  // per body, in its frame: its link's and merged
    std::vector<const XMLElement*> body_joint; // per body, its joint's element
    std::size_t visited = 0;
    // Link `link` fixed to body `body` (−1: the ground) at `offset` in that body's frame: a
    // frame, its mass merged into the body (moved into the body's frame).
    auto visit = [&](const std::string& link, int body, const multibody::pose& offset) {
        ++visited;
        m->frames.push_back({link, body, offset});
        if (body < 0) return;
        mat6& sum = inertia[static_cast<std::size_t>(body)];
        sum += moved(links[link].inertia, offset);
        if (!sum.allFinite())
            rd.fail(links[link].element,
                    "link " + link + ": merged into link " + m->bodies[static_cast<std::size_t>(body)].link +
                        " by fixed joints, the mass properties overflow a double");
    };
    // Depth first from the root, children in file order, by an explicit stack (a recursion
    // would overflow the call stack on a chain of some thousand links): each entry is a joint
    // still to walk, with the body its parent link is fixed to and that link's frame there.
    struct pending {
        std::size_t joint;
        int body;
        multibody::pose offset;
    };
    std::vector<pending> stack;
    auto push_children = [&](const std::string& link, int body, const multibody::pose& offset) {
        const std::vector<std::size_t>& c = children[link];
        for (auto k = c.rbegin(); k != c.rend(); ++k) // the first child on top
            stack.push_back({*k, body, offset});
    };
    visit(roots[0], -1, multibody::pose{});
    push_children(roots[0], -1, multibody::pose{});
    while (!stack.empty()) {
        const pending next = stack.back();
        stack.pop_back();
        const joint_data& j = joints[next.joint];
        const multibody::pose placement = next.offset * rd.origin(j.element);
        if (!placement.origin.allFinite())
            rd.fail(j.element, "joint " + j.name +
                                   ": its <origin> (after the fixed joints above it) overflows "
                                   "a double");
        if (j.type == "fixed") {
            visit(j.child, next.body, placement);
            push_children(j.child, next.body, placement);
            continue;
        }
        if (!links[j.child].has_inertial)
            rd.fail(links[j.child].element,
                    "link " + j.child + " moves (joint " + j.name + ") but has no <inertial>");
        multibody::body b;
        b.name = j.name;
        b.link = j.child;
        b.parent = next.body;
        b.kind = j.type == "prismatic" ? multibody::joint_kind::prismatic
                                       : multibody::joint_kind::revolute;
        b.placement = placement;
        b.axis = rd.axis(j.element, j.name);
        if (const XMLElement* lim = j.element->FirstChildElement("limit")) {
            if (j.type != "continuous") {
                b.limits.lower = rd.number(lim, "lower", b.limits.lower);
                b.limits.upper = rd.number(lim, "upper", b.limits.upper);
                if (b.limits.lower > b.limits.upper)
                    rd.fail(lim, "joint " + j.name + ": lower limit above the upper");
            }
            // URDF's effort and velocity are magnitudes (effort 0: unactuated, velocity 0: no
            // limit); a negative one is a sign error, not either of those.
            b.limits.effort = rd.number(lim, "effort", b.limits.effort);
            if (b.limits.effort < 0.0)
                rd.fail(lim, "joint " + j.name + ": negative effort " +
                                 std::to_string(b.limits.effort) +
                                 " (the largest torque or force, a magnitude; 0: unactuated)");
            b.limits.velocity = rd.number(lim, "velocity", b.limits.velocity);
            if (b.limits.velocity < 0.0)
                rd.fail(lim, "joint " + j.name + ": negative velocity limit " +
                                 std::to_string(b.limits.velocity) +
                                 " (a magnitude; 0: no limit)");
        }
        if (const XMLElement* dyn = j.element->FirstChildElement("dynamics")) {
            b.limits.damping = rd.number(dyn, "damping", 0.0);
            if (b.limits.damping < 0.0) rd.fail(dyn, "joint " + j.name + ": negative damping");
        }
        m->bodies.push_back(b);
        inertia.push_back(mat6::Zero());
        body_joint.push_back(j.element);
        const int child = static_cast<int>(m->bodies.size()) - 1;
        visit(j.child, child, multibody::pose{});
        push_children(j.child, child, multibody::pose{});
    }
    if (visited != links.size())
        rd.fail(robot, std::to_string(links.size() - visited) +
                           " links are not reachable from the root link " + roots[0] +
                           " (a closed loop)");
    if (m->bodies.empty())
        rd.fail(robot, "no revolute, continuous or prismatic joint: nothing moves");
    couple_mimics(rd, *m, inertia, body_joint);
    for (std::size_t i = 0; i < m->bodies.size(); ++i) {
        multibody::body& b = m->bodies[i];
        unpack(inertia[i], b);
        if (!(b.mass > 0.0))
            rd.fail(links[b.link].element,
                    "link " + b.link + " moves (joint " + b.name + ") but carries no mass");
    }
    check_finite(rd, *m, body_joint);
    try {
        m->check();
    } catch (const std::invalid_argument& e) { // not expected after the checks above
        rd.fail(robot, e.what());
    }
    return m;
}

std::shared_ptr<const multibody::model> load_urdf(const std::string& path) {
    std::string text;
    try {
        text = read_input_file(path, max_urdf_bytes, "URDF file");
    } catch (const input_error& e) {
        throw urdf_error(e.what());
    }
    return parse_urdf(text, path);
}

} // namespace varsym::models
