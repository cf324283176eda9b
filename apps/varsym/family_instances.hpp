// apps/varsym/family_instances.hpp: the Lobatto/Gauss family (16 fixed-size steppers) for the
// pendulum, which the run, paper, converge and bench commands all step, compiled once in
// family_instances.cpp instead of in each of them (about 2 minutes each at -O3).
#pragma once

#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/galerkin.hpp"

VARSYM_EXTERN_GALERKIN_FAMILY(varsym::pendulum::system);
