// models/src/urdf.cpp: URDF → multibody model, in two phases as Pinocchio's URDF visitor and
// RBDL: this file reads and checks the XML into plain data (read_urdf: links, joints, their
// depth-first order), urdf_build.cpp builds the tree of that data (build_tree). The XML is read
// by TinyXML-2 (Debian's libtinyxml2-dev): it reports the line of every element, so each refusal
// names the element and its line, and it prints nothing itself (urdfdom logs its own errors
// through console_bridge and builds a model varsym would then have to walk again). Only
// <robot>'s direct <link> and <joint> children are read: <transmission> (whose <joint> elements
// are not joints), <gazebo>, <material>, visuals and unknown tags are ignored; the links'
// <collision> shapes are kept for contact (urdf_reader.hpp, collisions). What
// is refused: docs/robots.md.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

#include "urdf_reader.hpp"
#include "varsym/models/input_file.hpp"

namespace varsym::models {

namespace urdf_detail {

namespace {

/// The joints by name (indices into robot_data::joints).
using joint_names = std::map<std::string, std::size_t>;
/// The joints whose parent is each link, in file order.
using joint_children = std::map<std::string, std::vector<std::size_t>>;

/// Reads <robot>'s <link> children into d.links (names unique, mass properties checked) and
/// returns their names in file order.
std::vector<std::string> read_links(const reader& rd, robot_data& d) {
    std::vector<std::string> link_order;
    for (const XMLElement* e = d.robot->FirstChildElement("link"); e;
         e = e->NextSiblingElement("link")) {
        const std::string name = rd.name(e, "link");
        if (d.links.contains(name))
            rd.fail(e, "link " + name + " is defined twice (first at line " +
                           std::to_string(d.links[name].element->GetLineNum()) + ")");
        link_data& l = d.links[name];
        l.element = e;
        rd.inertial(l, name);
        link_order.push_back(name);
    }
    if (d.links.empty()) rd.fail(d.robot, "no <link>");
    return link_order;
}

/// Reads <robot>'s <joint> children into d.joints (names unique, a supported type, defined
/// links, each link the child of one joint at most), filling `named` and `children`, and sets
/// d.root: the one link of `link_order` that is no joint's child.
void read_joints(const reader& rd, robot_data& d, const std::vector<std::string>& link_order,
                 joint_names& named, joint_children& children) {
    std::map<std::string, std::size_t> parent_joint; // child link -> its joint
    for (const XMLElement* e = d.robot->FirstChildElement("joint"); e;
         e = e->NextSiblingElement("joint")) {
        joint_data j;
        j.element = e;
        j.name = rd.name(e, "joint");
        j.type = rd.attribute(e, "type");
        if (named.contains(j.name))
            rd.fail(e, "joint " + j.name + " is defined twice (first at line " +
                           std::to_string(d.joints[named[j.name]].element->GetLineNum()) +
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
            if (!d.links.contains(l))
                rd.fail(e, "joint " + j.name + " names link " + l + ", which is not defined");
        if (parent_joint.contains(j.child))
            rd.fail(e, "joint " + j.name + ": link " + j.child + " is already the child of joint " +
                           d.joints[parent_joint[j.child]].name +
                           " (a closed loop; URDF describes trees)");
        named[j.name] = d.joints.size();
        parent_joint[j.child] = d.joints.size();
        children[j.parent].push_back(d.joints.size());
        d.joints.push_back(j);
    }
    std::vector<std::string> roots;
    for (const std::string& l : link_order)
        if (!parent_joint.contains(l)) roots.push_back(l);
    if (roots.size() != 1)
        rd.fail(d.robot, roots.empty()
                             ? std::string("every link has a parent: the joints form a closed loop")
                             : "links " + roots[0] + " and " + roots[1] +
                                   " both have no parent: the URDF must be one tree");
    d.root = roots[0];
}

/// The moving data of joint j, whose type is revolute, continuous or prismatic: its child link
/// has <inertial>; its kind, unit axis, <limit> (position bounds but for a continuous joint,
/// effort and velocity magnitudes) and <dynamics> damping.
void read_moving(const reader& rd, const robot_data& d, joint_data& j) {
    if (!d.links.at(j.child).has_inertial)
        rd.fail(d.links.at(j.child).element,
                "link " + j.child + " moves (joint " + j.name + ") but has no <inertial>");
    j.kind =
        j.type == "prismatic" ? multibody::joint_kind::prismatic : multibody::joint_kind::revolute;
    j.axis = rd.axis(j.element, j.name);
    multibody::joint_limits& l = j.limits;
    if (const XMLElement* lim = j.element->FirstChildElement("limit")) {
        if (j.type != "continuous") {
            l.lower = rd.number(lim, "lower", l.lower);
            l.upper = rd.number(lim, "upper", l.upper);
            if (l.lower > l.upper)
                rd.fail(lim, "joint " + j.name + ": lower limit above the upper");
        }
        // URDF's effort and velocity are magnitudes (effort 0: unactuated, velocity 0: no
        // limit); a negative one is a sign error, not either of those.
        l.effort = rd.number(lim, "effort", l.effort);
        if (l.effort < 0.0)
            rd.fail(lim, "joint " + j.name + ": negative effort " + std::to_string(l.effort) +
                             " (the largest torque or force, a magnitude; 0: unactuated)");
        l.velocity = rd.number(lim, "velocity", l.velocity);
        if (l.velocity < 0.0)
            rd.fail(lim, "joint " + j.name + ": negative velocity limit " +
                             std::to_string(l.velocity) + " (a magnitude; 0: no limit)");
    }
    if (const XMLElement* dyn = j.element->FirstChildElement("dynamics")) {
        l.damping = rd.number(dyn, "damping", 0.0);
        if (l.damping < 0.0) rd.fail(dyn, "joint " + j.name + ": negative damping");
    }
}

/// Walks the joints depth first from d.root, children in file order, by an explicit stack (a
/// recursion would overflow the call stack on a chain of some thousand links), reading each
/// joint's origin and a moving joint's data, into d.order. Returns per joint the moving joint
/// whose body carries its parent link (−1: the ground). Refuses links the walk does not reach
/// and a robot without a moving joint.
std::vector<int> walk(const reader& rd, robot_data& d, const joint_children& children,
                      bool need_joint) {
    struct pending {
        std::size_t joint;
        int mover; // the moving joint whose body carries the joint's parent link
    };
    std::vector<pending> stack;
    auto push_children = [&](const std::string& link, int mover) {
        const auto at = children.find(link);
        if (at == children.end()) return;
        for (auto k = at->second.rbegin(); k != at->second.rend(); ++k) // the first child on top
            stack.push_back({*k, mover});
    };
    std::vector<int> mover(d.joints.size(), -1);
    push_children(d.root, -1);
    while (!stack.empty()) {
        const pending next = stack.back();
        stack.pop_back();
        joint_data& j = d.joints[next.joint];
        j.origin = rd.origin(j.element);
        d.order.push_back(next.joint);
        mover[next.joint] = next.mover;
        if (j.moves()) read_moving(rd, d, j);
        push_children(j.child, j.moves() ? static_cast<int>(next.joint) : next.mover);
    }
    const std::size_t reached = d.order.size() + 1; // the root and each joint's child
    if (reached != d.links.size())
        rd.fail(d.robot, std::to_string(d.links.size() - reached) +
                             " links are not reachable from the root link " + d.root +
                             " (a closed loop)");
    if (need_joint && std::none_of(d.order.begin(), d.order.end(),
                                   [&](std::size_t k) { return d.joints[k].moves(); }))
        rd.fail(d.robot, "no revolute, continuous or prismatic joint: nothing moves");
    return mover;
}

/// Reads the <mimic> elements of the moving joints (on a fixed joint it is ignored: there is
/// no position to couple): θ = multiplier · q_master + offset (URDF's defaults 1 and 0). The
/// master is a moving joint without <mimic>; a moving joint below a mimic joint (`mover`, as
/// walk gives it) must mimic too (else it would be a coordinate after the mimic bodies, whose
/// parents must come first).
void read_mimics(const reader& rd, robot_data& d, const joint_names& named,
                 const std::vector<int>& mover) {
    for (const std::size_t k : d.order)
        if (d.joints[k].moves())
            d.joints[k].mimic.element = d.joints[k].element->FirstChildElement("mimic");
    auto mimics = [&](std::size_t k) { return d.joints[k].mimic.element != nullptr; };
    for (const std::size_t k : d.order) {
        const joint_data& j = d.joints[k];
        if (j.moves() && !mimics(k) && mover[k] >= 0 && mimics(static_cast<std::size_t>(mover[k])))
            rd.fail(j.element, "joint " + j.name + " moves below the mimic joint " +
                                   d.joints[static_cast<std::size_t>(mover[k])].name +
                                   ": a joint below a mimic joint must mimic too");
    }
    for (const std::size_t k : d.order) {
        joint_data& j = d.joints[k];
        const XMLElement* e = j.mimic.element;
        if (!e) continue;
        const std::string master = rd.attribute(e, "joint");
        const auto at = named.find(master);
        if (at == named.end())
            rd.fail(e, "joint " + j.name + " mimics " + master +
                           ", which is not a joint of this robot (joint names are case-sensitive)");
        const bool moves = d.joints[at->second].moves();
        if (!moves || mimics(at->second))
            rd.fail(e, "joint " + j.name + " mimics " + master +
                           (!moves ? ", which is not a revolute, continuous or prismatic joint"
                                   : ", which is a mimic joint itself (mimic its master instead)"));
        j.mimic.master = at->second;
        j.mimic.multiplier = rd.number(e, "multiplier", 1.0);
        j.mimic.offset = rd.number(e, "offset", 0.0);
    }
}

} // namespace

robot_data read_urdf(const reader& rd, const tinyxml2::XMLDocument& doc, bool need_joint) {
    robot_data d;
    d.robot = doc.RootElement();
    if (!d.robot || std::string(d.robot->Name()) != "robot")
        rd.fail(d.robot, "the root element must be <robot>");
    if (const XMLElement* second = d.robot->NextSiblingElement())
        rd.fail(second, "a second root element after <robot>: a URDF file holds one robot");
    d.name = rd.attribute(d.robot, "name", false);
    const std::vector<std::string> link_order = read_links(rd, d);
    joint_names named;
    joint_children children;
    read_joints(rd, d, link_order, named, children);
    const std::vector<int> mover = walk(rd, d, children, need_joint);
    read_mimics(rd, d, named, mover);
    return d;
}

} // namespace urdf_detail

std::shared_ptr<const multibody::tree> parse_urdf(std::string_view xml, const std::string& source,
                                                  multibody::base_kind base) {
    const urdf_detail::reader rd(source);
    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
        throw urdf_error(source + ":" + std::to_string(doc.ErrorLineNum()) +
                         ": malformed XML: " + doc.ErrorName());
    const bool fixed = base == multibody::base_kind::fixed;
    auto tree = urdf_detail::build_tree(rd, urdf_detail::read_urdf(rd, doc, fixed));
    if (fixed) return tree;
    try {
        return std::make_shared<const multibody::tree>(tree->with_base(base));
    } catch (const std::invalid_argument& e) {
        throw urdf_error(source + ": " + e.what());
    }
}

std::shared_ptr<const multibody::tree> load_urdf(const std::string& path,
                                                 multibody::base_kind base) {
    std::string text;
    try {
        text = read_input_file(path, max_urdf_bytes, "URDF file");
    } catch (const input_error& e) {
        throw urdf_error(e.what());
    }
    return parse_urdf(text, path, base);
}

} // namespace varsym::models

namespace varsym::models {

multibody::base_kind base_of(const std::string& word) {
    if (word == "fixed") return multibody::base_kind::fixed;
    if (word == "free") return multibody::base_kind::free;
    if (word == "planar") return multibody::base_kind::planar;
    throw std::invalid_argument("the base is fixed, free or planar, not '" + word + "'");
}

} // namespace varsym::models
