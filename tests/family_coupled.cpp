// tests/family_coupled.cpp: the family for the coupled pendulums of test_support.hpp, compiled
// once (family_instances.hpp).
#include "family_instances.hpp"

VARSYM_INSTANTIATE_GALERKIN_FAMILY(varsym::separable_system<2, varsym::test::coupled_pendulums>);
