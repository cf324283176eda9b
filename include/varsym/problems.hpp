// varsym/problems.hpp: the reference problems with exact solutions or closed forms (pendulum,
// oscillator, Kepler, double pendulum, heavy top, Hénon–Heiles, FPU chain) and the paper's
// experiments. Needs Boost.Math (elliptic functions) besides the core <varsym/varsym.hpp>.
#pragma once

#include "varsym/problems/chain.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/henon_heiles.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/problems/oscillator.hpp"
#include "varsym/problems/paper.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/varsym.hpp"
