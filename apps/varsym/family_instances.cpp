// apps/varsym/family_instances.cpp: the pendulum's family, compiled once (family_instances.hpp).
#include "family_instances.hpp"

VARSYM_INSTANTIATE_GALERKIN_FAMILY(varsym::pendulum::system);
