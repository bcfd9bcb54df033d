#include "harness/sweeps/accuracy_plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "cloth/analysis/linear_stability.hpp"
#include "cloth/model/constants.hpp"
#include "cloth/model/integrator.hpp"
#include "cloth/model/model.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/user_error.hpp"
#include "harness/scenario/engine_refusal.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_overrides.hpp"
#include "harness/scenario/scenario_writer.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

namespace {

using cloth::kInf;

/// The time-step study's reference takes at most this fraction of rk4's predicted limit, so
/// that its error-floor run at twice its step stays at half of it (a stretched, moving cloth is
/// stiffer than the rest state the prediction is for).
constexpr double kReferenceLimitFraction = 0.25;

std::string join_key(const std::string& a, const std::string& b, const std::string& c) {
  return a + "," + b + "," + c;
}

std::string grid_name(int nu, int nv) {
  return std::to_string(nu) + " x " + std::to_string(nv);
}

/// Throws unless dt divides the scenario's frame_interval (frames must land on steps); hint
/// closes the message, saying what to give instead.
void check_divides(const Scenario& sc, double dt, const std::string& what,
                   const std::string& hint = "every swept dt must: give --dts that divide it") {
  const double r = sc.frame_interval / dt;
  const double n = std::round(r);
  // std::invalid_argument, not UserError: the accuracy tests expect this type
  if (!(dt > 0) || !std::isfinite(r) || n < 1 || std::abs(r - n) > 1e-9 * r)
    throw UserError(what + ": dt = " + format_double(dt) + " s does not divide frame_interval = " +
                    format_double(sc.frame_interval) + " s of " + sc.source + " (" + hint + ")");
  if (sc.duration / dt > kMaxSteps)
    throw UserError(what + ": dt = " + format_double(dt) + " s would take duration / dt = " +
                    format_double(sc.duration / dt) + " steps, more than " +
                    format_double(kMaxSteps) + "; give larger --dts or fewer --halvings");
}

/// Throws UserError for an option out of range.
void check_options(const Scenario& sc, const AccuracyOptions& o) {
  if (o.out_dir.empty()) throw UserError("accuracy: no output folder given");
  if (o.dts.empty() && o.halvings < 1)
    throw UserError("--halvings " + std::to_string(o.halvings) +
                    ": expected at least 1 time step per engine");
  // each halving doubles the steps: past 60 no run could be made (kMaxSteps < 2^30)
  if (o.dts.empty() && o.halvings > 60)
    throw UserError("--halvings " + std::to_string(o.halvings) +
                    ": expected at most 60 (each halves dt; runs of more than " +
                    format_double(kMaxSteps) + " steps are refused)");
  if (o.repeats < 1) throw UserError("--repeats " + std::to_string(o.repeats) + ": expected >= 1");
  if (o.shard.sharded() && !o.resolutions.empty())
    throw UserError("--shard " + o.shard.text() +
                    " with --resolutions: only the time-step study can be sharded; run the "
                    "resolution study without --shard");
  for (int r : o.resolutions)
    if (r < 2)
      throw UserError("--resolutions: expected grids of at least 2 x 2, got " + std::to_string(r));
  if (!o.resolutions.empty() && sc.scene.mesh)
    throw UserError("--resolutions: " + sc.source +
                    "'s cloth is a triangle mesh, and --resolutions sets a grid's particles; "
                    "compare a generated shape's resolutions with clothbench map --vary "
                    "cloth.generate.edge_length=...");
  for (size_t k = 0; k < sc.constraints.size(); ++k)
    if (!o.resolutions.empty() && sc.constraints[k].select == "indices")
      throw UserError(
          "--resolutions: constraint " + std::to_string(k) + " of " + sc.source +
          " selects particles by grid indices, which do not carry over to another grid (select "
          "them by corners, edge:... or disk to compare resolutions)");
}

/// The engines the options name, in scenario order; throws for a name the scenario lacks.
std::vector<EngineSpec> selected_engines(const Scenario& sc, const AccuracyOptions& o) {
  for (const std::string& name : o.engines) {
    if (std::none_of(sc.engines.begin(), sc.engines.end(),
                     [&](const EngineSpec& e) { return e.name == name; })) {
      std::string known;
      for (const EngineSpec& e : sc.engines) known += (known.empty() ? "" : ", ") + e.name;
      throw UserError("--engine " + name + ": no such engine in " + sc.source +
                      " (engines: " + known + ")");
    }
  }
  std::vector<EngineSpec> out;
  for (const EngineSpec& e : sc.engines)
    if (o.engines.empty() || std::count(o.engines.begin(), o.engines.end(), e.name) > 0)
      out.push_back(e);
  return out;
}

/// The integrators the options name (all when none), in cloth::all_integrators() order.
std::vector<cloth::Integrator> selected_integrators(const AccuracyOptions& o) {
  std::vector<cloth::Integrator> out;
  for (cloth::Integrator i : cloth::all_integrators())
    if (o.integrators.empty() || std::count(o.integrators.begin(), o.integrators.end(), i) > 0)
      out.push_back(i);
  return out;
}

/// The integrators swept for engine e: the selected ones for a custom engine, else none.
std::vector<std::optional<cloth::Integrator>> own_integrators(
    const EngineSpec& e, const std::vector<cloth::Integrator>& integrators) {
  if (e.kind != EngineKind::custom) return {std::nullopt};
  return {integrators.begin(), integrators.end()};
}

/// The time steps swept for engine e, largest first.
std::vector<double> swept_dts(const Scenario& sc, const EngineSpec& e, const AccuracyOptions& o) {
  std::vector<double> dts = o.dts;
  if (dts.empty())
    for (int k = 0; k < o.halvings; ++k) dts.push_back(e.dt / std::ldexp(1.0, k));
  std::sort(dts.begin(), dts.end(), std::greater<double>());
  dts.erase(std::unique(dts.begin(), dts.end()), dts.end());
  for (double dt : dts) check_divides(sc, dt, "engine " + e.name);
  return dts;
}

/// The custom engine whose options the reference borrows: the scenario's reference engine when
/// it is custom, else its first custom engine; nullptr when it has none.
const EngineSpec* reference_base(const Scenario& sc) {
  if (sc.engines.empty()) return nullptr;
  const EngineSpec& r = sc.engines[static_cast<size_t>(sc.reference_index())];
  if (r.kind == EngineKind::custom) return &r;
  for (const EngineSpec& e : sc.engines)
    if (e.kind == EngineKind::custom) return &e;
  return nullptr;
}

double total_mass(const Scenario& sc) {
  const cloth::ClothParams& cp = sc.scene.cloth;
  if (cp.areal_density > 0) return cp.areal_density * cp.size_u * cp.size_v;
  return cp.total_mass > 0 ? cp.total_mass : cp.particle_mass * cp.nu * cp.nv;
}

std::string rerun_at_grid(const EngineSpec& e, int r, double mass) {
  return "--set cloth.particles=[" + std::to_string(r) + "," + std::to_string(r) + "] " +
         "--set cloth.total_mass=" + format_double(mass) + " " + rerun_overrides(e);
}

/// The time-step study: engine, then integrator, then dt from the largest; returns the
/// smallest swept dt.
double plan_time_steps(const Scenario& sc, const AccuracyOptions& o,
                       const std::vector<EngineSpec>& engines,
                       const std::vector<cloth::Integrator>& integrators, AccuracyPlan& plan) {
  double smallest_dt = kInf;
  for (const EngineSpec& e : engines) {
    plan.engine_names.push_back(e.name);
    const std::vector<double> dts = swept_dts(sc, e, o);
    smallest_dt = std::min(smallest_dt, dts.back());
    for (const std::optional<cloth::Integrator>& integrator : own_integrators(e, integrators))
      for (double dt : dts) {
        AccuracyConfig c;
        c.spec = with_integrator_and_dt(e, integrator, dt);
        c.integrator = integrator;
        c.key = join_key(e.name, integrator_label(integrator), format_double(dt));
        c.rerun = rerun_overrides(c.spec);
        plan.dt_keys.push_back(c.key);
        plan.configs.push_back(std::move(c));
      }
  }
  return smallest_dt;
}

/// The base engine of the references, and the words that name it.
EngineSpec reference_spec(const Scenario& sc, std::string* words) {
  const EngineSpec* base = reference_base(sc);
  EngineSpec spec;
  spec.name = base ? base->name : "reference";
  if (base) spec = *base;
  *words = base ? "custom engine " + base->name + "'s options" : "default custom-engine options";
  return spec;
}

/// rk4's predicted stability limit (s) on sc's scene.
double rk4_predicted_limit(const Scenario& sc) {
  return cloth::predicted_stable_dt(cloth::Integrator::rk4,
                                    cloth::linear_spectrum(cloth::build_model(sc.scene)));
}

/// A reference's rk4 step on the grid of `grid`: `wanted`, or, when that is past
/// kReferenceLimitFraction of rk4's predicted limit there (implicit engines at large steps),
/// the largest step within it that divides a frame. *why says which, `wanted_words` naming
/// where `wanted` came from.
double reference_dt(const Scenario& grid, double wanted, const std::string& wanted_words,
                    std::string* why) {
  *why = wanted_words;
  const double rk4_limit = rk4_predicted_limit(grid);
  if (wanted <= kReferenceLimitFraction * rk4_limit) return wanted;
  *why = "within a quarter of rk4's predicted limit " + format_double(rk4_limit) +
         " s and dividing a frame; " + wanted_words + ", " + format_double(wanted) +
         " s, is past it";
  return grid.frame_interval /
         std::ceil(grid.frame_interval / (kReferenceLimitFraction * rk4_limit));
}

/// The user's --reference-dt, refused unless it is as fine as the finest swept step and
/// within a quarter of rk4's predicted limit (past it rk4 is no reference).
double chosen_reference_dt(const Scenario& sc, double dt, double smallest_dt) {
  if (dt > smallest_dt * (1 + 1e-12))
    throw UserError("--reference-dt " + format_double(dt) +
                    ": a reference must be at least as fine as the steps it judges; the "
                    "smallest swept dt is " +
                    format_double(smallest_dt) + " s");
  const double rk4_limit = rk4_predicted_limit(sc);
  if (dt > kReferenceLimitFraction * rk4_limit)
    throw UserError("--reference-dt " + format_double(dt) +
                    ": past a quarter of rk4's predicted limit " + format_double(rk4_limit) +
                    " s on this scene; give at most " +
                    format_double(kReferenceLimitFraction * rk4_limit) + " s");
  check_divides(
      sc, dt, "--reference-dt",
      "e.g. " + format_double(sc.frame_interval / std::ceil(sc.frame_interval / dt)) + " s does");
  return dt;
}

/// The time-step study's reference: the custom engine with rk4 well below every swept dt.
void plan_reference(const Scenario& sc, const AccuracyOptions& o, double smallest_dt,
                    AccuracyPlan& plan) {
  const bool custom = reference_base(sc) != nullptr;
  std::string words;
  const EngineSpec base = reference_spec(sc, &words);
  AccuracyReference& ref = plan.reference;
  ref.study = "dt";
  ref.engine = custom ? base.name : "";
  std::string why;
  if (o.reference_dt > 0) {
    ref.dt = chosen_reference_dt(sc, o.reference_dt, smallest_dt);
    why = "--reference-dt";
  } else {
    ref.dt = reference_dt(sc, smallest_dt / 4,
                          "smallest swept dt " + format_double(smallest_dt) + " s / 4", &why);
  }
  ref.nu = sc.scene.cloth.nu;
  ref.nv = sc.scene.cloth.nv;
  check_divides(sc, ref.dt, "the reference");
  plan.reference_run.spec = with_integrator_and_dt(base, cloth::Integrator::rk4, ref.dt);
  plan.reference_run.rerun = custom ? rerun_overrides(plan.reference_run.spec) : "";
  plan.floor_run.spec = with_integrator_and_dt(base, cloth::Integrator::rk4, 2 * ref.dt);
  ref.description = "rk4 at dt = " + format_double(ref.dt) + " s (" + why + ") on " +
                    grid_name(ref.nu, ref.nv) + " particles, " + words;
}

/// The scene again on square grids of the same size and mass, from the coarsest.
void plan_grids(const Scenario& sc, const AccuracyOptions& o, AccuracyPlan& plan) {
  plan.sizes = o.resolutions;
  std::sort(plan.sizes.begin(), plan.sizes.end());
  plan.sizes.erase(std::unique(plan.sizes.begin(), plan.sizes.end()), plan.sizes.end());
  if (plan.sizes.empty()) return;
  const std::string text = scenario_to_toml(sc);
  for (int r : plan.sizes) {
    try {
      plan.grids.push_back(
          parse_scenario(text, sc.source + " on " + grid_name(r, r),
                         {"cloth.particles=[" + std::to_string(r) + ", " + std::to_string(r) + "]",
                          "cloth.total_mass=" + format_double(total_mass(sc))}));
    } catch (const UserError& e) {
      // the grid is the user's --resolutions value, not a --set they gave
      throw UserError(
          as_option_error(e.what(), "cloth.particles", "--resolutions " + std::to_string(r)));
    }
  }
}

/// The resolution study: every configuration at its engine's dt on every grid; its reference
/// is rk4 at the smallest dt of either study (explicit --dts may lie above the engines' own)
/// on the finest grid.
void plan_resolutions(const Scenario& sc, const std::vector<EngineSpec>& engines,
                      const std::vector<cloth::Integrator>& integrators, double smallest_dt,
                      AccuracyPlan& plan) {
  const double mass = total_mass(sc);
  for (size_t g = 0; g < plan.grids.size(); ++g)
    for (const EngineSpec& e : engines)
      for (const std::optional<cloth::Integrator>& integrator : own_integrators(e, integrators)) {
        AccuracyConfig c;
        c.spec = with_integrator_and_dt(e, integrator, e.dt);
        c.integrator = integrator;
        c.grid = static_cast<int>(g);
        c.key = join_key(e.name, integrator_label(integrator),
                         std::to_string(plan.sizes[g] * plan.sizes[g]));
        c.rerun = rerun_at_grid(c.spec, plan.sizes[g], mass);
        plan.configs.push_back(std::move(c));
      }
  // canonical order: engine, integrator, then grids from the coarsest
  for (const EngineSpec& e : engines)
    for (const std::optional<cloth::Integrator>& integrator : own_integrators(e, integrators))
      for (int r : plan.sizes)
        plan.res_keys.push_back(
            join_key(e.name, integrator_label(integrator), std::to_string(r * r)));
  std::string words;
  const EngineSpec base = reference_spec(sc, &words);
  AccuracyReference& rr = plan.resolution_reference;
  rr.study = "resolution";
  rr.engine = plan.reference.engine;
  double smallest = smallest_dt;
  for (const EngineSpec& e : engines) smallest = std::min(smallest, e.dt);
  std::string why;
  rr.dt = reference_dt(plan.grids.back(), smallest, "the smallest dt swept or run", &why);
  check_divides(plan.grids.back(), rr.dt, "the resolution reference");
  rr.nu = rr.nv = plan.sizes.back();
  rr.description = "rk4 at dt = " + format_double(rr.dt) + " s (" + why + ") on " +
                   grid_name(rr.nu, rr.nv) + " particles (the finest grid), " + words;
  plan.resolution_reference_run.spec = with_integrator_and_dt(base, cloth::Integrator::rk4, rr.dt);
  if (reference_base(sc))
    plan.resolution_reference_run.rerun =
        rerun_at_grid(plan.resolution_reference_run.spec, plan.sizes.back(), mass);
}

}  // namespace

AccuracyPlan plan_accuracy(const Scenario& sc, const AccuracyOptions& o) {
  check_options(sc, o);
  const std::vector<EngineSpec> engines = selected_engines(sc, o);
  const std::vector<cloth::Integrator> integrators = selected_integrators(o);
  // a scene an engine refuses fails here, before any work
  for (const EngineSpec& e : engines) require_engine_can_model(e, sc.scene, "");
  AccuracyPlan plan;
  const double smallest_dt = plan_time_steps(sc, o, engines, integrators, plan);
  // the grids first: a grid the user cannot have is refused before any spectrum is computed
  plan_grids(sc, o, plan);
  plan_reference(sc, o, smallest_dt, plan);
  if (!plan.grids.empty()) plan_resolutions(sc, engines, integrators, smallest_dt, plan);
  return plan;
}

}  // namespace clothbench
