#include "harness/io/output_schema.hpp"

#include <sstream>
#include <stdexcept>

namespace clothbench {

namespace {

// columns several files share
constexpr OutputColumn kEngine{"engine", "text", "the engine's name in the scenario"};
constexpr OutputColumn kIntegrator{"integrator", "text",
                                   "the custom engine's integrator; empty for a Bullet engine"};
constexpr OutputColumn kT{"t", "s", "simulated time of the frame"};
constexpr OutputColumn kRerun{"rerun", "text",
                              "the --set overrides that make `clothbench run` repeat the row"};

// the columns of stability.csv, which map.csv repeats after its varied keys
const std::vector<OutputColumn>& stability_columns() {
  static const std::vector<OutputColumn> columns = {
      kEngine,
      kIntegrator,
      {"stable_dt", "s", "largest time step found stable over the horizon; empty when none"},
      {"first_unstable_dt", "s",
       "smallest time step found unstable above stable_dt; inf when none up to --dt-max"},
      {"predicted_dt", "s", "the limit linear theory predicts; empty without a theory"},
      {"ratio_measured_to_predicted", "1", "stable_dt / predicted_dt when both limits were found"},
      {"cause", "text", "how the first unstable run failed, and the limiting mode"},
      {"runs", "count", "simulations the search took"},
      {"rerun", "text", "the --set overrides that rerun the stable_dt run"},
      {"rerun_unstable", "text", "the --set overrides that rerun the first_unstable_dt run"},
      {"method", "text", "blowup, growth or both: which limits the row holds"},
      {"growth_stable_dt", "s",
       "largest time step at which no perturbation grows faster than the physical rate plus "
       "--growth-tol; empty when none"},
      {"growth_first_unstable_dt", "s",
       "smallest time step found unstable by growth above growth_stable_dt; inf when none up "
       "to --dt-max"},
      {"growth_rate", "1/s",
       "growth rate ln(rho) / dt of the fastest-growing state at growth_first_unstable_dt"},
      {"physical_rate", "1/s", "that state's growth rate measured in steps of dt / 8"},
      {"growth_ratio", "1", "growth_stable_dt / predicted_dt when both limits were found"},
      {"growth_cause", "text",
       "where the growth is: set by contact (only the state in contact grows) or free, "
       "states where the step map is not smooth, and \"near the physics\" when no unstable "
       "state grows more than 20 % faster than its physical rate (check such a limit with "
       "`--method blowup`)"},
      {"mode_structural", "1", "the growing mode's spring energy in structural springs, fraction"},
      {"mode_shear", "1", "the same in shear springs"},
      {"mode_bend", "1", "the same in bend springs"},
      {"growth_steps", "count", "engine steps the growth measurement took"},
      {"blowup_steps", "count", "engine steps the blow-up search took"}};
  return columns;
}

std::vector<OutputColumn> map_columns() {
  std::vector<OutputColumn> columns = {
      {kVariedKeyColumn, "the key's",
       "one column per --vary key, named by the key (e.g. cloth.damping): its value at the "
       "point"}};
  for (const OutputColumn& c : stability_columns()) columns.push_back(c);
  return columns;
}

// summary.csv's columns: one engine's run
std::vector<OutputColumn> summary_columns() {
  return {kEngine,
          {"kind", "text", "the engine kind (custom, bullet-deformable, bullet-softbody)"},
          kIntegrator,
          {"dt", "s", "time step"},
          {"steps", "count", "steps taken"},
          {"wall_s", "s", "wall-clock time spent in the engine's steps"},
          {"us_per_step", "1e-6 s", "wall-clock microseconds per step"},
          {"force_evals", "count", "force evaluations over the run"},
          {"stable", "0/1", "1 when the run ended without a blow-up or a timeout"},
          {"blowup_t", "s", "simulated time of the first unstable step; empty when stable"},
          {"max_energy_error", "J", "largest |energy_error| while stable"},
          {"final_rms_vs_reference", "m",
           "RMS particle distance to the reference engine at the last common frame"},
          {"max_rms_vs_reference", "m", "largest RMS particle distance to the reference engine"},
          {"drape_coefficient", "1",
           "Cusick drape coefficient (shadow - support) / (cloth - support) at the end; empty "
           "without a support"},
          {"final_kinetic", "J", "kinetic energy of the last logged state"},
          {"static_residual", "1",
           "largest net force on a free particle over its weight, last logged state; 0 at rest"},
          {"newton_iterations", "count",
           "Newton iterations over the run (implicit solvers; 0 for the others and non-custom "
           "engines)"},
          {"cg_iterations", "count", "conjugate-gradient iterations over the run"},
          {"cg_unconverged", "count", "linear solves that stopped at their iteration limit"},
          {"newton_unconverged", "count",
           "implicit Euler steps (line-search Newton) whose Newton iteration ended above "
           "newton_tolerance: at newton_iterations, or with no descent left"}};
}

// the run's per-engine tables
std::vector<OutputFile> run_files() {
  return {
      {"summary.csv", "clothbench run, in the run folder", "one engine", summary_columns()},
      {"frames.csv",
       "clothbench run, in the run folder",
       "one engine at one logged frame",
       {kEngine,
        kT,
        {"kinetic", "J", "kinetic energy"},
        {"gravity_potential", "J", "gravitational potential energy"},
        {"elastic_potential", "J", "energy stored in the springs"},
        {"dissipated", "J", "energy taken out by the spring dampers and air drag so far"},
        {"contact_work", "J", "net work of the contact response so far, relative to the colliders"},
        {"collider_work", "J",
         "work of the moving colliders' motion so far: each contact impulse dotted with its "
         "collider's velocity (0 for static colliders, and in an engine that cannot split it)"},
        {"unbooked", "J",
         "energy balance no book explains (Bullet steps with a contact; steps whose handles "
         "moved by projection, less the handles' work)"},
        {"handle_work", "J",
         "work of the handles' holders so far, from the scene's forces on the handled particles "
         "along their path (the harness's, the same for every engine)"},
        {"total_energy", "J", "kinetic plus both potentials"},
        {"energy_error", "J",
         "total_energy + dissipated - contact_work - collider_work - handle_work - unbooked - "
         "the initial total"},
        {"max_strain", "1",
         "largest |l / l0 - 1| over every spring, bend springs included (a fold reads near 1)"},
        {"mean_strain", "1", "mean |l / l0 - 1| over the springs"},
        {"com_x", "m", "centre of mass, x"},
        {"com_y", "m", "centre of mass, y"},
        {"com_z", "m", "centre of mass, z"},
        {"min_y", "m", "lowest particle height"},
        {"max_penetration", "m", "deepest particle below a collider's surface"},
        {"shadow_area", "m^2", "the cloth's shadow on the plane normal to gravity"},
        {"stable", "0/1", "1 while the run is stable; the last row of a blow-up is 0"},
        {"contacts", "count",
         "particles in contact at the frame's last step; empty when the engine cannot say"},
        {"contact_fx", "N", "total contact force on the cloth, x; empty when unknown"},
        {"contact_fy", "N", "total contact force on the cloth, y; empty when unknown"},
        {"contact_fz", "N", "total contact force on the cloth, z; empty when unknown"},
        {"max_stretch", "1",
         "largest l / l0 - 1 > 0 over the structural and shear springs (the edge springs of a "
         "mesh); bend springs left out; the blow-up test reads this"},
        {"max_compression", "1", "largest 1 - l / l0 > 0 over the same springs"},
        {"self_intersections", "count",
         "edge-triangle pairs sharing no vertex where the edge crosses the triangle's interior "
         "(exact predicates; touching is not crossing); empty when a position is not finite"},
        {"min_self_distance", "m",
         "smallest vertex-triangle or edge-edge distance between parts more than two rings "
         "apart, capped at half the mean rest edge length; empty when a position is not finite"}}}};
}

// the cantilever standard's sequence of overhangs
OutputFile overhangs_file() {
  return {"overhangs.csv",
          "clothbench run, in the run folder, when the scenario's cantilever [test] has "
          "overhang_rule = \"standard\"",
          "one settled run of one engine's sequence of overhangs towards 41.5 degrees, in the "
          "order run (the first is the scene's own overhang, the scenario's run itself)",
          {kEngine,
           {"edge", "m", "rest x of the last held column (the clamp)"},
           {"overhang", "m", "rest length from the clamp to the tip"},
           {"chord_angle", "deg",
            "the chord's angle below the horizontal at the run's end; empty when it blew up"},
           {"settle_change", "deg", "chord angle at the end minus at nine tenths of the run"},
           {"settled", "1", "1 when stable and |settle_change| <= 0.05 degrees"},
           {"bracket", "1",
            "1 for the two neighbouring overhangs that bracket 41.5 degrees, between which "
            "standard_overhang interpolates the chord angle linearly"}}};
}

// bias.csv: the bias-extension curves
OutputFile bias_file() {
  return {"bias.csv",
          "clothbench run, in the run folder, when the scenario's [test] is a bias-extension",
          "one frame of one engine's bias-extension curve (force and shear force for the custom "
          "engines alone: the other engines' forces are not the scene's springs)",
          {kEngine,
           kT,
           {"displacement", "m", "the handle's prescribed displacement d along x"},
           {"force", "N",
            "the springs' elastic force along x across the specimen's central section (the "
            "clamp force, quasi-static); empty for a non-custom engine"},
           {"angle_pin_jointed", "rad",
            "the central zone's shear angle of the pin-jointed net at d: pi/2 - 2 acos[(H - W "
            "+ d) / (sqrt(2) (H - W))] (Cao et al. 2008)"},
           {"angle", "rad",
            "the central zone's shear angle measured from its particles: pi/2 less the angle "
            "between the deformed yarn directions of its least-squares affine map"},
           {"shear_force", "N/m",
            "shear force per unit length at the measured angle, normalised by the zones' "
            "energy balance (docs/methods.md); empty for a non-custom engine"},
           {"shear_force_pin_jointed", "N/m",
            "the same normalisation at the pin-jointed angle; empty for a non-custom engine"}}};
}

// the run's comparisons: each engine against the reference, its shapes, the attribution
std::vector<OutputFile> comparison_files() {
  return {{"tests.csv",
           "clothbench run, in the run folder, when the scenario has a [test]",
           "one metric of the scenario's textile standard test on one engine's final state",
           {kEngine,
            {"metric", "text",
             "cantilever: chord_angle, tip_deflection, overhang, bending_length (the elastica's), "
             "bending_length_peirce, flexural_rigidity, and with overhang_rule = \"standard\" "
             "standard_overhang (where the chord reaches 41.5 degrees), bending_length_standard "
             "(half of it) and standard_settles (the runs it took, overhangs.csv); drape: "
             "drape_coefficient, folds (local "
             "maxima of the outline's radius around the support's axis, smoothed over 10 "
             "degrees), min_radius and max_radius of that smoothed outline; strip-tensile: "
             "tensile_stiffness, fit_strain, max_strain, max_force_per_width; bias-extension: "
             "shear_stiffness (at the measured angle), shear_stiffness_pin_jointed, fit_angle, "
             "final_shear_angle (measured), "
             "final_shear_angle_pin_jointed, max_force"},
            {"value", "as unit",
             "the metric's value; empty when undefined (the run blew up, "
             "a chord angle the elastica cannot invert, fewer than 3 frames in a tensile fit, "
             "or an engine whose forces are not the scene's springs)"},
            {"unit", "text", "the value's unit: deg, m, N, N m, N/m, N/m/rad, 1 or count"}}},
          bias_file(),
          {"tensile.csv",
           "clothbench run, in the run folder, when the scenario's [test] is a strip-tensile",
           "one frame of one custom engine's force-strain curve (the other engines' forces are "
           "not the scene's springs: they get no rows)",
           {kEngine,
            kT,
            {"strain", "1",
             "the handle's prescribed displacement along the test's direction "
             "over the gauge length (clamp to handle, at rest)"},
            {"force_per_width", "N/m",
             "the springs' elastic tension across the strip's central section at the engine's "
             "positions, along the test's direction, over the strip's rest width"}}},
          overhangs_file(),
          {"divergence.csv",
           "clothbench run, in the run folder",
           "one engine other than the reference at one frame both logged",
           {kEngine,
            {"reference", "text", "the reference engine's name"},
            kT,
            {"rms_distance", "m", "RMS over particles of the distance to the reference"},
            {"max_distance", "m", "largest particle distance to the reference"},
            {"com_distance", "m", "distance between the two centres of mass"},
            {"energy_difference", "J", "total energy minus the reference's"},
            {"shadow_area_difference", "m^2", "shadow area minus the reference's"}}},
          {"snapshots.csv",
           "clothbench run, in the run folder",
           "one particle of one engine at one kept shape (initial, final, every snapshot_interval)",
           {kEngine,
            kT,
            {"i", "count", "grid index along u"},
            {"j", "count", "grid index along v"},
            {"x", "m", "position, x"},
            {"y", "m", "position, y"},
            {"z", "m", "position, z"}}},
          {"attribution.csv",
           "clothbench run --explain, in the run folder",
           "one Bullet engine's distance to the reference, at the final frame or its largest",
           {{"engine", "text", "the Bullet engine"},
            {"reference", "text", "the run's reference engine"},
            {"matched", "text",
             "the custom engine with the Bullet engine's time scheme; empty when none"},
            {"at", "text", "final (the last common frame) or max (largest over the frames)"},
            {"t", "s", "the frame of final; of max, the last frame compared"},
            {"total_rms", "m", "RMS distance of the Bullet engine to the reference"},
            {"scheme_rms", "m", "RMS distance of the matched engine to the reference"},
            {"model_rms", "m", "RMS distance of the matched engine to the Bullet engine"},
            {"note", "text", "why a row has no split, or where it stops short of the end"}}}};
}

std::vector<OutputFile> sweep_files() {
  return {
      {"stability.csv", "clothbench stability, in its output folder",
       "one engine (custom engines: one integrator)", stability_columns()},
      {"map.csv", "clothbench map, in its output folder",
       "one point of the grid, engine and integrator", map_columns()},
      {"work_precision.csv",
       "clothbench accuracy, in its output folder",
       "one engine and integrator at one time step",
       {kEngine,
        kIntegrator,
        {"dt", "s", "time step"},
        {"stable", "0/1", "1 when the run stayed stable"},
        {"error_final", "m",
         "RMS particle distance to the fine reference at the end; empty when unstable"},
        {"error_max", "m",
         "largest RMS particle distance over the logged frames; empty when unstable"},
        {"wall_s", "s", "wall-clock time in the engine's steps, median of the repeats"},
        {"wall_s_per_sim_s", "1", "wall-clock seconds per simulated second"},
        {"force_evals", "count", "force evaluations over the run"},
        {"cg_iterations", "count", "conjugate-gradient iterations over the run"},
        kRerun}},
      {"convergence.csv",
       "clothbench accuracy, in its output folder",
       "one engine and integrator",
       {kEngine,
        kIntegrator,
        {"order", "1",
         "fitted order of convergence of error_final in dt; empty with fewer than 2 points"},
        {"points", "count", "stable rows above the reference's error floor the fit used"}}},
      {"recommendation.csv",
       "clothbench accuracy --tolerance, in its output folder",
       "the cheapest stable row meeting the tolerance, per engine (scope engine) and overall",
       {{"scope", "text", "engine or overall"},
        {"engine", "text", "the engine (scope engine) or the winner's (overall); empty when none"},
        kIntegrator,
        {"dt", "s", "time step; empty when nothing meets the tolerance"},
        {"error_max", "m", "the row's error_max"},
        {"wall_s_per_sim_s", "1", "the row's wall-clock seconds per simulated second"},
        {"tolerance", "m", "the --tolerance given"},
        {"cost", "count",
         "machine-independent work in particle force evaluations; empty for a Bullet row"}}},
      {"reference.csv",
       "clothbench accuracy, in its output folder",
       "one fine reference run (time-step study, resolution study)",
       {{"study", "text", "dt or resolution"},
        {"engine", "text", "the custom engine whose solver options the reference uses"},
        kIntegrator,
        {"dt", "s", "the reference's time step"},
        {"particles", "count", "particles of the reference's grid"},
        {"error_floor", "m", "the reference's own error, below which errors are not resolved"},
        kRerun}},
      {"resolution.csv",
       "clothbench accuracy --resolutions, in its output folder",
       "one engine and integrator on one grid",
       {kEngine,
        kIntegrator,
        {"particles", "count", "particles of the grid"},
        {"dt", "s", "time step"},
        {"stable", "0/1", "1 when the run stayed stable"},
        {"error_final", "m", "RMS distance to the fine-grid reference at the end"},
        {"wall_s_per_sim_s", "1", "wall-clock seconds per simulated second"},
        {"force_evals", "count", "force evaluations over the run"},
        {"cg_iterations", "count", "conjugate-gradient iterations over the run"},
        kRerun}},
      {"resolution_recommendation.csv",
       "clothbench accuracy --resolutions --tolerance, in its output folder",
       "the cheapest stable grid meeting the tolerance, per engine and overall",
       {{"scope", "text", "engine or overall"},
        {"engine", "text", "the engine (scope engine) or the winner's (overall); empty when none"},
        kIntegrator,
        {"particles", "count", "particles of the grid"},
        {"dt", "s", "time step"},
        {"error_final", "m", "the row's error_final"},
        {"wall_s_per_sim_s", "1", "wall-clock seconds per simulated second"},
        {"tolerance", "m", "the --tolerance given"},
        {"cost", "count",
         "machine-independent work in particle force evaluations; empty for a Bullet row"}}}};
}

std::vector<OutputFile> baseline_files() {
  const char* where = "clothbench check --update, in reference/baselines/<scenario>/";
  return {{"baselines/metrics.csv",
           where,
           "one gated quantity of one engine",
           {kEngine,
            {"quantity", "text", "the gated quantity, a summary.csv column"},
            {"value", "the quantity's", "its recorded value"}}},
          {"baselines/shape.csv",
           where,
           "one particle of one engine's final shape",
           {kEngine,
            {"i", "count", "grid index along u"},
            {"j", "count", "grid index along v"},
            {"x", "m", "position, x"},
            {"y", "m", "position, y"},
            {"z", "m", "position, z"}}},
          {"baselines/stability.csv",
           where,
           "one engine and integrator's stability limits (scenarios with a [stability] search)",
           {kEngine,
            kIntegrator,
            {"stable_dt", "s", "largest time step found stable"},
            {"first_unstable_dt", "s", "smallest time step found unstable; inf when none"}}},
          {"baselines/metrics_ensemble.csv",
           where,
           "one member's value of one quantity of one engine gated by an ensemble (scenarios "
           "with [ensemble.<engine>] tables), and per such engine its growth_exponent",
           {kEngine,
            {"quantity", "text",
             "the ensemble-gated quantity (one of metrics.csv's, or a [test] metric as "
             "test.<metric>); growth_exponent: ln(|dX(T)| / |dX(0)|) / T (1/s) between "
             "members 0 and 1"},
            {"member", "count", "ensemble member, 0 the unperturbed scene"},
            {"value", "the quantity's", "the member's value"}}},
          {"baselines/tests.csv",
           where,
           "one metric of the scenario's [test] on one engine (scenarios with a [test]), gated "
           "by tolerances.toml's [tests] table",
           {kEngine,
            {"metric", "text", "the metric, a row of the run's tests.csv"},
            {"value", "the metric's", "its recorded value; empty when undefined"}}}};
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string markdown_cell(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

// clothbench fit: the parameters that make each engine's metrics hit their targets
std::vector<OutputFile> fit_files() {
  return {{"fit.csv",
           "clothbench fit, in its output folder",
           "one target metric of one engine: the parameter fitted for it and what it reached",
           {kEngine,
            {"parameter", "text",
             "the scenario key fitted, as --set takes it (engine.KEY: the engine's own key; "
             "a+b: both set to the value)"},
            {"value", "as the key", "the fitted value: the best run's; empty when no run was made"},
            {"metric", "text", "the target metric (a [test] metric or drape_coefficient)"},
            {"target", "as the metric", "the value asked for"},
            {"achieved", "as the metric",
             "the metric at the fitted values of every parameter of the engine; empty when no "
             "run gave it"},
            {"relative_error", "1", "(achieved - target) / |target|"},
            {"runs", "count",
             "runs of the metric's scenario this fit made (its bracket and secant steps; a "
             "joint fit's evaluations, each running every scenario of its targets once, a run made "
             "before reused); 0 "
             "when the target was found unreachable before any run"},
            {"sensitivity", "metric unit per parameter unit",
             "d metric / d parameter between the two runs nearest the fitted value; empty with "
             "fewer than two runs that gave the metric; a joint fit's: from its Jacobian at the "
             "fitted values"},
            {"sensitivities", "text",
             "a joint fit (several targets on one engine): d metric / d each of its parameters "
             "at the fitted values, KEY=VALUE separated by spaces; empty for a one-parameter "
             "fit"},
            {"status", "text",
             "converged (within tolerance), unreachable (the target lies beyond what the "
             "parameter's range or the engine's stability gives, or several targets conflict: "
             "value is the best reached; or the scenario cannot show it at any value: runs 0), "
             "budget (--max-runs spent), failed (no run gave the metric), no engine (the "
             "metric's scenario has no such engine)"}}}};
}

const std::vector<OutputFile>& output_files() {
  static const std::vector<OutputFile> files = [] {
    std::vector<OutputFile> all = run_files();
    for (auto group : {comparison_files(), sweep_files(), fit_files(), baseline_files()})
      all.insert(all.end(), group.begin(), group.end());
    return all;
  }();
  return files;
}

const OutputFile& output_file(std::string_view name) {
  for (const OutputFile& f : output_files())
    if (name == f.name) return f;
  throw std::logic_error("output_file: no output file named " + std::string(name));
}

std::vector<std::string> output_header(std::string_view name) {
  std::vector<std::string> header;
  for (const OutputColumn& c : output_file(name).columns)
    if (std::string_view(c.name) != kVariedKeyColumn) header.emplace_back(c.name);
  return header;
}

std::string output_schema_markdown() {
  std::ostringstream o;
  bool first = true;
  for (const OutputFile& f : output_files()) {
    if (!first) o << '\n';
    first = false;
    o << "### " << f.name << "\n\nWritten by " << f.written_by << "; one row per " << f.row
      << ".\n\n| column | unit | meaning |\n|---|---|---|\n";
    for (const OutputColumn& c : f.columns)
      o << "| `" << c.name << "` | " << c.unit << " | " << markdown_cell(c.meaning) << " |\n";
  }
  return o.str();
}

std::string output_schema_json() {
  std::ostringstream o;
  o << "{\"files\": [";
  bool first_file = true;
  for (const OutputFile& f : output_files()) {
    o << (first_file ? "" : ",") << "\n  {\"name\": " << json_string(f.name)
      << ", \"written_by\": " << json_string(f.written_by) << ", \"row\": " << json_string(f.row)
      << ", \"columns\": [";
    first_file = false;
    bool first = true;
    for (const OutputColumn& c : f.columns) {
      o << (first ? "" : ",") << "\n    {\"name\": " << json_string(c.name)
        << ", \"unit\": " << json_string(c.unit) << ", \"meaning\": " << json_string(c.meaning)
        << "}";
      first = false;
    }
    o << "]}";
  }
  o << "\n]}\n";
  return o.str();
}

}  // namespace clothbench
