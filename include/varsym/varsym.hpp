// varsym/varsym.hpp: the core of the varsym library: systems, quadrature and the family's tables,
// the schemes and their steppers, Newton, the drivers and run state, and the diagnostics.
// Reference problems with exact solutions are in <varsym/problems.hpp>; the test oracles (the
// paper's full Newton systems, Lobatto IIIA–IIIB) in varsym/reference/.
#pragma once

#include "varsym/autodiff/reverse.hpp"
#include "varsym/autodiff/second_order.hpp"
#include "varsym/diagnostics/convergence.hpp"
#include "varsym/diagnostics/error_norms.hpp"
#include "varsym/diagnostics/stability.hpp"
#include "varsym/diagnostics/symplecticity.hpp"
#include "varsym/integrate.hpp"
#include "varsym/lie/lgvi.hpp"
#include "varsym/lie/rigid_body.hpp"
#include "varsym/lie/so3.hpp"
#include "varsym/quadrature/rules.hpp"
#include "varsym/run/observers.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/tableau.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/solvers/stage_equation.hpp"
#include "varsym/solvers/tridiagonal.hpp"
#include "varsym/stepper.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"
#include "varsym/types.hpp"
#include "varsym/version.hpp"
