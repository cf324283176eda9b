// apps/varsym/models/model_robot.cpp: the model `urdf`, a robot read from the URDF file of
// --urdf FILE (the models layer's robot_model), which `varsym run`, `ensemble`, `section`,
// `converge` and `stability` run like a registry model. Its parameters (gravity, damping, the PD
// controller, torques) are the shared parameter options.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "models/model_run.hpp"
#include "models/registry_models.hpp"
#include "options/expression_options.hpp"
#include "varsym/models/animation.hpp"
#include "varsym/models/input_file.hpp"
#include "varsym/models/robot.hpp"

namespace varsym::cli {

void check_resumed_input(const checkpoint& ck, const checkpoint::input_file& now) {
    const auto was = std::find_if(ck.inputs.begin(), ck.inputs.end(),
                                  [&](const auto& in) { return in.path == now.path; });
    if (was == ck.inputs.end())
        throw usage_error("cannot resume: the checkpoint records no digest of the URDF file '" +
                          now.path + "', so the robot cannot be checked; start a new run");
    if (was->digest != now.digest)
        throw usage_error("cannot resume: the URDF file '" + now.path +
                          "' changed since the run started (" + was->digest + " then, " +
                          now.digest + " now); restore it, or start a new run");
}

std::shared_ptr<const multibody::tree> robot_tree_of(const urdf_spec& u,
                                                     checkpoint::input_file* file) {
    if (u.path.empty())
        throw usage_error("--model urdf needs --urdf FILE, the robot's URDF description");
    std::shared_ptr<const multibody::tree> tree;
    try {
        // One read: the bytes parsed are the bytes whose digest a checkpoint records.
        const std::string text =
            models::read_input_file(u.path, models::max_urdf_bytes, "URDF file");
        if (file != nullptr)
            *file = {std::filesystem::absolute(u.path).lexically_normal().string(),
                     models::content_digest(text)};
        tree = models::parse_urdf(text, u.path, models::base_of(u.base.empty() ? "fixed" : u.base));
    } catch (const std::invalid_argument& e) { // models::urdf_error, models::input_error
        throw usage_error(std::string("--urdf: ") + e.what());
    }
    return tree;
}

std::shared_ptr<const models::model> robot_model_of(const urdf_spec& u,
                                                    checkpoint::input_file* file) {
    return robot_model_of(u, robot_tree_of(u, file));
}

std::shared_ptr<const models::model> robot_model_of(const urdf_spec& u,
                                                    std::shared_ptr<const multibody::tree> tree) {
    const std::vector<std::string> torques =
        u.torques.empty() ? std::vector<std::string>{}
                          : split_list(u.torques, "--torques", "5*sin(t),0,-2*elbow_joint_dot");
    try {
        return std::make_shared<const models::model>(models::robot_model(tree, torques));
    } catch (const std::exception& e) { // a parse error, a name that is not a joint's
        throw usage_error(std::string("--torques: ") + e.what());
    }
}

void add_urdf_option(CLI::App& cmd, urdf_spec& u) {
    cmd.add_option("--urdf", u.path,
                   "urdf: the robot's URDF file (implies --model urdf; see 'varsym models')");
    cmd.add_option("--base", u.base,
                   "urdf: how the root link is held: fixed (bolted to the ground), free "
                   "(position and a unit quaternion) or planar (x, z, pitch about y)")
        ->check(CLI::IsMember({"fixed", "free", "planar"}))
        ->default_str("fixed");
    cmd.add_option("--torques", u.torques,
                   "urdf: joint torques as expressions in t, the joints' names and NAME_dot, "
                   "one per joint, comma-separated [N m or N]");
}

model make_robot_model(std::shared_ptr<parameter_options> po) {
    auto spec = std::make_shared<urdf_spec>();
    const models::model& rm = models::robot_options();
    model m;
    m.name = "urdf";
    m.summary = "your robot from its URDF file (--urdf FILE): joints, inertias, damping, PD";
    std::string own = describe(rm, false);
    const auto cut = own.find("\n  Parameters:");
    m.description =
        "  --urdf FILE: the robot's revolute, continuous and prismatic joints are the\n"
        "  coordinates (fixed joints merge their links); L = 1/2 qdot' M(q) qdot - V(q) from\n"
        "  the links' masses and inertia tensors, derivatives by the recursive algorithms\n"
        "  (docs/robots.md). q: joint positions [rad, m] in depth-first order from the root\n"
        "  link; columns q_JOINT, p_JOINT by the URDF's joint names. Gravity along -z.\n"
        "  Forces: the URDF's joint damping (--no-damping drops it); with --kp a PD controller\n"
        "  on every joint tracking a minimum-jerk move from the start to --target over\n"
        "  --move-time, with gravity compensation unless --no-gravity-compensation; constant\n"
        "  joint torques --torque, or --torques typed in t, the joint names and NAME_dot\n"
        "  (e.g. 5*sin(t)). Columns: energy, work, energy_balance (energy - E0 - work),\n"
        "  limit_violations (joints outside their URDF position limits). Start: --q0 (0),\n"
        "  --v0 (0) or --p0. No period: default --time 5 --steps 5000.\n"
        "  --base free or planar sets the root link moving (docs/robots.md): the base's\n"
        "  coordinates come first (free: base_x, base_y, base_z and the unit quaternion\n"
        "  base_qw, base_qx, base_qy, base_qz; planar: base_x, base_z, base_ry), the lists\n"
        "  --kp, --kd, --target, --torque are per joint after them, and columns give the\n"
        "  base's velocity, the total momenta and the centre of mass." +
        (cut == std::string::npos ? "" : own.substr(cut, own.find("\n  Initial state") - cut));
    m.options = {"--urdf", "--base", "--torques"};
    for (const auto& p : rm.parameters)
        m.options.push_back("--" + p.option_name());
    for (const auto& l : rm.lists)
        m.options.push_back("--" + l.option_name());
    m.add_options = [spec](CLI::App& cmd) { add_urdf_option(cmd, *spec); };
    m.run = [spec, po](const run_setup& s) {
        run_setup with_file = s;
        checkpoint::input_file file;
        const auto tree = robot_tree_of(*spec, &file);
        const auto robot = robot_model_of(*spec, tree);
        if (s.resume) check_resumed_input(*s.resume, file);
        with_file.inputs = {file};
        if (s.animate.empty()) {
            run_model(*robot, with_file, po->values(*robot), po->lists(*robot));
            return;
        }
        const std::vector<double> values = po->values(*robot);
        const models::lists lists = po->lists(*robot);
        run_animated(
            with_file, static_cast<int>(models::robot_coordinates(*tree).size()), false,
            [&](const run_setup& r) { run_model(*robot, r, values, lists); },
            [&](const frame_recorder& f, const Eigen::MatrixXd& q) {
                write_animation(tree, f.t, q, spec->path, s.animate, 0.0, s.mesh_path, s.quiet,
                                models::robot_obstacles(tree, values, lists, q.row(0).transpose()),
                                f.forces);
            });
    };
    return m;
}

} // namespace varsym::cli
