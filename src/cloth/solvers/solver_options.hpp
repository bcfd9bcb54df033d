#pragma once
/// @file solver_options.hpp
/// Options of the custom engine: which integrator and how implicit Euler solves.

#include <optional>
#include <string_view>
#include <vector>

#include "cloth/model/integrator.hpp"

namespace cloth {

/// How implicit Euler treats the nonlinear system of a step.
enum class NewtonMethod {
  linearized,   ///< Baraff and Witkin: Newton steps without a line search, from (x0, v0)
  line_search,  ///< Newton on the incremental potential, backtracking line search, residual test
  trust_region  ///< Newton on the incremental potential in a trust region (Steihaug-Toint CG on
                ///< the exact Hessian), residual test
};

/// True for the methods that minimise the step's incremental potential (line-search and
/// trust-region): they share the residual test, the forcing and contacts in the solve.
inline bool minimizes_potential(NewtonMethod m) {
  return m == NewtonMethod::line_search || m == NewtonMethod::trust_region;
}

/// Which linear solver implicit Euler uses for each Newton system.
enum class LinearSolver {
  automatic,        ///< linearized: cg; line-search: block-jacobi-cg, two-level-cg from 48 x 48
                    ///< particles on a grid (fastest measured, README)
  cg,               ///< conjugate gradient, Jacobi (diagonal) preconditioner
  block_jacobi_cg,  ///< conjugate gradient, 3 by 3 block-Jacobi preconditioner (assembled matrix)
  two_level_cg,     ///< block-Jacobi plus a coarse-grid correction (coarse_grid.hpp); grids only
  ldlt              ///< sparse direct LDL^T (Eigen SimplicialLDLT), symbolic factorisation reused
};

/// How tightly implicit Euler solves each Newton system.
enum class CgForcing {
  fixed,    ///< every system to cg_tolerance
  adaptive  ///< line-search: Eisenstat and Walker's forcing terms, never tighter than cg_tolerance
};

/// Where implicit Euler resolves contact with the rigid colliders.
enum class ContactMode {
  after_step,  ///< a projection after the step (every integrator's contact pass)
  in_solve,    ///< line-search: normal velocities held in the solve (contact_constraints.hpp)
  barrier      ///< line-search: a barrier potential in the step's objective (contact_barrier.hpp)
};

/// "linearized", "line-search", "trust-region".
const char* newton_method_name(NewtonMethod m);
/// The method with that name, if any.
std::optional<NewtonMethod> parse_newton_method(std::string_view name);
/// "auto", "cg", "block-jacobi-cg", "two-level-cg", "ldlt".
const char* linear_solver_name(LinearSolver s);
/// The solver with that name, if any.
std::optional<LinearSolver> parse_linear_solver(std::string_view name);

/// "fixed", "adaptive".
const char* cg_forcing_name(CgForcing f);
/// The forcing with that name, if any.
std::optional<CgForcing> parse_cg_forcing(std::string_view name);

/// "after-step", "in-solve", "barrier".
const char* contact_mode_name(ContactMode c);
/// The contact mode with that name, if any.
std::optional<ContactMode> parse_contact_mode(std::string_view name);

/// Every Newton method, every linear solver, every forcing: in the order above (the order the
/// scenario format, the schema and --help list their names).
const std::vector<NewtonMethod>& all_newton_methods();
const std::vector<LinearSolver>& all_linear_solvers();
const std::vector<CgForcing>& all_cg_forcings();
const std::vector<ContactMode>& all_contact_modes();

/// The scenario format's Newton method for an engine that names none: line-search, the mode
/// measured stable on the fabric_128 example at 1/30 s where the linearized step fails at its
/// first step (docs/methods.md). SolverOptions{} itself is the linearized step.
constexpr NewtonMethod kScenarioNewton = NewtonMethod::line_search;
/// The scenario format's contacts with line-search and trust-region when an engine names none:
/// the barrier, whose static colliders never do positive work (in-solve's do, methods.md).
constexpr ContactMode kScenarioLineSearchContacts = ContactMode::barrier;

/// Options of the custom engine. The defaults are the linearized step (Baraff and Witkin); the
/// scenario format's defaults differ for implicit-euler (kScenarioNewton).
struct SolverOptions {
  Integrator integrator = Integrator::rk4;
  NewtonMethod newton = NewtonMethod::linearized;  // implicit-euler
  int newton_iterations = 1;      // implicit-euler: limit; linearized with 1 is Baraff and Witkin
  double newton_tolerance = 0.3;  // implicit-euler, line-search: max |M^-1 residual| / h (m/s^2)
  LinearSolver linear_solver = LinearSolver::automatic;  // implicit-euler
  double cg_tolerance = 1e-8;               // implicit-euler: relative residual |S r| / |S b|
  int cg_max_iterations = 2000;             // implicit-euler
  CgForcing cg_forcing = CgForcing::fixed;  // implicit-euler, line-search
  ContactMode contacts =
      ContactMode::after_step;   // implicit-euler (in-solve, barrier: line-search)
  bool clamp_compressed = true;  // implicit-euler: drop negative transverse stiffness
  // implicit-euler, line-search, CG solvers: Newton iterations per step on the clamped matrix
  // before the exact one (implicit_euler.hpp)
  int clamped_iterations = 2;
  int substeps = 1;     // xpbd: substeps per step
  int iterations = 10;  // xpbd: sweeps per substep; projective: local/global iterations
};

/// Newton iteration limit of line-search mode when the scenario does not give one.
constexpr int kLineSearchNewtonIterations = 20;
/// CG tolerance of line-search mode when the scenario does not give one: an inexact Newton
/// step suffices, since the line search and the residual test decide the accuracy. With
/// adaptive forcing it is the tightest relative residual a system is solved to.
constexpr double kLineSearchCgTolerance = 1e-3;
/// The loosest (and the first) relative residual of adaptive forcing.
constexpr double kForcingMax = 0.5;

/// two-level-cg: fine particles per coarse-grid interval along each grid axis, at most.
constexpr int kCoarsening = 8;

/// Eisenstat and Walker's second forcing term (1996; gamma 0.9, exponent 2, their safeguard):
/// the relative CG residual for the next Newton system.
/// @param previous_eta   the last system's forcing term
/// @param residual_ratio the Newton residual now over the one before the last system
/// @param floor          the tightest forcing term allowed (cg_tolerance)
double next_forcing(double previous_eta, double residual_ratio, double floor);

/// Kelley's safeguard against oversolving (Iterative Methods for Linear and Nonlinear Equations,
/// 1995, eq. 6.20): a forcing term need not take the Newton residual much below the tolerance,
/// so none is tighter than kOversolveFraction tolerance / residual; at most kForcingMax.
/// @param eta        the forcing term from next_forcing
/// @param residual   the Newton residual the next system starts from
/// @param tolerance  the Newton tolerance on that residual (same norm and units)
double forcing_for_tolerance(double eta, double residual, double tolerance);

/// The fraction of the Newton tolerance the last system aims for (Kelley's 0.5).
constexpr double kOversolveFraction = 0.5;

/// Implicit Euler with newton = line-search, that mode's iteration and forcing defaults and
/// contacts in the solve (the scenario format's default contacts are kScenarioLineSearchContacts).
SolverOptions line_search_options(LinearSolver solver = LinearSolver::automatic);

}  // namespace cloth
