#include "cloth/solver_options.hpp"

#include <array>
#include <utility>

namespace cloth {

namespace {

const std::array<std::pair<NewtonMethod, const char*>, 2> kNewtonNames = {
    {{NewtonMethod::linearized, "linearized"}, {NewtonMethod::line_search, "line-search"}}};

const std::array<std::pair<LinearSolver, const char*>, 4> kSolverNames = {
    {{LinearSolver::automatic, "auto"},
     {LinearSolver::cg, "cg"},
     {LinearSolver::block_jacobi_cg, "block-jacobi-cg"},
     {LinearSolver::ldlt, "ldlt"}}};

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

}  // namespace

const char* newton_method_name(NewtonMethod m) { return name_in(kNewtonNames, m); }
std::optional<NewtonMethod> parse_newton_method(std::string_view name) {
  return parse_in(kNewtonNames, name);
}
const char* linear_solver_name(LinearSolver s) { return name_in(kSolverNames, s); }
std::optional<LinearSolver> parse_linear_solver(std::string_view name) {
  return parse_in(kSolverNames, name);
}

SolverOptions line_search_options(LinearSolver solver) {
  SolverOptions o;
  o.integrator = Integrator::implicit_euler;
  o.newton = NewtonMethod::line_search;
  o.newton_iterations = kLineSearchNewtonIterations;
  o.cg_tolerance = kLineSearchCgTolerance;
  o.linear_solver = solver;
  return o;
}

}  // namespace cloth
