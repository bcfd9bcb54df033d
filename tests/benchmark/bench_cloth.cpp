/// @file bench_cloth.cpp
/// Kernel and step benchmarks of the custom engine (Google Benchmark; not part of ctest).
///   BM_spring_forces/<particles per edge>: one full spring + damping force evaluation of the
///     seed cloth at that resolution, with springs_per_second.
///   BM_spring_paths/<path>: the 64 x 64 seed cloth's springs in one force evaluation as in
///     BM_spring_forces, through the grid kernel ("grid") and as a general list (laid out by
///     renumbered()) after a random shuffle of the particle numbers ("shuffled") and after
///     locality_order renumbering of the shuffled ones ("renumbered"); items_per_second
///     counts springs.
///   BM_spring_mesh/<numbering>: the same on a generated irregular mesh with about as many
///     springs, in the generator's numbering and after locality_order.
///   BM_step/<integrator>: one step of the seed scene at the report's h = 1e-4 s
///     (implicit-euler at h = 1/60 s, with its CG iterations per step).
///   BM_newton/<solver>/<particles per edge>: the first 0.3 s (9 steps of h = 1/30 s) of the
///     seed scene at that resolution and the seed's total mass (625 kg) in implicit Euler,
///     newton = "line-search", from rest (the cloth's own motion passes strain 1 at 0.358 s at
///     128 x 128, README), with Newton iterations per step, CG iterations per Newton iteration
///     and sim_s_per_s (simulated seconds per wall second). Solvers cg, block-jacobi-cg,
///     two-level-cg and ldlt (ldlt only at 25 and 64).
///   BM_newton_fixed_forcing/block-jacobi-cg/<particles per edge>: the same with every Newton
///     system solved to cg_tolerance (1e-3), the forcing before adaptive forcing.
///   BM_newton_without_sphere/block-jacobi-cg/128: BM_newton's run with the sphere removed.
///   BM_symplectic/<particles per edge>: one symplectic-euler step of the same scene at
///     h = 1e-5 s (the estimate of its largest stable step at 128), with sim_s_per_s.
///   BM_self_intersection/<flat|folded>/<15|64>: one SelfIntersectionMeter::measure of an n x n
///     grid (spacing 1/(n-1) m, cutoff one spacing), flat or with its upper half folded back over
///     the lower half and through it, with triangles_per_second and the crossings found.

#include <benchmark/benchmark.h>

#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include "cloth/analysis/self_intersection.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/triangle_mesh.hpp"

namespace {

using namespace cloth;

void BM_spring_forces(benchmark::State& state) {
  Scene s = seed_scene();
  s.cloth.nu = s.cloth.nv = static_cast<int>(state.range(0));
  s.held.clear();
  const Model m = build_model(s);
  // a shaken state, so that no spring is at rest and no branch is trivial
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Matrix3X x = m.x0, v = Matrix3X::Zero(3, m.particle_count());
  for (Eigen::Index p = 0; p < x.cols(); ++p)
    for (int r = 0; r < 3; ++r) {
      x(r, p) += u(rng);
      v(r, p) = u(rng);
    }
  Matrix3X f(3, x.cols()), buf(3, x.cols());
  for (auto _ : state) {
    f.setZero();
    benchmark::DoNotOptimize(add_spring_forces(m.springs, x, v, f, buf));
    benchmark::ClobberMemory();
  }
  state.counters["springs"] = m.springs.count();
  state.counters["springs_per_second"] = benchmark::Counter(
      static_cast<double>(m.springs.count()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_spring_forces)->Arg(25)->Arg(64)->Arg(128);

/// Which numbering and kernel BM_spring_paths measures.
enum class SpringPath { grid, shuffled, renumbered };

void BM_spring_paths(benchmark::State& state, SpringPath path) {
  Scene s = seed_scene();
  s.cloth.nu = s.cloth.nv = 64;
  s.held.clear();
  const Model m = build_model(s);
  const int n = m.particle_count();
  // the shaken state of BM_spring_forces
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Matrix3X x = m.x0, v = Matrix3X::Zero(3, n);
  for (Eigen::Index p = 0; p < x.cols(); ++p)
    for (int r = 0; r < 3; ++r) {
      x(r, p) += u(rng);
      v(r, p) = u(rng);
    }
  // particle p becomes new_of_old[p]: a random shuffle, then (renumbered) locality_order's
  std::vector<int> new_of_old(static_cast<size_t>(n));
  std::iota(new_of_old.begin(), new_of_old.end(), 0);
  if (path != SpringPath::grid) std::shuffle(new_of_old.begin(), new_of_old.end(), rng);
  SpringSet springs = path == SpringPath::grid ? m.springs : renumbered(m.springs, new_of_old);
  if (path == SpringPath::renumbered) {
    const std::vector<int> order = locality_order(n, springs.links());
    springs = renumbered(springs, order);
    for (int& q : new_of_old) q = order[static_cast<size_t>(q)];
  }
  Matrix3X xn(3, n), vn(3, n);
  for (int p = 0; p < n; ++p) {
    xn.col(new_of_old[static_cast<size_t>(p)]) = x.col(p);
    vn.col(new_of_old[static_cast<size_t>(p)]) = v.col(p);
  }
  Matrix3X f(3, n), buf(3, n);
  for (auto _ : state) {
    f.setZero();
    benchmark::DoNotOptimize(add_spring_forces(springs, xn, vn, f, buf));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * springs.count());
}
BENCHMARK_CAPTURE(BM_spring_paths, grid, SpringPath::grid);
BENCHMARK_CAPTURE(BM_spring_paths, shuffled, SpringPath::shuffled);
BENCHMARK_CAPTURE(BM_spring_paths, renumbered, SpringPath::renumbered);

/// A generated irregular mesh with about as many springs as the 64 x 64 grid (a 1 m square of
/// 1.7 cm triangles: 24,276 springs against the grid's 23,938), in the generator's numbering
/// ("as_generated", lattice rows) or after locality_order ("renumbered").
void BM_spring_mesh(benchmark::State& state, bool renumber) {
  ShapeSpec spec;
  spec.shape = MeshShape::rectangle;
  spec.edge_length = 0.017;
  spec.center = {0.0, 0.0, 0.0};
  Scene s;
  s.mesh = std::make_shared<const TriangleMesh>(generate_mesh(spec));
  s.cloth.areal_density = 0.2;
  s.cloth.k_structural = 50.0;
  s.cloth.k_bend = 5.0;
  s.cloth.damping = 0.01;
  const Model m = build_model(s);
  const int n = m.particle_count();
  // the model's own springs (as the engine runs them), or renumbered for locality
  SpringSet springs = m.springs;
  std::vector<int> new_of_old(static_cast<size_t>(n));
  std::iota(new_of_old.begin(), new_of_old.end(), 0);
  if (renumber) {
    new_of_old = locality_order(n, springs.links());
    springs = renumbered(springs, new_of_old);
  }
  // the shaken state of BM_spring_forces, in the new numbering
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Matrix3X x(3, n), v(3, n);
  for (int p = 0; p < n; ++p)
    for (int r = 0; r < 3; ++r) {
      x(r, new_of_old[size_t(p)]) = m.x0(r, p) + u(rng);
      v(r, new_of_old[size_t(p)]) = u(rng);
    }
  Matrix3X f(3, n), buf(3, n);
  for (auto _ : state) {
    f.setZero();
    benchmark::DoNotOptimize(add_spring_forces(springs, x, v, f, buf));
    benchmark::ClobberMemory();
  }
  state.counters["springs"] = springs.count();
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * springs.count());
}
BENCHMARK_CAPTURE(BM_spring_mesh, as_generated, false);
BENCHMARK_CAPTURE(BM_spring_mesh, renumbered, true);

void BM_step(benchmark::State& state, Integrator integrator) {
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth cloth(seed_scene(), o);
  const bool large_steps = integrator == Integrator::implicit_euler ||
                           integrator == Integrator::xpbd || integrator == Integrator::projective;
  const double h = large_steps ? 1.0 / 60.0 : 1e-4;
  for (auto _ : state) cloth.step(h);
  const Counters c = cloth.counters();
  state.counters["h"] = h;
  state.counters["force_evals_per_step"] = double(c.force_evals) / double(c.steps);
  if (integrator == Integrator::implicit_euler)
    state.counters["cg_iterations_per_step"] = double(c.cg_iterations) / double(c.steps);
}

void BM_newton(benchmark::State& state, LinearSolver solver, CgForcing forcing, bool sphere) {
  SolverOptions o = line_search_options(solver);
  o.cg_forcing = forcing;
  Scene scene = seed_scene(static_cast<int>(state.range(0)));
  if (!sphere) scene.spheres.clear();
  const double h = 1.0 / 30.0;
  constexpr int kSteps = 9;
  Counters total;
  for (auto _ : state) {
    state.PauseTiming();
    MassSpringCloth cloth(scene, o);
    state.ResumeTiming();
    for (int i = 0; i < kSteps; ++i) cloth.step(h);
    const Counters c = cloth.counters();
    total.steps += c.steps;
    total.newton_iterations += c.newton_iterations;
    total.cg_iterations += c.cg_iterations;
  }
  state.counters["newton_per_step"] = double(total.newton_iterations) / double(total.steps);
  state.counters["cg_per_newton"] =
      double(total.cg_iterations) / double(std::max<std::int64_t>(1, total.newton_iterations));
  state.counters["sim_s_per_s"] =
      benchmark::Counter(kSteps * h, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_symplectic(benchmark::State& state) {
  SolverOptions o;
  o.integrator = Integrator::symplectic_euler;
  MassSpringCloth cloth(seed_scene(static_cast<int>(state.range(0))), o);
  const double h = 1e-5;
  for (auto _ : state) cloth.step(h);
  state.counters["sim_s_per_s"] =
      benchmark::Counter(h, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_symplectic)->Arg(25)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);

void BM_self_intersection(benchmark::State& state, bool folded) {
  const int n = static_cast<int>(state.range(0));
  const double s = 1.0 / (n - 1);
  Matrix3X x(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // the lower half flat in y = 0; the upper half mirrored back over it, shifted by 0.3 s in
      // x and tilted so it passes down through the flat half a quarter of the rows past the fold
      const int half = n / 2;
      const bool upper = folded && j >= half;
      const double z = upper ? (n - 1 - j + 0.3) * s : j * s;
      const double y = upper ? 0.08 * (j - half - n / 4 - 0.5) * s : 0.0;
      x.col(j * n + i) = Vector3((i + (upper ? 0.3 : 0.0)) * s, y, z);
    }
  const SelfIntersectionMeter meter(n * n, grid_triangles(n, n), s);
  SelfIntersection r;
  for (auto _ : state) {
    r = meter.measure(x);
    benchmark::DoNotOptimize(r);
  }
  const auto triangles = static_cast<double>(meter.triangles().size());
  state.counters["triangles"] = triangles;
  state.counters["crossings"] = r.crossings;
  state.counters["work_per_element"] =
      double(r.work) / (n * n + double(meter.edges().size()) + triangles);
  state.counters["triangles_per_second"] =
      benchmark::Counter(triangles, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK_CAPTURE(BM_self_intersection, flat, false)
    ->Arg(15)
    ->Arg(64)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_self_intersection, folded, true)
    ->Arg(15)
    ->Arg(64)
    ->Unit(benchmark::kMillisecond);

// xpbd (10 sweeps) and projective (10 iterations, prefactored) at 1/30 s on the seed scene
void BM_large_step(benchmark::State& state, Integrator integrator) {
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth cloth(seed_scene(static_cast<int>(state.range(0))), o);
  const double h = 1.0 / 30.0;
  cloth.step(h);  // projective factorises on its first step
  for (auto _ : state) cloth.step(h);
  state.counters["sim_s_per_s"] =
      benchmark::Counter(h, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

// BM_step/<integrator>: one step of the seed scene (implicit-euler, xpbd and projective at
// h = 1/60 s, the others at 1e-4 s)
int main(int argc, char** argv) {
  for (const Integrator integrator : all_integrators())
    benchmark::RegisterBenchmark(("BM_step/" + std::string(integrator_name(integrator))).c_str(),
                                 BM_step, integrator)
        ->Unit(benchmark::kMicrosecond);
  for (const LinearSolver solver : {LinearSolver::cg, LinearSolver::block_jacobi_cg,
                                    LinearSolver::two_level_cg, LinearSolver::ldlt}) {
    auto* b = benchmark::RegisterBenchmark(
        ("BM_newton/" + std::string(linear_solver_name(solver))).c_str(), BM_newton, solver,
        CgForcing::adaptive, true);
    b->Arg(25)->Arg(64)->Unit(benchmark::kMillisecond);
    // a factorisation at 128 per edge takes seconds, and a step needs several
    if (solver != LinearSolver::ldlt) b->Arg(128);
  }
  benchmark::RegisterBenchmark("BM_newton_fixed_forcing/block-jacobi-cg", BM_newton,
                               LinearSolver::block_jacobi_cg, CgForcing::fixed, true)
      ->Arg(25)
      ->Arg(64)
      ->Arg(128)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_newton_without_sphere/block-jacobi-cg", BM_newton,
                               LinearSolver::block_jacobi_cg, CgForcing::adaptive, false)
      ->Arg(128)
      ->Unit(benchmark::kMillisecond);
  for (const Integrator integrator : {Integrator::xpbd, Integrator::projective})
    benchmark::RegisterBenchmark(
        ("BM_large_step/" + std::string(integrator_name(integrator))).c_str(), BM_large_step,
        integrator)
        ->Arg(25)
        ->Arg(64)
        ->Arg(128)
        ->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
