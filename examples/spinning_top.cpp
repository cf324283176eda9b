// examples/spinning_top.cpp: a heavy top on SO(3) with the Lie group variational integrator.
// Started upright with a sideways push, its axis passes through the vertical again and again,
// where Euler angles are singular. R stays a rotation with no projection, and the vertical
// angular momentum and the spin are conserved to round-off (docs/rigid_bodies.md).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <varsym/varsym.hpp>

int main() {
    using namespace varsym;
    const lie::rigid_body top(lie::vec3(1.0, 1.0, 0.5).asDiagonal().toDenseMatrix(), // J [kg m²]
                              lie::vec3(0.0, 0.0, 1.0), // centre of mass on the axis [m]
                              1.0);                     // weight [N]
    lie::body_state x;                                  // R = I: the axis is vertical
    x.pi = top.inertia() * lie::vec3(0.6, 0.0, 5.0);    // Ω: a push and a spin [rad/s]
    const double e0 = top.energy(x), lz0 = lie::rigid_body::spatial_momentum(x)(2);
    const double spin0 = x.pi(2);

    bool ok = true;
    for (const int order : {2, 4, 6}) {
        lie::lgvi stepper(top, 0.001, order);
        lie::body_state y = x;
        double de = 0, dlz = 0, dspin = 0, orth = 0, nearest = 1.0;
        for (int k = 1; k <= 100000; ++k) { // 100 s
            if (!stepper.step(y).converged) {
                std::printf("order %d: step %d did not converge\n", order, k);
                return 1;
            }
            de = std::max(de, std::abs(top.energy(y) - e0) / e0);
            dlz = std::max(dlz, std::abs(lie::rigid_body::spatial_momentum(y)(2) - lz0));
            dspin = std::max(dspin, std::abs(y.pi(2) - spin0));
            orth = std::max(orth, so3::orthogonality_error(y.R));
            if (k > 1000) nearest = std::min(nearest, std::acos(std::min(y.R(2, 2), 1.0)));
        }
        std::printf("order %d, 1e5 steps: energy %.1e, L_z %.1e, spin %.1e, |R^T R - I| %.1e, "
                    "closest to the vertical after 1 s: %.1e rad\n",
                    order, de, dlz, dspin, orth, nearest);
        // Bounded energy (order 2: ~1e-7 here), momenta and R to round-off, and the axis back
        // at the vertical (to within the distance one step travels, h|Ω_1| ~ 6e-4 rad).
        ok = ok && de < 1e-6 && dlz < 1e-13 && dspin < 1e-13 && orth < 1e-14 && nearest < 2e-3;
    }
    std::printf(ok ? "OK\n" : "FAILED\n");
    return ok ? 0 : 1;
}
