#pragma once
/// @file ensemble_runs.hpp
/// The members of a scenario's ensembles (tolerances_file.hpp, [ensemble.<engine>]): run,
/// summarized, and counted. An engine's ensemble has members = N fixed in its tolerances, or
/// the count its baseline recorded, which check --update chose from the measured spread:
/// the fewest members (at least kMinChosenMembers) with which Welch's test catches each
/// quantity's stated `detect` shift with probability kEnsemblePower (ensemble_size.hpp), or as
/// many as `max_seconds` of member runs allow when the goals need more.

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cloth/model/types.hpp"
#include "harness/gate/ensemble_gate.hpp"
#include "harness/gate/tolerances_file.hpp"
#include "harness/run/runner.hpp"

namespace clothbench {

/// Members run first when check --update chooses N, and the fewest it records.
constexpr int kPilotMembers = 8;
constexpr int kMinChosenMembers = 4;

using EnsembleSizes = std::map<std::string, int>;             // members, by engine
using EngineShapes = std::map<std::string, cloth::Matrix3X>;  // 3 by #P, by engine

/// How check --update chose one engine's ensemble size.
struct EnsembleChoice {
  int members = 0;            // recorded
  int cap = 0;                // most members max_seconds allows
  double member_seconds = 0;  // s, mean wall time of a member run that includes the engine
  bool capped = false;        // the cap, not the goals, set members
  std::map<std::string, double> detectable;  // by quantity: shift caught at `members`
};

/// The members of one scenario's ensembles, run as they are asked for. Member 0 is the run
/// given; member m >= 1 runs the scene perturbed at round-off (ensemble_member.hpp, drawn with
/// `seed`) with the engines that need it and the reference.
class EnsembleMembers {
 public:
  EnsembleMembers(const Scenario& sc, const Tolerances& tol, const RunResult& run0,
                  const EngineShapes& shapes, int jobs, std::uint64_t seed);

  /// Runs, on `jobs` threads, the members 1..sizes[engine]-1 each engine does not have yet.
  void run_up_to(const EnsembleSizes& sizes);
  /// Each engine's members 0..sizes[engine]-1 by "engine/quantity" (final_shape_rms from
  /// `shapes`), and its growth exponent between members 0 and 1 ("engine/growth_exponent").
  EnsembleValues values(const EnsembleSizes& sizes) const;
  /// Mean wall time (s) of the member runs (m >= 1) that included engine; 0 before any.
  double member_seconds(const std::string& engine) const;
  /// Members of engine run so far, member 0 included.
  int count(const std::string& engine) const;

 private:
  struct End {
    std::map<std::string, double> values;  // metrics.csv's quantities, final_shape_rms and
                                           // the [test]'s metrics (test.<metric>)
    cloth::Matrix3X start, end;            // first and last positions, 3 by #P
    double t_end = 0;                      // s, time of the last frame
  };
  void summarize(int member, const RunResult& r);

  const Scenario& m_sc;
  const Tolerances& m_tol;
  const EngineShapes& m_shapes;
  int m_jobs;
  std::uint64_t m_seed;
  std::map<std::string, std::vector<End>> m_ends;        // by engine, in member order
  std::map<std::string, std::vector<double>> m_seconds;  // by engine, one per member run
};

/// The sizes a check runs: members = N where the tolerances fix it, else the count the
/// baseline recorded (kPilotMembers when it recorded none, at least 2).
EnsembleSizes recorded_sizes(const Tolerances& tol, const EnsembleValues& recorded);

/// check --update: runs the fixed ensembles and chooses (running members as it goes) the size
/// of each ensemble with `detect`, Welch's test at level alpha. Writes the sizes to record to
/// sizes and returns the choices by engine; with progress, says on stderr what it runs.
std::map<std::string, EnsembleChoice> choose_sizes(EnsembleMembers& members, const Tolerances& tol,
                                                   double alpha, bool progress,
                                                   EnsembleSizes& sizes);

/// Sample standard deviation of the finite values of v (NaN with fewer than 2).
double finite_spread(const std::vector<double>& v);

}  // namespace clothbench
