// tests/family_pendulum.cpp: the family for the pendulum, compiled once (family_instances.hpp).
#include "family_instances.hpp"

VARSYM_INSTANTIATE_GALERKIN_FAMILY(varsym::pendulum::system);
