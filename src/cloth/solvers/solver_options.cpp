#include "cloth/solvers/solver_options.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace cloth {

namespace {

constexpr std::array<std::pair<NewtonMethod, const char*>, 3> kNewtonNames = {
    {{NewtonMethod::linearized, "linearized"},
     {NewtonMethod::line_search, "line-search"},
     {NewtonMethod::trust_region, "trust-region"}}};

constexpr std::array<std::pair<LinearSolver, const char*>, 5> kSolverNames = {
    {{LinearSolver::automatic, "auto"},
     {LinearSolver::cg, "cg"},
     {LinearSolver::block_jacobi_cg, "block-jacobi-cg"},
     {LinearSolver::two_level_cg, "two-level-cg"},
     {LinearSolver::ldlt, "ldlt"}}};

constexpr std::array<std::pair<CgForcing, const char*>, 2> kForcingNames = {
    {{CgForcing::fixed, "fixed"}, {CgForcing::adaptive, "adaptive"}}};

constexpr std::array<std::pair<ContactMode, const char*>, 3> kContactNames = {
    {{ContactMode::after_step, "after-step"},
     {ContactMode::in_solve, "in-solve"},
     {ContactMode::barrier, "barrier"}}};

template <class Table, class Value>
const char* name_in(const Table& table, Value v) {
  for (const auto& [value, name] : table)
    if (value == v) return name;
  return "?";
}

template <class Table>
auto parse_in(const Table& table, std::string_view name)
    -> std::optional<typename Table::value_type::first_type> {
  for (const auto& [value, text] : table)
    if (name == text) return value;
  return std::nullopt;
}

template <class Table>
auto values_in(const Table& table) {
  std::vector<typename Table::value_type::first_type> values;
  for (const auto& entry : table) values.push_back(entry.first);
  return values;
}

}  // namespace

const std::vector<NewtonMethod>& all_newton_methods() {
  static const std::vector<NewtonMethod> all = values_in(kNewtonNames);
  return all;
}
const std::vector<LinearSolver>& all_linear_solvers() {
  static const std::vector<LinearSolver> all = values_in(kSolverNames);
  return all;
}
const std::vector<ContactMode>& all_contact_modes() {
  static const std::vector<ContactMode> all = values_in(kContactNames);
  return all;
}
const std::vector<CgForcing>& all_cg_forcings() {
  static const std::vector<CgForcing> all = values_in(kForcingNames);
  return all;
}

const char* newton_method_name(NewtonMethod m) {
  return name_in(kNewtonNames, m);
}
std::optional<NewtonMethod> parse_newton_method(std::string_view name) {
  return parse_in(kNewtonNames, name);
}
const char* linear_solver_name(LinearSolver s) {
  return name_in(kSolverNames, s);
}
std::optional<LinearSolver> parse_linear_solver(std::string_view name) {
  return parse_in(kSolverNames, name);
}

const char* cg_forcing_name(CgForcing f) {
  return name_in(kForcingNames, f);
}
std::optional<CgForcing> parse_cg_forcing(std::string_view name) {
  return parse_in(kForcingNames, name);
}
const char* contact_mode_name(ContactMode c) {
  return name_in(kContactNames, c);
}
std::optional<ContactMode> parse_contact_mode(std::string_view name) {
  return parse_in(kContactNames, name);
}

double next_forcing(double previous_eta, double residual_ratio, double floor) {
  constexpr double kGamma = 0.9;
  double eta = kGamma * residual_ratio * residual_ratio;
  // the safeguard: do not tighten abruptly while the last forcing term was loose
  const double safeguard = kGamma * previous_eta * previous_eta;
  if (safeguard > 0.1) eta = std::max(eta, safeguard);
  return std::max(floor, std::min(kForcingMax, eta));
}

double forcing_for_tolerance(double eta, double residual, double tolerance) {
  return std::min(kForcingMax, std::max(eta, kOversolveFraction * tolerance / residual));
}

SolverOptions line_search_options(LinearSolver solver) {
  SolverOptions o;
  o.integrator = Integrator::implicit_euler;
  o.newton = NewtonMethod::line_search;
  o.newton_iterations = kLineSearchNewtonIterations;
  o.cg_tolerance = kLineSearchCgTolerance;
  o.cg_forcing = CgForcing::adaptive;
  o.contacts = ContactMode::in_solve;
  o.linear_solver = solver;
  return o;
}

}  // namespace cloth
