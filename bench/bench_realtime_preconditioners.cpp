// The pieces of a real-time frame of the implicit model on the real-time vein (scenes/realtime/
// hand-dorsal-vein-catheter.json: 0.3 mm along the wall, 3 layers, 5,712 nodes), each against the one it
// replaces (docs/performance.md, "Real time at hand speed"):
//   BM_RealtimeHessianProduct       the Newton operator's product K v: double precision (the energy's
//   matrix-free
//                                   product) against SinglePrecisionHessian (assembled per-node tangents,
//                                   floats);
//   BM_RealtimePreconditionerApply  one application: the meshless factor's float solves against one V-cycle
//   of the
//                                   wall multigrid (smoothing with the float operator, coarse solve,
//                                   smoothing);
//   BM_RealtimePreconditionerRefresh its refresh at a new state: the factor's numeric refactorisation against
//   the
//                                   multigrid's level build (tangents, smoother blocks, Galerkin coarse
//                                   matrix and its factor).
// Arguments {variant, OpenMP threads}: variant 0 is the one replaced, 1 the one in use. Counter ns_per_pair:
// wall time per call over the neighbour pairs (the product's figure of merit; docs/performance.md); and
// stabilizer_nnz, the entries of the stabiliser's 2-hop matrix the float product also applies. The state
// is the rest configuration with a 10 um smooth perturbation (the costs do not depend on the deformation).
//
// Run: build/bench/vascsim_bench --benchmark_filter=Realtime --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>
#include <omp.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <memory>

#include "vascsim/core/blas_control.hpp"
#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/meshless_factor.hpp"
#include "vascsim/model/single_precision_hessian.hpp"
#include "vascsim/model/stabilizer_matrix.hpp"
#include "vascsim/model/wall_multigrid.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

using namespace vascsim;

constexpr double kInvH2 = 3600.0;  // the inertia shift of 60 frames/s, 1/s^2

struct RealtimeCase {
  std::unique_ptr<Simulation> sim;
  std::unique_ptr<FreeDofs> free;
  std::unique_ptr<ContactActiveSet> contacts;
  Vec3Array x, v;
  double pairs = 0.0;
};

// x with every node moved by a micrometre along x: another state for the same costs.
Vec3Array shifted(const Vec3Array& x) {
  Vec3Array y = x;
  for (Vec3& p : y) p.x() += 1e-6;
  return y;
}

const RealtimeCase& realtime_case() {
  static std::unique_ptr<RealtimeCase> c;
  if (c) return *c;
  spdlog::set_level(spdlog::level::warn);
  c = std::make_unique<RealtimeCase>();
  c->sim = std::make_unique<Simulation>(
      load_scene(std::string(VASCSIM_SOURCE_DIR) + "/scenes/realtime/hand-dorsal-vein-catheter.json", {}));
  const Problem& p = c->sim->problem();
  c->free = std::make_unique<FreeDofs>(p);
  c->contacts = std::make_unique<ContactActiveSet>(p, *c->free);
  c->x = p.discretization().rest_positions();
  for (auto& q : c->x) q += 1e-5 * Vec3(std::sin(q.x() * 1e3), std::cos(q.z() * 2e3), std::sin(q.y() * 3e3));
  c->v.assign(c->x.size(), Vec3::Ones());
  c->pairs = static_cast<double>(p.discretization().pairs().col.size());
  return *c;
}

void set_counters(benchmark::State& state, const RealtimeCase& c) {
  state.counters["N"] = static_cast<double>(c.x.size());
  state.counters["threads"] = static_cast<double>(state.range(1));
  state.counters["ns_per_pair"] = benchmark::Counter(
      c.pairs * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_RealtimeHessianProduct(benchmark::State& state) {
  const RealtimeCase& c = realtime_case();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const PointPrimitiveEnergy& energy = c.sim->problem().energy();
  Vec3Array out;
  if (state.range(0) == 0) {
    const auto lin = energy.linearize(c.x);
    for (auto _ : state) {
      energy.hessian_product(lin, c.v, out);
      benchmark::DoNotOptimize(out.data());
    }
  } else {
    SinglePrecisionHessian single(energy);
    single.linearize(c.x);
    if (energy.stabilizer_matrix())
      state.counters["stabilizer_nnz"] = energy.stabilizer_matrix()->matrix().nonZeros();
    for (auto _ : state) {
      single.product(c.v, out);
      benchmark::DoNotOptimize(out.data());
    }
  }
  set_counters(state, c);
}

void BM_RealtimePreconditionerApply(benchmark::State& state) {
  const RealtimeCase& c = realtime_case();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  set_blas_threads(1);
  const Problem& p = c.sim->problem();
  Vec3Array z;
  if (state.range(0) == 0) {
    MeshlessFactorOptions o;
    o.inv_h2 = kInvH2;
    MeshlessFactor factor(p, *c.free, o);
    factor.refactor(c.x);
    for (auto _ : state) benchmark::DoNotOptimize(factor.apply(c.v, z));
    state.counters["nnz_L"] = factor.stats().nnz_l;
  } else {
    WallMultigridOptions o;
    o.inv_h2 = kInvH2;
    WallMultigrid mg(p, *c.free, *c.contacts, o);
    mg.install(mg.build_level(c.x));
    SinglePrecisionHessian single(p.energy());
    single.linearize(c.x);
    const NewtonOperator op = [&](const Vec3Array& a, Vec3Array& b) {
      single.product(a, b, ProductForm::Smoothing);
    };
    mg.set_operator(&op);
    for (auto _ : state) benchmark::DoNotOptimize(mg.apply(c.v, z));
    mg.set_operator(nullptr);
  }
  set_counters(state, c);
}

void BM_RealtimePreconditionerRefresh(benchmark::State& state) {
  const RealtimeCase& c = realtime_case();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  set_blas_threads(1);
  const Problem& p = c.sim->problem();
  if (state.range(0) == 0) {
    MeshlessFactorOptions o;
    o.inv_h2 = kInvH2;
    MeshlessFactor factor(p, *c.free, o);
    factor.refactor(c.x);  // the symbolic analysis, done once per session
    for (auto _ : state) factor.refactor(c.x);
  } else {
    WallMultigridOptions o;
    o.inv_h2 = kInvH2;
    WallMultigrid mg(p, *c.free, *c.contacts, o);
    std::unique_ptr<WallMultigrid::Level> level = mg.build_level(c.x);  // likewise
    for (auto _ : state) level = mg.build_level(c.x, std::move(level));
  }
  set_counters(state, c);
}

// The fixed costs of a frame, besides its CG iterations: the internal forces of a residual (variant 0: double
// precision, the stabiliser's 2-hop matrix included, no energy; variant 1: in float, SinglePrecisionHessian's
// linearisation at the state and its forces, as a real-time residual takes them) and the float operator's
// linearisation at a new state (every node's tangent). The float runs alternate between two states: a
// linearisation at the state of the last one is skipped.
void BM_RealtimeForces(benchmark::State& state) {
  const RealtimeCase& c = realtime_case();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const PointPrimitiveEnergy& energy = c.sim->problem().energy();
  Vec3Array f;
  if (state.range(0) == 0) {
    for (auto _ : state) {
      energy.forces(c.x, f, false);
      benchmark::DoNotOptimize(f.data());
    }
  } else {
    SinglePrecisionHessian single(energy);
    const Vec3Array x[2] = {c.x, shifted(c.x)};
    int k = 0;
    for (auto _ : state) {
      single.linearize(x[k ^= 1]);
      single.forces(f);
      benchmark::DoNotOptimize(f.data());
    }
  }
  set_counters(state, c);
}

void BM_RealtimeLinearize(benchmark::State& state) {
  const RealtimeCase& c = realtime_case();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  SinglePrecisionHessian single(c.sim->problem().energy());
  const Vec3Array x[2] = {c.x, shifted(c.x)};
  int k = 0;
  for (auto _ : state) single.linearize(x[k ^= 1]);
  set_counters(state, c);
}

void threads_only(benchmark::internal::Benchmark* b) {
  b->ArgNames({"variant", "threads"})
      ->ArgsProduct({{1}, {1, 2}})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

void variants(benchmark::internal::Benchmark* b) {
  b->ArgNames({"variant", "threads"})
      ->ArgsProduct({{0, 1}, {1, 2}})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_RealtimeHessianProduct)->Apply(variants);
BENCHMARK(BM_RealtimePreconditionerApply)->Apply(variants);
BENCHMARK(BM_RealtimePreconditionerRefresh)->Apply(variants)->Iterations(3);
BENCHMARK(BM_RealtimeForces)->Apply(variants);
BENCHMARK(BM_RealtimeLinearize)->Apply(threads_only);

}  // namespace
