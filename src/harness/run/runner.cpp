#include "harness/run/runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "cloth/forces/energies.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "harness/engines/engine_factory.hpp"
#include "harness/fabric/cantilever_metrics.hpp"
#include "harness/fabric/tensile_metrics.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/staged_folder.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/build_info.hpp"
#include "harness/run/engine_metric.hpp"
#include "harness/run/ensemble_member.hpp"
#include "harness/run/mesh_file.hpp"
#include "harness/run/overhang_sequence.hpp"
#include "harness/run/run_books.hpp"
#include "harness/run/trajectory_files.hpp"
#include "harness/scenario/engine_refusal.hpp"
#include "harness/scenario/scenario_writer.hpp"

namespace clothbench {

std::atomic<bool>& interrupt_requested() {
  static std::atomic<bool> flag{false};
  return flag;
}

long long planned_steps(const Scenario& sc, const EngineSpec& spec) {
  return std::llround(sc.duration / spec.dt);
}

namespace {

/// True once a run started at started has taken more than sc.max_run_seconds (when set).
bool over_budget(const Scenario& sc, std::chrono::steady_clock::time_point started) {
  return sc.max_run_seconds > 0 &&
         !(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() <=
           sc.max_run_seconds);
}

/// The energy half of the blow-up test: a run fails once its energy error, the energy its
/// scheme created, exceeds blowup_energy times the EnergyScale. One-sided: a scheme that loses
/// energy (backward Euler's numerical damping) is dissipative, not unstable.
class EnergyTest {
 public:
  /// Starts the books at sim's current (initial) state.
  EnergyTest(const cloth::Model& model, const cloth::Simulator& sim, const RunBooks& books,
             double blowup_energy)
      : m_model(model), m_sim(sim), m_books(books), m_scale(model), m_limit(blowup_energy) {
    const cloth::Energies e = cloth::compute_energies(model, sim.positions(), sim.velocities());
    m_e0 = e.total();
    m_scale.observe(e.kinetic, e.elastic_potential);
  }
  /// Total energy at the start (J).
  double e0() const { return m_e0; }
  /// Why the current state fails the test ("energy", or "non-finite" for a NaN or infinite
  /// energy error: a velocity gone bad while the positions are still finite); nullptr when it
  /// passes. Its energies join the scale first.
  const char* failure() {
    const cloth::Energies e =
        cloth::compute_energies(m_model, m_sim.positions(), m_sim.velocities());
    m_scale.observe(e.kinetic, e.elastic_potential);
    const double error = energy_error(e.total(), m_books.now(), m_e0);
    if (!std::isfinite(error)) return "non-finite";
    return m_scale.exceeded_by(error, m_limit) ? "energy" : nullptr;
  }

 private:
  const cloth::Model& m_model;
  const cloth::Simulator& m_sim;
  const RunBooks& m_books;
  EnergyScale m_scale;
  double m_limit;
  double m_e0 = 0;  // J
};

/// The contacts of a frame: how many particles touch a collider, and the colliders' impulse
/// over the frame divided by its time (NaN and -1 for an engine that cannot say).
class ContactMeter {
 public:
  explicit ContactMeter(const cloth::Simulator& sim)
      : m_sim(sim), m_impulse(sim.contact_impulse()), m_t(sim.time()) {}
  FrameMetrics read(FrameMetrics m) {
    m.contacts = m_sim.contacts();
    const Eigen::Vector3d now = m_sim.contact_impulse();
    const double span = m_sim.time() - m_t;
    m.contact_force =
        span > 0 ? Eigen::Vector3d((now - m_impulse) / span) : Eigen::Vector3d(now * 0.0);
    m_impulse = now;
    m_t = m_sim.time();
    return m;
  }

 private:
  const cloth::Simulator& m_sim;
  Eigen::Vector3d m_impulse;  // N s, at the last frame
  double m_t;                 // s, of the last frame
};

}  // namespace

namespace {

/// Advances sim by k steps of dt (one step() call when k is 1, as every engine but an external
/// one is stepped); an engine that cannot go on (cloth::EngineFailure) fails the run with its
/// message as the cause, and false is returned.
bool advance_engine(cloth::Simulator& sim, double dt, long long k, EngineRun& run) {
  try {
    if (k == 1)
      sim.step(dt);
    else
      sim.advance(dt, static_cast<int>(k));
    return true;
  } catch (const cloth::EngineFailure& e) {
    run.stable = false;
    run.cause = std::string("engine failed: ") + e.what();
    run.blowup_t = sim.time();
    return false;
  }
}

/// The figures of a finished run: its counters, final kinetic energy and static residual.
void finish_run(EngineRun& run, const cloth::Simulator& sim, const cloth::Model& model) {
  // a run that blew up before its first frame has no energy error (not 0: nothing was measured)
  if (!run.stable && !run.timed_out && run.frames.size() <= 2) run.max_energy_error = NAN;
  run.counters = sim.counters();
  run.final_kinetic = run.frames.back().kinetic;
  run.final_static_residual = static_residual(model, sim.time(), sim.positions(), sim.velocities());
}

/// Advances progress by a frame of steps; the label carries the simulated time, so that a slow
/// engine shows how far it has come. Live bar or not: in a log, Progress prints a plain line
/// every 5 %, so a long run there is not silent.
void show_frame(Progress& progress, const Scenario& sc, const EngineSpec& spec,
                const cloth::Simulator& sim, long long steps) {
  char label[128];
  const std::string& name = spec.label.empty() ? spec.name : spec.label;
  std::snprintf(label, sizeof label, "%s  t = %.2f / %.2f s", name.c_str(), sim.time(),
                sc.duration);
  progress.advance(double(steps), label);
}

/// The engine of spec on sc's scene; null when it cannot start (an external program that fails
/// to run or to answer its handshake), with run then a failed run of the initial state alone.
std::unique_ptr<cloth::Simulator> start_engine(const Scenario& sc, const EngineSpec& spec,
                                               const cloth::Model& model, bool keep_positions,
                                               EngineRun& run) {
  try {
    return make_engine(spec, engine_scene(sc, spec));
  } catch (const cloth::EngineFailure& e) {
    const cloth::Matrix3X v0 = cloth::Matrix3X::Zero(3, model.particle_count());
    const double e0 = cloth::compute_energies(model, model.x0, v0).total();
    run.frames.push_back(frame_metrics(model, 0.0, model.x0, v0, EnergyBooks{}, e0));
    run.frames.back().stable = false;
    if (keep_positions) run.positions.push_back(model.x0);
    run.snapshot_times.push_back(0.0);
    run.snapshots.push_back(model.x0);
    run.stable = false;
    run.cause = std::string("engine failed: ") + e.what();
    run.blowup_t = 0.0;
    run.max_energy_error = NAN;
    run.final_kinetic = 0.0;
    return nullptr;
  }
}

}  // namespace

namespace {

/// run_engine on model, the engine's own scene's.
EngineRun run_engine_on(const Scenario& sc, const EngineSpec& spec, const cloth::Model& model,
                        Progress* progress, bool keep_positions) {
  EngineRun run;
  run.spec = spec;
  auto sim = start_engine(sc, spec, model, keep_positions, run);
  if (!sim) return run;
  const long long steps_per_frame = std::llround(sc.frame_interval / spec.dt);
  const long long frames = std::llround(sc.duration / sc.frame_interval);
  const long long frames_per_snapshot =
      sc.snapshot_interval > 0 ? std::llround(sc.snapshot_interval / sc.frame_interval) : 0;
  const long long steps_per_check =
      std::clamp(std::llround(kEnergyCheckInterval / spec.dt), 1LL, steps_per_frame);
  RunBooks books(model, *sim);
  EnergyTest energy_test(model, *sim, books, sc.blowup_energy);
  auto fail = [&](const char* cause) {
    run.stable = false;
    run.cause = cause;
    run.blowup_t = sim->time();
  };

  // frames sit on the exact grid k * frame_interval; a blow-up row at the failing step's time
  ContactMeter contact(*sim);
  const cloth::SelfIntersectionMeter meter = cloth::rest_shape_meter(model.x0, model.triangles);
  auto log_frame = [&](long long frame, bool stable) {
    const double t = stable ? double(frame) * sc.frame_interval : sim->time();
    FrameMetrics m = contact.read(frame_metrics(model, t, sim->positions(), sim->velocities(),
                                                books.now(), energy_test.e0(), &meter));
    m.stable = stable;
    // a NaN energy error sticks (std::max would drop it and let the gate pass)
    if (stable && !std::isnan(run.max_energy_error) &&
        !(std::abs(m.energy_error) <= run.max_energy_error))
      run.max_energy_error = std::abs(m.energy_error);
    run.frames.push_back(m);
    if (keep_positions) run.positions.push_back(sim->positions());
  };
  auto snapshot = [&]() {
    run.snapshot_times.push_back(run.frames.back().t);
    run.snapshots.push_back(sim->positions());
  };

  log_frame(0, true);
  snapshot();
  const auto started = std::chrono::steady_clock::now();
  // an engine that pays per request advances from one energy check to the next in one batch,
  // and its blow-up tests run at the batch's end; every other engine is tested every step
  const long long batch = sim->prefers_batches() ? steps_per_check : 1;
  for (long long f = 1; f <= frames && run.stable; ++f) {
    for (long long s = 0; s < steps_per_frame;) {
      // every step: one frame can be long (a stability trial is a single frame)
      if (interrupt_requested()) throw Interrupted();
      if (over_budget(sc, started)) {
        run.stable = false;
        run.timed_out = true;
        break;
      }
      const long long k = std::min(batch, steps_per_frame - s);
      const auto t0 = std::chrono::steady_clock::now();
      if (!advance_engine(*sim, spec.dt, k, run)) break;
      run.wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      books.observe();
      s += k;
      if (!cloth::within_stretch(model.springs, sim->positions(), sc.blowup_strain)) {
        fail(sim->positions().allFinite() ? "strain" : "non-finite");
        break;
      }
      if (s % steps_per_check == 0 || s == steps_per_frame) {
        if (const char* cause = energy_test.failure()) {
          fail(cause);
          break;
        }
      }
    }
    log_frame(f, run.stable);
    if (progress) show_frame(*progress, sc, spec, *sim, steps_per_frame);
    const bool last = f == frames || !run.stable;
    if (last || (frames_per_snapshot > 0 && f % frames_per_snapshot == 0)) snapshot();
  }
  finish_run(run, *sim, model);
  return run;
}

}  // namespace

EngineRun run_engine(const Scenario& sc, const EngineSpec& spec, const cloth::Model& model,
                     Progress* progress, bool keep_positions) {
  // an engine with overrides is measured in its own scene's model (same particles, own forces)
  if (!spec.scene) return run_engine_on(sc, spec, model, progress, keep_positions);
  return run_engine_on(sc, spec, cloth::build_model(*spec.scene), progress, keep_positions);
}

namespace {

/// Each engine's sequence of overhangs (overhang_sequence.hpp), into result.overhangs.
void run_overhang_sequences(const Scenario& sc, RunResult& result, Progress& progress) {
  for (const EngineRun& run : result.runs) {
    result.overhangs.push_back(standard_overhang_sequence(sc, result.model, run));
    const OverhangSequence& q = result.overhangs.back();
    progress.line(run.spec.name + ": standard overhang " + format_double(q.overhang) +
                  " m (c = " + format_double(q.bending_length) + " m) after " +
                  std::to_string(q.runs.size()) + " settles");
  }
}

}  // namespace

RunResult run_scenario(const Scenario& unperturbed, const RunOptions& options) {
  Scenario sc = unperturbed;
  sc.scene = perturbed_scene(sc.scene, options.member, options.member_seed);
  RunResult result;
  result.scenario = sc;
  result.model = cloth::build_model(sc.scene);
  const int ref = sc.reference_index();
  // which engines run: the filter, plus the reference
  std::vector<int> chosen;
  for (const std::string& name : options.engines) {
    auto it = std::find_if(sc.engines.begin(), sc.engines.end(),
                           [&](const EngineSpec& e) { return e.name == name; });
    if (it == sc.engines.end()) {
      std::string known;
      for (const EngineSpec& e : sc.engines) known += (known.empty() ? "" : ", ") + e.name;
      throw UserError("--engine " + name + ": no such engine in " + sc.source +
                      " (engines: " + known + ")");
    }
  }
  for (int i = 0; i < static_cast<int>(sc.engines.size()); ++i) {
    const bool wanted = options.engines.empty() || i == ref ||
                        std::count(options.engines.begin(), options.engines.end(),
                                   sc.engines[static_cast<size_t>(i)].name) > 0;
    if (wanted) chosen.push_back(i);
  }
  // a scene an engine refuses fails before any work (the loader refused it already, unless
  // the caller changed the scene since)
  // an engine's own scene is perturbed as the scenario's is
  for (int i : chosen) {
    EngineSpec& e = sc.engines[static_cast<size_t>(i)];
    if (e.scene)
      e.scene = std::make_shared<const cloth::Scene>(
          perturbed_scene(*e.scene, options.member, options.member_seed));
    require_engine_can_model(e, engine_scene(sc, e), "");
  }

  double total_steps = 0;
  for (int i : chosen) total_steps += double(planned_steps(sc, sc.engines[static_cast<size_t>(i)]));
  Progress progress(total_steps, "steps", options.progress);
  for (int i : chosen) {
    const EngineSpec& spec = sc.engines[static_cast<size_t>(i)];
    if (i == ref) result.reference = static_cast<int>(result.runs.size());
    EngineRun run = run_engine(sc, spec, result.model, &progress, options.keep_positions);
    std::ostringstream msg;
    msg << spec.name << ": " << run.counters.steps << " steps of " << spec.dt << " s in "
        << format_double(std::round(run.wall_s * 1000) / 1000) << " s ("
        << std::llround(run.counters.steps / std::max(run.wall_s, 1e-9)) << " steps/s), "
        << (run.stable ? std::string("stable")
            : run.timed_out
                ? "timeout: stopped at t = " + format_double(run.frames.back().t) +
                      " s after --max-run-seconds " + format_double(sc.max_run_seconds) + " s"
                : "unstable (" + run.cause + ") at t = " + format_double(run.blowup_t) + " s");
    if (run.counters.cg_unconverged > 0)
      msg << "; " << run.counters.cg_unconverged
          << " linear solves stopped at cg_max_iterations before reaching cg_tolerance";
    if (run.counters.newton_unconverged > 0)
      msg << "; " << run.counters.newton_unconverged << " of " << run.counters.steps
          << " steps ended Newton above newton_tolerance (newton_iterations reached or no "
             "descent): those steps are not implicit Euler's solution";
    progress.line(msg.str());
    result.runs.push_back(std::move(run));
  }
  // the standard's sequence of overhangs, one engine after another
  if (sc.test.kind == "cantilever" && sc.test.overhang_rule == "standard")
    run_overhang_sequences(sc, result, progress);
  // divergence of every engine from the reference, frame by frame while both ran
  const EngineRun& r = result.runs[static_cast<size_t>(result.reference)];
  for (const EngineRun& run : result.runs) {
    std::vector<Divergence> d;
    const size_t n =
        std::min({run.frames.size(), r.frames.size(), run.positions.size(), r.positions.size()});
    for (size_t k = 0; k < n; ++k) {
      // an unstable last frame sits at the blow-up time, not on the common frame grid
      if (!run.frames[k].stable || !r.frames[k].stable) break;
      d.push_back(divergence(run.positions[k], run.frames[k], r.positions[k], r.frames[k]));
    }
    result.divergence.push_back(std::move(d));
  }
  return result;
}

double final_divergence(const RunResult& result, size_t i) {
  const std::vector<Divergence>& d = result.divergence[i];
  if (d.empty() || !result.runs[size_t(result.reference)].stable) return NAN;
  return d.back().rms_distance;
}

double final_drape_coefficient(const RunResult& result, const EngineRun& run) {
  const cloth::Model& model = result.model;
  // flat in x-z at rest: a grid in the xz plane, or a mesh whose vertices share one height
  const bool horizontal = model.x0.row(1).maxCoeff() - model.x0.row(1).minCoeff() <= 0.0;
  // the held disks: a grid's disk, or a ball around a point of a horizontal cloth's plane
  std::vector<double> disks;
  for (const ConstraintSpec& c : result.scenario.constraints) {
    if (c.select == "disk") disks.push_back(c.disk_radius);
    if (c.select == "within" && horizontal && c.center.y() == model.x0(1, 0))
      disks.push_back(c.disk_radius);
  }
  const cloth::Scene& scene = result.scenario.scene;
  const double support = support_area(disks, scene.spheres, horizontal, scene.shapes.cylinders);
  const double cloth_area =
      scene.mesh ? cloth::mesh_area(*scene.mesh) : scene.cloth.size_u * scene.cloth.size_v;
  if (support <= 0 || cloth_area <= support || run.frames.empty())
    return std::numeric_limits<double>::quiet_NaN();
  return drape_coefficient(run.frames.back().shadow_area, support, cloth_area);
}

namespace {

/// The facts about engine kinds and integrators that the gate and the report read from
/// run.json rather than keeping copies of their own, as JSON members (two-space indented).
std::string facts_json() {
  std::ostringstream o;
  o << "  \"engine_kinds\": {";
  const auto& kinds = engine_kind_table();
  for (size_t k = 0; k < kinds.size(); ++k)
    o << (k ? "," : "") << "\n    \"" << kinds[k].name
      << "\": {\"has_integrators\": " << (kinds[k].has_integrators ? "true" : "false")
      << ", \"energy_gated\": " << (kinds[k].energy_gated ? "true" : "false")
      << ", \"energy_note\": \"" << kinds[k].energy_note << "\"}";
  o << "\n  },\n  \"integrators\": {";
  const auto& integrators = cloth::all_integrators();
  for (size_t k = 0; k < integrators.size(); ++k)
    o << (k ? "," : "") << "\n    \"" << cloth::integrator_name(integrators[k])
      << "\": {\"order\": " << cloth::integrator_order(integrators[k])
      << ", \"force_evals_per_step\": " << cloth::force_evals_per_step(integrators[k]) << "}";
  o << "\n  }";
  return o.str();
}

/// s as a JSON string, quoted and escaped.
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\u%04x", c);
      out += hex;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

/// Each engine's self-collision ("on", "off" or "not available") and, when any engine has
/// some, each engine's overrides (key path: value as TOML text), as JSON members.
std::string self_collision_json(const Scenario& s) {
  std::ostringstream o;
  o << "  \"self_collision\": {";
  for (size_t k = 0; k < s.engines.size(); ++k)
    o << (k ? ", " : "") << "\"" << s.engines[k].name << "\": \""
      << self_collision_name(self_collision_of(s.engines[k], engine_scene(s, s.engines[k]).cloth))
      << "\"";
  o << "},\n";
  // each engine's own scene keys, when any engine has some
  if (std::none_of(s.engines.begin(), s.engines.end(),
                   [](const EngineSpec& e) { return !e.overrides.empty(); }))
    return o.str();
  o << "  \"overrides\": {";
  for (size_t k = 0; k < s.engines.size(); ++k) {
    o << (k ? ", " : "") << "\"" << s.engines[k].name << "\": {";
    for (size_t j = 0; j < s.engines[k].overrides.size(); ++j)
      o << (j ? ", " : "") << json_string(s.engines[k].overrides[j].first) << ": "
        << json_string(s.engines[k].overrides[j].second);
    o << "}";
  }
  o << "},\n";
  return o.str();
}

/// frames.csv: one row per engine per frame.
void write_frames(const RunResult& result, CsvWriter& frames) {
  for (const EngineRun& run : result.runs)
    for (const FrameMetrics& m : run.frames) {
      frames.add(run.spec.name).add(m.t).add(m.kinetic).add(m.gravity_potential);
      frames.add(m.elastic_potential).add(m.dissipated).add(m.contact_work).add(m.collider_work);
      frames.add(m.unbooked);
      frames.add(m.handle_work);
      frames.add(m.total_energy).add(m.energy_error);
      frames.add(m.max_strain).add(m.mean_strain).add(m.com.x()).add(m.com.y()).add(m.com.z());
      frames.add(m.min_y).add(m.max_penetration).add(m.shadow_area).add(m.stable ? 1 : 0);
      // an engine that cannot say leaves the contact columns empty
      if (m.contacts < 0)
        frames.skip().skip().skip().skip();
      else
        frames.add(m.contacts)
            .add(m.contact_force.x())
            .add(m.contact_force.y())
            .add(m.contact_force.z());
      frames.add(m.max_stretch).add(m.max_compression);
      // a state that is not finite has no self-intersection count
      if (m.self_intersections < 0)
        frames.skip().skip();
      else
        frames.add(m.self_intersections).add(m.min_self_distance);
      frames.end_row();
    }
}

/// divergence.csv: every engine but the reference against it, per frame.
void write_divergence(const RunResult& result, CsvWriter& div) {
  const std::string ref_name = result.runs[static_cast<size_t>(result.reference)].spec.name;
  for (size_t i = 0; i < result.runs.size(); ++i) {
    if (static_cast<int>(i) == result.reference) continue;
    for (const Divergence& d : result.divergence[i]) {
      div.add(result.runs[i].spec.name).add(ref_name).add(d.t).add(d.rms_distance);
      div.add(d.max_distance).add(d.com_distance).add(d.energy_difference);
      div.add(d.shadow_area_difference).end_row();
    }
  }
}

/// snapshots.csv: every particle of every kept shape.
void write_snapshots(const RunResult& result, CsvWriter& snaps) {
  const int nu = result.model.nu;
  for (const EngineRun& run : result.runs)
    for (size_t s = 0; s < run.snapshots.size(); ++s)
      for (Eigen::Index p = 0; p < run.snapshots[s].cols(); ++p) {
        snaps.add(run.spec.name).add(run.snapshot_times[s]);
        snaps.add(static_cast<int>(p % nu)).add(static_cast<int>(p / nu));
        snaps.add(run.snapshots[s](0, p)).add(run.snapshots[s](1, p)).add(run.snapshots[s](2, p));
        snaps.end_row();
      }
}

/// summary.csv: one row per engine.
void write_summary(const RunResult& result, CsvWriter& summary) {
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineRun& run = result.runs[i];
    const std::vector<Divergence>& d = result.divergence[i];
    summary.add(run.spec.name).add(std::string(engine_kind_name(run.spec.kind)));
    if (engine_kind_info(run.spec.kind).has_integrators)
      summary.add(std::string(cloth::integrator_name(run.spec.solver.integrator)));
    else
      summary.skip();
    summary.add(run.spec.dt).add(static_cast<long long>(run.counters.steps)).add(run.wall_s);
    summary.add(run.counters.steps > 0 ? 1e6 * run.wall_s / double(run.counters.steps) : 0.0);
    summary.add(static_cast<long long>(run.counters.force_evals)).add(run.stable ? 1 : 0);
    if (run.stable || run.timed_out)
      summary.skip();  // a timeout: stable 0 with no blow-up time
    else
      summary.add(run.blowup_t);
    // undefined (blew up before its first frame): empty; a NaN energy stays "nan"
    if (!run.stable && std::isnan(run.max_energy_error))
      summary.skip();
    else
      summary.add(run.max_energy_error);
    const double final_rms = final_divergence(result, i);
    if (std::isnan(final_rms))
      summary.skip();
    else
      summary.add(final_rms);
    if (d.size() <= 1) {
      summary.skip();  // nothing after the common start was compared
    } else {
      double worst = 0;
      for (const Divergence& x : d) worst = std::max(worst, x.rms_distance);
      summary.add(worst);
    }
    const double dc = final_drape_coefficient(result, run);
    if (std::isnan(dc))
      summary.skip();
    else
      summary.add(dc);
    summary.add(run.final_kinetic).add(run.final_static_residual);
    summary.add(static_cast<long long>(run.counters.newton_iterations))
        .add(static_cast<long long>(run.counters.cg_iterations))
        .add(static_cast<long long>(run.counters.cg_unconverged))
        .add(static_cast<long long>(run.counters.newton_unconverged))
        .end_row();
  }
}

/// overhangs.csv: every settle of each engine's sequence of overhangs, in the order run.
void write_overhangs(const RunResult& result, CsvWriter& out) {
  for (size_t i = 0; i < result.overhangs.size(); ++i)
    for (const OverhangRun& r : result.overhangs[i].runs)
      out.add(result.runs[i].spec.name)
          .add(r.edge)
          .add(r.overhang)
          .add(r.chord_angle)
          .add(r.settle_change)
          .add(r.settled ? 1 : 0)
          .add(r.bracket ? 1 : 0)
          .end_row();
}

/// bias.csv's rows of one engine: its bias-extension curve, undefined values empty.
void write_bias_rows(const RunResult& result, const EngineRun& run, CsvWriter& bias) {
  for (const BiasPoint& p : bias_extension_curve(result, run)) {
    bias.add(run.spec.name).add(p.t).add(p.displacement);
    for (double v : {p.force, p.angle_pin, p.angle, p.shear_force, p.shear_force_pin})
      if (std::isfinite(v))
        bias.add(v);
      else
        bias.skip();
    bias.end_row();
  }
}

/// tests.csv: the [test]'s metrics of every engine (empty values where undefined, e.g. for a
/// run that did not end stable: its final shape is not a settled one); tensile.csv, when given,
/// the strip-tensile curves; bias, when given, the bias-extension curves.
void write_tests(const RunResult& result, CsvWriter& tests, CsvWriter* tensile, CsvWriter* bias) {
  for (const EngineRun& run : result.runs) {
    for (const TestMetric& row : test_metrics(result, run)) {
      tests.add(run.spec.name).add(row.metric);
      if (std::isfinite(row.value))
        tests.add(row.value);
      else
        tests.skip();
      tests.add(row.unit).end_row();
    }
    if (bias) write_bias_rows(result, run, *bias);
    if (!tensile) continue;
    for (const TensilePoint& p : strip_tensile_curve(result, run))
      tensile->add(run.spec.name).add(p.t).add(p.strain).add(p.force_per_width).end_row();
  }
}

}  // namespace

std::string run_info_json(const std::string& members) {
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  std::ostringstream o;
  o << "{\n  \"tool\": \"clothbench\",\n  \"version\": \"" << kVersion << "\",\n"
    << "  \"git_commit\": \"" << kGitCommit << "\",\n  \"compiler\": \"" << kCompiler
    << "\",\n  \"date\": \"" << date << "\",\n"
    << members << facts_json() << "\n}\n";
  return o.str();
}

void write_run_info(const std::string& dir) {
  // a run's record stays (it says what its engines' self-collision was): a sweep into a run's
  // folder adds its results beside the run's
  std::error_code ec;
  if (std::filesystem::exists(dir + "frames.csv", ec) &&
      std::filesystem::exists(dir + "run.json", ec))
    return;
  AtomicFile info(dir + "run.json");
  info.write(run_info_json());
  info.commit();
}

namespace {

/// Writes the run's files into dir (ending with '/').
void write_run_files(const RunResult& result, const std::string& dir) {
  // each file's columns come from its schema (output_schema.cpp)
  CsvWriter frames(dir + "frames.csv", output_header("frames.csv"));
  write_frames(result, frames);
  CsvWriter div(dir + "divergence.csv", output_header("divergence.csv"));
  write_divergence(result, div);
  CsvWriter snaps(dir + "snapshots.csv", output_header("snapshots.csv"));
  write_snapshots(result, snaps);
  CsvWriter summary(dir + "summary.csv", output_header("summary.csv"));
  write_summary(result, summary);
  AtomicFile toml(dir + "scenario.toml");
  toml.write(scenario_to_toml(result.scenario));
  AtomicFile info(dir + "run.json");
  info.write(run_info_json(self_collision_json(result.scenario)));
  // the [test]'s metrics, when the scenario has one
  std::unique_ptr<CsvWriter> tests, tensile, bias;
  if (result.scenario.test.kind == "strip-tensile")
    tensile = std::make_unique<CsvWriter>(dir + "tensile.csv", output_header("tensile.csv"));
  if (result.scenario.test.kind == "bias-extension")
    bias = std::make_unique<CsvWriter>(dir + "bias.csv", output_header("bias.csv"));
  if (!result.scenario.test.kind.empty()) {
    tests = std::make_unique<CsvWriter>(dir + "tests.csv", output_header("tests.csv"));
    write_tests(result, *tests, tensile.get(), bias.get());
  }
  std::unique_ptr<CsvWriter> overhangs;
  if (!result.overhangs.empty()) {
    overhangs = std::make_unique<CsvWriter>(dir + "overhangs.csv", output_header("overhangs.csv"));
    write_overhangs(result, *overhangs);
  }
  std::vector<std::unique_ptr<AtomicFile>> trajectory;
  write_trajectories(result, dir, trajectory);
  // a mesh's triangles, for the report's shapes
  if (result.model.is_mesh) {
    trajectory.push_back(std::make_unique<AtomicFile>(dir + "mesh.obj"));
    trajectory.back()->write(rest_mesh_obj(result.model));
  }
  // every file is complete: make them all appear (the trajectory index last)
  frames.commit();
  div.commit();
  snaps.commit();
  summary.commit();
  toml.commit();
  info.commit();
  if (tests) tests->commit();
  if (tensile) tensile->commit();
  if (overhangs) overhangs->commit();
  if (bias) bias->commit();
  for (auto& f : trajectory) f->commit();
}

}  // namespace

void write_run(const RunResult& result, const std::string& out) {
  make_directories(out);
  StagedFolder staged(out);
  staged.owns("trajectory");  // the new run's, or none: never an older run's beside new CSVs
  staged.owns("mesh.obj");
  staged.owns("tests.csv");  // the new run's [test] metrics, or none
  staged.owns("tensile.csv");
  staged.owns("overhangs.csv");  // the new run's sequence of overhangs, or none
  staged.owns("bias.csv");
  try {
    write_run_files(result, staged.path());
  } catch (const UserError& e) {
    throw UserError(staged.in_folder(e.what()));
  }
  staged.commit();
}

}  // namespace clothbench
