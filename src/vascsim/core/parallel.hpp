#pragma once
// When a loop over nodes is worth an OpenMP parallel region.

#include "vascsim/core/types.hpp"

namespace vascsim {

/// Below this many nodes one thread is faster: a fork/join (and, in Gauss-Seidel sweeps, a barrier per
/// colour) costs more than the work it splits, and on a loaded 2-core machine two threads were measured
/// 5-16x slower than one on small clouds (docs/architecture.md, "Threads").
constexpr Index kParallelMinNodes = 2048;

}  // namespace vascsim
