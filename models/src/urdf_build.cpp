// models/src/urdf_build.cpp: the build phase of the URDF reader (urdf_reader.hpp): the
// multibody::tree of a robot read and checked by read_urdf (urdf.cpp). Each moving joint becomes
// a body (tree::add_body), depth first from the root link; a link fixed to a body is a frame of
// it and its mass properties are merged into the body's; the mimic joints' bodies are then moved
// after the coordinates' and coupled. What overflows a double is refused here, naming the element
// and its line.
#include <map>
#include <vector>

#include "urdf_reader.hpp"
#include "varsym/multibody/algorithms.hpp"

namespace varsym::models::urdf_detail {

namespace {

/// Refuses a model whose poses or mass properties overflow a double at q = 0 (each number is
/// finite, but lengths of 1e200 m or masses of 1e308 kg make m c c or the subtree sums
/// infinite), naming the joint of the smallest subtree that overflows. `joint[i]` is body i's
/// joint element.
void check_finite(const reader& rd, const multibody::tree& m,
                  const std::vector<const XMLElement*>& joint) {
    multibody::workspace w;
    multibody::kinematics(m, w, Eigen::VectorXd::Zero(m.dof()));
    auto finite = [&](std::size_t k) {
        return w.x[k].origin.allFinite() && w.x[k].rotation.allFinite() && w.s[k].allFinite() &&
               w.inertia[k].allFinite() && w.gravity[k].allFinite();
    };
    for (std::size_t k = 0; k < m.bodies.size(); ++k)
        if (!finite(k))
            rd.fail(joint[k], "joint " + m.bodies[k].name +
                                  ": the pose or the mass properties of its link overflow a "
                                  "double at q = 0 (lengths or masses too large)");
    multibody::subtree_sums(m, w, true);
    for (std::size_t k = m.bodies.size(); k-- > 0;) // leaves first: the smallest subtree
        if (!w.inertia_c[k].allFinite() || !w.gravity_c[k].allFinite() ||
            !std::isfinite(w.s[k].dot(w.inertia_c[k] * w.s[k])))
            rd.fail(joint[k], "joint " + m.bodies[k].name +
                                  ": the mass properties of the links it moves overflow a double "
                                  "at q = 0 (lengths or masses too large)");
}

/// Moves the bodies of mimic joints after the coordinates' (each group in its order) and
/// couples them to their masters (read_urdf checked the couplings and that no coordinate moves
/// below a mimic body). `joint` (per body, its joint in d.joints) and `inertia` (per body) are
/// reordered too; `body_of` gives each moving joint's body before the move.
void couple_mimics(const robot_data& d, multibody::tree& m, std::vector<mat6>& inertia,
                   std::vector<std::size_t>& joint, const std::vector<int>& body_of) {
    const std::size_t n = m.bodies.size();
    if (n == 0) return; // a single link (a free rigid body)
    auto mimics = [&](std::size_t k) { return d.joints[joint[k]].mimic.element != nullptr; };
    std::vector<std::size_t> order; // new index -> old: coordinates, then mimic bodies
    for (const bool second : {false, true})
        for (std::size_t k = 0; k < n; ++k)
            if (mimics(k) == second) order.push_back(k);
    if (!mimics(order.back())) return; // no mimic joint: the order stays
    std::vector<int> new_index(n);
    for (std::size_t i = 0; i < n; ++i)
        new_index[order[i]] = static_cast<int>(i);
    std::vector<multibody::body> bodies = std::move(m.bodies);
    m.bodies.clear();
    std::vector<mat6> inertias;
    std::vector<std::size_t> joints;
    for (const std::size_t k : order) {
        const int p = bodies[k].parent;
        m.add_body(p >= 0 ? new_index[static_cast<std::size_t>(p)] : -1, bodies[k]);
        inertias.push_back(inertia[k]);
        joints.push_back(joint[k]);
    }
    for (const std::size_t k : order) {
        const mimic_data& c = d.joints[joint[k]].mimic;
        if (c.element)
            m.mimics.push_back(
                {new_index[static_cast<std::size_t>(body_of[c.master])], c.multiplier, c.offset});
    }
    for (multibody::frame& f : m.frames)
        if (f.body >= 0) f.body = new_index[static_cast<std::size_t>(f.body)];
    inertia = std::move(inertias);
    joint = std::move(joints);
}

} // namespace

std::shared_ptr<multibody::tree> build_tree(const reader& rd, const robot_data& d) {
    auto m = std::make_shared<multibody::tree>();
    m->name = d.name;
    std::vector<mat6> inertia;                     // per body, in its frame: its link's and merged
    std::vector<std::size_t> body_joint;           // per body, its joint in d.joints
    std::vector<int> body_of(d.joints.size(), -1); // per moving joint, its body
    // Where each link reached so far is fixed: its body (−1: the ground) and its frame there.
    struct fixed_to {
        int body;
        multibody::pose offset;
    };
    std::map<std::string, fixed_to> at;
    mat6 ground = mat6::Zero(); // the root link and the links fixed to it (a floating base)
    // Link `link` fixed to body `body` at `offset` in that body's frame: a frame, its mass
    // merged into the body (moved into the body's frame).
    auto visit = [&](const std::string& link, int body, const multibody::pose& offset) {
        at[link] = {body, offset};
        m->frames.push_back({link, body, offset});
        if (body < 0) { // the ground's: a floating base's mass (tree::with_base checks it)
            ground += moved(d.links.at(link).inertia, offset);
            return;
        }
        mat6& sum = inertia[static_cast<std::size_t>(body)];
        const link_data& l = d.links.at(link);
        sum += moved(l.inertia, offset);
        if (!sum.allFinite())
            rd.fail(l.element, "link " + link + ": merged into link " +
                                   m->bodies[static_cast<std::size_t>(body)].link +
                                   " by fixed joints, the mass properties overflow a double");
    };
    visit(d.root, -1, multibody::pose{});
    for (const std::size_t k : d.order) { // depth first: each joint's parent link reached
        const joint_data& j = d.joints[k];
        const fixed_to parent = at.at(j.parent);
        const multibody::pose placement = parent.offset * j.origin;
        if (!placement.origin.allFinite())
            rd.fail(j.element, "joint " + j.name +
                                   ": its <origin> (after the fixed joints above it) overflows "
                                   "a double");
        if (!j.moves()) {
            visit(j.child, parent.body, placement);
            continue;
        }
        multibody::body b;
        b.name = j.name;
        b.link = j.child;
        b.kind = j.kind;
        b.placement = placement;
        b.axis = j.axis;
        b.limits = j.limits;
        const int child = m->add_body(parent.body, b);
        inertia.push_back(mat6::Zero());
        body_joint.push_back(k);
        body_of[k] = child;
        visit(j.child, child, multibody::pose{});
    }
    unpack(ground, m->root);
    m->root.name = m->root.link = d.root;
    couple_mimics(d, *m, inertia, body_joint, body_of);
    std::vector<const XMLElement*> joint_element; // per body, its joint's element
    for (std::size_t i = 0; i < m->bodies.size(); ++i) {
        multibody::body& b = m->bodies[i];
        unpack(inertia[i], b);
        if (!(b.mass > 0.0))
            rd.fail(d.links.at(b.link).element,
                    "link " + b.link + " moves (joint " + b.name + ") but carries no mass");
        joint_element.push_back(d.joints[body_joint[i]].element);
    }
    check_finite(rd, *m, joint_element);
    for (const multibody::frame& f : m->frames) // the links' shapes, where the links went
        for (multibody::collision_shape s : rd.collisions(d.links.at(f.name).element, f.name)) {
            s.body = f.body;
            s.offset = f.offset * s.offset;
            m->collisions.push_back(std::move(s));
        }
    const auto colours = rd.materials(d.robot);
    for (const multibody::frame& f : m->frames)
        for (multibody::visual_shape s : rd.visuals(d.links.at(f.name).element, f.name, colours)) {
            s.body = f.body;
            s.offset = f.offset * s.offset;
            m->visuals.push_back(std::move(s));
        }
    try {
        m->check();
    } catch (const std::invalid_argument& e) { // not expected after the checks above
        rd.fail(d.robot, e.what());
    }
    return m;
}

} // namespace varsym::models::urdf_detail
