// models/src/robot_target.cpp: a robot frame's target pose at the end of an optimal motion
// (models::frame_target, an optimal::end_function): φ(q) = (o(q) − o*; 2 v/c), o the frame's
// origin, v = ½ vee(A − Aᵀ) = sin θ n and c = √(1 + tr A) = 2 cos(θ/2) for A = R*ᵀR(q), the
// rotation by θ about n (in R*'s frame) from the target orientation to the frame's: the
// origin's miss [m] and 2 sin(θ/2) n (≈ θ n [rad] near the target; unlike sin θ n, zero at
// θ = 0 only). The exact Jacobian from the frame's world Jacobian (multibody::frame_jacobian):
// ∂R/∂q_j = ω̂_j R, so ∂A/∂q_j = R*ᵀ ω̂_j R =: A_j, ∂v = ½ vee(A_j − A_jᵀ), ∂c = tr A_j / (2c).
// See docs/optimal_control.md ("Task-space targets").
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "varsym/models/robot.hpp"
#include "varsym/multibody/algorithms.hpp"

namespace varsym::models {

namespace {

using multibody::mat3;
using multibody::vec3;

/// The vector of the skew part: vee(S) = (S₃₂, S₁₃, S₂₁).
vec3 vee(const mat3& s) {
    return {s(2, 1), s(0, 2), s(1, 0)};
}

const multibody::frame& find_frame(const multibody::tree& r, const std::string& name) {
    const auto f = std::find_if(r.frames.begin(), r.frames.end(),
                                [&](const auto& x) { return x.name == name; });
    if (f != r.frames.end()) return *f;
    std::string known;
    for (const auto& x : r.frames)
        known += (known.empty() ? "" : ", ") + x.name;
    throw std::invalid_argument("no link '" + name + "' in " + r.name + " (its links: " + known +
                                ")");
}

class frame_target_function final : public optimal::end_function {
  public:
    frame_target_function(std::shared_ptr<const multibody::tree> r, multibody::frame f,
                          const vec3& position, const std::optional<mat3>& rotation)
        : r_(std::move(r)), f_(std::move(f)), position_(position), rotation_(rotation) {}

    [[nodiscard]] int dimension() const override { return r_->dof(); }
    [[nodiscard]] int rows() const override { return rotation_ ? 6 : 3; }

    void evaluate(const Eigen::VectorXd& q, Eigen::VectorXd& value,
                  Eigen::MatrixXd* jacobian) const override {
        multibody::workspace w; // a few small vectors per call: this runs once per iteration
        multibody::kinematics(*r_, w, q);
        const multibody::pose x = multibody::frame_pose(w, f_);
        value.resize(rows());
        value.head<3>() = x.origin - position_;
        Eigen::MatrixXd j6; // the frame's world Jacobian: angular rows 0–2, origin rows 3–5
        if (jacobian) multibody::frame_jacobian(*r_, w, f_, j6);
        if (!rotation_) {
            if (jacobian) *jacobian = j6.bottomRows(3);
            return;
        }
        const mat3 a = rotation_->transpose() * x.rotation;
        const vec3 v = 0.5 * vee(a - a.transpose());
        // c → 0 only at θ = π, where |φ_rot| = 2 is largest: floored there.
        const double c = std::max(std::sqrt(std::max(1.0 + a.trace(), 0.0)), 1e-8);
        value.tail<3>() = 2.0 * v / c;
        if (!jacobian) return;
        jacobian->resize(6, r_->dof());
        jacobian->topRows(3) = j6.bottomRows(3);
        for (int j = 0; j < r_->dof(); ++j) {
            const mat3 aj =
                rotation_->transpose() * multibody::skew(vec3(j6.block<3, 1>(0, j))) * x.rotation;
            const vec3 dv = 0.5 * vee(aj - aj.transpose());
            const double dc = aj.trace() / (2.0 * c);
            jacobian->block<3, 1>(3, j) = 2.0 * dv / c - 2.0 * v * dc / (c * c);
        }
    }

  private:
    std::shared_ptr<const multibody::tree> r_;
    multibody::frame f_;
    vec3 position_;
    std::optional<mat3> rotation_;
};

} // namespace

multibody::pose frame_pose_at(const multibody::tree& r, const std::string& frame,
                              const Eigen::VectorXd& q) {
    const multibody::frame& f = find_frame(r, frame);
    if (q.size() != r.dof())
        throw std::invalid_argument("q has " + std::to_string(q.size()) + " entries; " + r.name +
                                    " has " + std::to_string(r.dof()) + " joints");
    multibody::workspace w;
    multibody::kinematics(r, w, q);
    return multibody::frame_pose(w, f);
}

std::shared_ptr<const optimal::end_function>
frame_target(std::shared_ptr<const multibody::tree> r, const std::string& frame,
             const Eigen::Vector3d& position, const std::optional<Eigen::Matrix3d>& rotation) {
    if (!r) throw std::invalid_argument("frame_target: no robot");
    const multibody::frame f = find_frame(*r, frame);
    if (!position.allFinite())
        throw std::invalid_argument("the target position of " + frame + " must be finite");
    if (rotation && !(rotation->allFinite() &&
                      (*rotation * rotation->transpose() - mat3::Identity()).norm() < 1e-9 &&
                      rotation->determinant() > 0.0))
        throw std::invalid_argument("the target orientation of " + frame +
                                    " must be a rotation matrix");
    if (f.body < 0)
        throw std::invalid_argument("link " + frame +
                                    " is fixed to the ground: no joint moves "
                                    "it; target a link the joints move");
    return std::make_shared<frame_target_function>(std::move(r), f, position, rotation);
}

frame_miss frame_target_miss(const multibody::tree& r, const std::string& frame,
                             const Eigen::VectorXd& q, const Eigen::Vector3d& position,
                             const std::optional<Eigen::Matrix3d>& rotation) {
    const multibody::pose x = frame_pose_at(r, frame, q);
    frame_miss out{(x.origin - position).norm(), 0.0};
    if (rotation) {
        const double c = 0.5 * ((rotation->transpose() * x.rotation).trace() - 1.0);
        out.angle = std::acos(std::clamp(c, -1.0, 1.0));
    }
    return out;
}

} // namespace varsym::models
