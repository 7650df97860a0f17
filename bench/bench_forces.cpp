// Throughput of the point-primitive force kernels (docs/performance.md): PointPrimitiveEnergy::forces,
// PointPrimitiveEnergy::hessian_product, one ExplicitIntegrator::substep and one EnergyHessian refill, on
// jittered box lattices of about 1k, 10k and 100k nodes (h = 2 Delta, SVK, stabiliser alpha 0.1: the library
// defaults).
//
// Arguments: {nodes per axis, OpenMP threads}. Counters:
//   N            nodes
//   K            mean neighbours per node (pairs / N)
//   ns_per_node  wall time per call / N, ns
//   ns_per_pair  wall time per call / #neighbour pairs, ns (the docs/performance.md figure of merit)
// Times are wall-clock (UseRealTime), since the kernels run on an OpenMP team.
//
// Run: build-bench/bench/vascsim_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/energy_hessian.hpp"
#include "vascsim/model/explicit_model.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/model/problem.hpp"
#include "vascsim/model/stability.hpp"

namespace {

using namespace vascsim;

constexpr double kSpacing = 1e-3;  // lattice spacing Delta, m
constexpr double kJitter = 0.05;   // node jitter, fraction of Delta

// One benchmark body: the discretisation, energy and problem, plus a deformed configuration x and a
// direction v for the Hessian product. Built once per size, outside every timed loop.
struct Case {
  std::unique_ptr<Discretization> disc;
  std::unique_ptr<PointPrimitiveEnergy> energy;
  std::unique_ptr<Problem> problem;
  Vec3Array x, v;
  double dt = 0.0;
  double nodes = 0.0, pairs = 0.0;
};

const Case& get_case(int nodes_per_axis) {
  static std::map<int, std::unique_ptr<Case>> cache;
  auto& slot = cache[nodes_per_axis];
  if (slot) return *slot;

  auto c = std::make_unique<Case>();
  const int cells = nodes_per_axis - 1;
  BoxSpec box;
  box.min_m = Vec3::Zero();
  box.max_m = Vec3::Constant(cells * kSpacing);
  box.cells = Eigen::Vector3i::Constant(cells);
  box.jitter = kJitter;
  box.seed = 7;
  const NodeCloud cloud = make_box(box);
  c->disc = std::make_unique<Discretization>(cloud, Material{});  // h = 2 Delta, tet-partition volumes
  c->energy = std::make_unique<PointPrimitiveEnergy>(*c->disc, EnergyOptions{});  // SVK, alpha_hg = 0.1

  // A cantilever: bottom face (z = 0 layer) fixed, gravity on; the substep then exercises the
  // constrained branch as well as the free update.
  Region base;
  base.name = "base";
  base.bc = RegionBcType::Fixed;
  const Vec3Array& X = c->disc->rest_positions();
  for (Index i = 0; i < c->disc->num_nodes(); ++i)
    if (X[i].z() < 0.5 * kSpacing) base.nodes.push_back(i);
  c->problem = std::make_unique<Problem>(*c->energy, std::vector<Region>{base}, Vec3(0.0, 0.0, -9.81));
  c->dt = cfl_time_step(*c->energy, 0.2);  // well inside the stability limit: the state stays bounded

  // Deformed state: 1 % of Delta random displacement (the kernels are branch-free in x; this only
  // keeps the numbers non-trivial). v: a random unit-scale direction.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  c->x = X;
  c->v.resize(X.size());
  for (std::size_t i = 0; i < X.size(); ++i) {
    c->x[i] += 0.01 * kSpacing * Vec3(uni(rng), uni(rng), uni(rng));
    c->v[i] = Vec3(uni(rng), uni(rng), uni(rng));
  }
  c->nodes = static_cast<double>(c->disc->num_nodes());
  c->pairs = static_cast<double>(c->disc->pairs().col.size());
  slot = std::move(c);
  return *slot;
}

void set_counters(benchmark::State& state, const Case& c) {
  using benchmark::Counter;
  state.counters["N"] = c.nodes;
  state.counters["K"] = c.pairs / c.nodes;
  state.counters["threads"] = static_cast<double>(state.range(1));
  // Rate counters divide by the elapsed time; kInvert turns items/s into s/item, and the 1e-9 scale
  // turns seconds into nanoseconds.
  state.counters["ns_per_node"] =
      Counter(c.nodes * 1e-9, Counter::kIsIterationInvariantRate | Counter::kInvert);
  state.counters["ns_per_pair"] =
      Counter(c.pairs * 1e-9, Counter::kIsIterationInvariantRate | Counter::kInvert);
}

void BM_Forces(benchmark::State& state) {
  const Case& c = get_case(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Vec3Array f;
  c.energy->forces(c.x, f);  // warm-up: sizes f, faults in the pages
  for (auto _ : state) {
    const double U = c.energy->forces(c.x, f);
    benchmark::DoNotOptimize(U);
    benchmark::DoNotOptimize(f.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, c);
}

void BM_HessianProduct(benchmark::State& state) {
  const Case& c = get_case(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Vec3Array out;
  c.energy->hessian_product(c.x, c.v, out);
  for (auto _ : state) {
    c.energy->hessian_product(c.x, c.v, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, c);
}

// One CG iteration's product: the linearisation (F_i, S_i per node) is built once per Newton step and reused.
void BM_HessianProductLinearized(benchmark::State& state) {
  const Case& c = get_case(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Vec3Array out;
  const auto lin = c.energy->linearize(c.x);
  c.energy->hessian_product(lin, c.v, out);
  for (auto _ : state) {
    c.energy->hessian_product(lin, c.v, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, c);
}

// One numeric refill of the assembled Hessian (model/energy_hessian.hpp), the preconditioner quasi_static
// refactors: the full matrix, and the block lower triangle a Cholesky factorisation reads, which computes
// only its blocks. Third argument: 1 lower triangle only, 0 full. The 46^3 size is left out (its full Hessian
// takes several GB).
void BM_HessianRefill(benchmark::State& state) {
  const Case& c = get_case(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const bool lower = state.range(2) != 0;
  EnergyHessian H(*c.energy, {HessianStencil::Full, false, lower, CompactLumping::Polar});
  H.assemble(c.x);
  for (auto _ : state) {
    H.assemble(c.x);
    benchmark::DoNotOptimize(H.matrix().valuePtr());
    benchmark::ClobberMemory();
  }
  set_counters(state, c);
  state.counters["lower_only"] = lower ? 1.0 : 0.0;
}

void BM_ExplicitSubstep(benchmark::State& state) {
  const Case& c = get_case(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  ExplicitIntegrator integ(*c.problem, c.dt, 10.0);
  integ.positions() = c.x;  // start deformed; the integrator then evolves it
  integ.substep(1.0);
  for (auto _ : state) {
    integ.substep(1.0);
    benchmark::DoNotOptimize(integ.positions().data());
    benchmark::ClobberMemory();
  }
  for (const Vec3& p : integ.positions())
    if (!p.allFinite()) {
      state.SkipWithError("substep state became non-finite (dt above the stability limit?)");
      break;
    }
  set_counters(state, c);
}

// {nodes per axis, threads}: 10^3 = 1,000, 22^3 = 10,648, 46^3 = 97,336 nodes.
void sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n_axis", "threads"});
  for (int n : {10, 22, 46})
    for (int t : {1, 2}) b->Args({n, t});
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Forces)->Apply(sizes);
BENCHMARK(BM_HessianProduct)->Apply(sizes);
BENCHMARK(BM_HessianProductLinearized)->Apply(sizes);
BENCHMARK(BM_ExplicitSubstep)->Apply(sizes);
BENCHMARK(BM_HessianRefill)
    ->ArgNames({"n_axis", "threads", "lower"})
    ->ArgsProduct({{10, 22}, {1, 2}, {0, 1}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
