// models/src/figure.cpp: the 3-D figures the built-in models share (models/figure.hpp): a rigid
// body about a fixed point, and a planar chain of links.
#include "varsym/models/figure.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "varsym/lie/so3.hpp"

namespace varsym::models {

using multibody::mat3;
using multibody::vec3;

figure_part figure_solid(std::string kind, int body, const vec3& size, const vec3& at,
                         const std::array<double, 4>& rgba, const vec3& axis) {
    figure_part p;
    p.kind = std::move(kind);
    p.body = body;
    p.size = size;
    p.offset.origin = at;
    p.offset.rotation = Eigen::Quaterniond::FromTwoVectors(vec3::UnitZ(), axis).toRotationMatrix();
    p.rgba = rgba;
    return p;
}

namespace {

/// The sides of the box of uniform density whose principal moments of inertia are i (a
/// sorted-free triple), scaled so that its longest side is 1 m: a uniform box of mass m and
/// sides a, b, c has I_1 = m (b² + c²)/12, …, so a² = 6 (I_2 + I_3 − I_1)/m.
vec3 equivalent_box(const vec3& i) {
    vec3 s2;
    for (int k = 0; k < 3; ++k)
        s2(k) = i((k + 1) % 3) + i((k + 2) % 3) - i(k);
    const double top = s2.maxCoeff();
    if (!(top > 0.0)) return vec3::Ones(); // no inertia: a unit cube
    // A flat body (I_3 = I_1 + I_2) has a side 0: drawn 2 % of the longest.
    return (s2 / top).cwiseMax(4e-4).cwiseSqrt();
}

} // namespace

figure rigid_figure(const mat3& inertia, const vec3& com) {
    using namespace figure_colour;
    figure f;
    f.bodies = 1;
    f.coordinates = 3;
    f.place = [](std::span<const double> q, std::span<multibody::pose> poses) {
        poses[0].rotation = so3::from_euler(q[0], q[1], q[2]);
        poses[0].origin = vec3::Zero();
    };
    const double c = com.norm();
    if (c > 0.0) {
        // A top or a 3-D pendulum: the rod from the pivot along c, the disc across it at c.
        const vec3 axis = com / c;
        const vec3 across = axis.unitOrthogonal();
        const double r = 0.45 * c;
        f.parts.push_back(figure_solid("sphere", 0, vec3(0.05 * c, 0, 0), vec3::Zero(), rod));
        f.parts.push_back(
            figure_solid("cylinder", 0, vec3(0.03 * c, 1.2 * c, 0), 0.6 * com, rod, axis));
        f.parts.push_back(figure_solid("cylinder", 0, vec3(r, 0.12 * c, 0), com, body, axis));
        f.parts.push_back(figure_solid("box", 0, vec3(0.12, 0.12, 0.14) * c,
                                       com + 0.98 * r * across, blue, axis));
        f.floor = com.z() >= 0.0 ? 0.0 : -1.3 * c;
        return f;
    }
    // A free body: the box of its inertia along the principal axes, marked on its + faces: the
    // body's axes 1, 2, 3 where J is diagonal, else J's eigenvectors by increasing moment.
    mat3 axes = mat3::Identity();
    vec3 moments = inertia.diagonal();
    if (!inertia.isDiagonal(0.0)) {
        const Eigen::SelfAdjointEigenSolver<mat3> eig(inertia);
        axes = eig.eigenvectors();
        if (axes.determinant() < 0.0) axes.col(2) *= -1.0;
        moments = eig.eigenvalues();
    }
    const vec3 sides = equivalent_box(moments);
    figure_part box = figure_solid("box", 0, sides, vec3::Zero(), body);
    box.offset.rotation = axes;
    f.parts.push_back(box);
    const std::array<std::array<double, 4>, 3> marks{red, green, blue};
    for (int k = 0; k < 3; ++k) {
        const vec3 a = axes.col(k);
        f.parts.push_back(figure_solid("box", 0, vec3(0.16, 0.16, 0.04), (sides(k) / 2 + 0.01) * a,
                                       marks[static_cast<std::size_t>(k)], a));
    }
    f.floor = -(sides.norm() / 2 + 0.2);
    return f;
}

figure planar_links_figure(const std::vector<double>& lengths, const std::vector<double>& masses) {
    using namespace figure_colour;
    if (lengths.size() != masses.size() || lengths.empty())
        throw std::invalid_argument("planar_links_figure: one length and one mass per link");
    figure f;
    const auto n = static_cast<int>(lengths.size());
    f.bodies = n;
    f.coordinates = n;
    const double reach = [&] {
        double s = 0.0;
        for (double l : lengths)
            s += l;
        return s;
    }();
    const double heaviest = *std::max_element(masses.begin(), masses.end());
    const double thick = 0.025 * reach;
    f.parts.push_back(figure_solid("box", -1, vec3(0.12, 0.12, 0.06) * reach,
                                   vec3(0, 0, 0.03 * reach), rod)); // the fixed base
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        // Link i's frame: at its joint, z along the link.
        f.parts.push_back(figure_solid("sphere", i, vec3(1.3 * thick, 0, 0), vec3::Zero(), rod));
        f.parts.push_back(figure_solid("capsule", i, vec3(thick, lengths[k], 0),
                                       vec3(0, 0, lengths[k] / 2), body));
        if (masses[k] > 0.0 && heaviest > 0.0) // a ball of volume ∝ m, the heaviest 0.07 reach
            f.parts.push_back(figure_solid(
                "sphere", i, vec3(0.07 * reach * std::cbrt(masses[k] / heaviest), 0, 0),
                vec3(0, 0, lengths[k]), red));
    }
    f.floor = -1.1 * reach;
    f.place = [lengths](std::span<const double> q, std::span<multibody::pose> poses) {
        vec3 joint = vec3::Zero();
        for (std::size_t i = 0; i < lengths.size(); ++i) {
            // The link points along (sin θ, 0, −cos θ): z turned by π − θ about y.
            poses[i].rotation =
                Eigen::AngleAxisd(std::numbers::pi - q[i], vec3::UnitY()).toRotationMatrix();
            poses[i].origin = joint;
            joint += lengths[i] * vec3(std::sin(q[i]), 0.0, -std::cos(q[i]));
        }
    };
    return f;
}

} // namespace varsym::models
