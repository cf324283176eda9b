// varsym/varsym.hpp: umbrella header for the varsym library.
#pragma once

#include "varsym/diagnostics/convergence.hpp"
#include "varsym/diagnostics/error_norms.hpp"
#include "varsym/diagnostics/symplecticity.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/paper.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/paper_reference.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/solvers/stage_equation.hpp"
#include "varsym/systems/separable.hpp"
#include "varsym/types.hpp"
