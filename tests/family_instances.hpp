// tests/family_instances.hpp: the Lobatto/Gauss family (galerkin::fixed_stepper, 16 members) for
// the two systems most tests step, compiled once in family_pendulum.cpp and family_coupled.cpp
// instead of again in every test source (about 2 minutes each at -O3). Include it before the
// first use of galerkin::stepper or with_stepper on these systems.
#pragma once

#include "test_support.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/galerkin.hpp"

VARSYM_EXTERN_GALERKIN_FAMILY(varsym::pendulum::system);
VARSYM_EXTERN_GALERKIN_FAMILY(varsym::separable_system<2, varsym::test::coupled_pendulums>);
