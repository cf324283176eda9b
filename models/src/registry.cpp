// models/src/registry.cpp: the registry of built-in models. Adding a model is its file in this
// folder (defining `model NAME()` in varsym::models::defs) and one line in the list below, in
// the order `varsym models` shows them.
#include "varsym/models/model.hpp"

#define VARSYM_MODEL_LIST(X)                                                                       \
    X(pendulum)                                                                                    \
    X(oscillator)                                                                                  \
    X(kepler)                                                                                      \
    X(henon_heiles)                                                                                \
    X(double_pendulum)                                                                             \
    X(spring_pendulum)                                                                             \
    X(heavy_top)                                                                                   \
    X(cart_pole)                                                                                   \
    X(acrobot)                                                                                     \
    X(chain)                                                                                       \
    X(arm)                                                                                         \
    X(four_bar)                                                                                    \
    X(slider_crank)                                                                                \
    X(spherical_pendulum)                                                                          \
    X(rigid_body)                                                                                  \
    X(top)                                                                                         \
    X(pendulum_3d)

namespace varsym::models {

namespace defs {
#define VARSYM_DECLARE_MODEL(name) model name();
VARSYM_MODEL_LIST(VARSYM_DECLARE_MODEL)
#undef VARSYM_DECLARE_MODEL
} // namespace defs

const std::vector<model>& registry() {
#define VARSYM_MAKE_MODEL(name) defs::name(),
    static const std::vector<model> all = [] {
        std::vector<model> list{VARSYM_MODEL_LIST(VARSYM_MAKE_MODEL)};
        for (model& m : list) { // the default start, as the model completes it
            const problem pr = m.make(m.defaults(), {}, models::lists(m.lists.size()));
            m.q0 = pr.q0;
            m.p0 = pr.p0;
        }
        return list;
    }();
#undef VARSYM_MAKE_MODEL
    return all;
}

} // namespace varsym::models
