#pragma once
/// @file projective.hpp
/// Fast mass-springs (Liu, Bargteil, O'Brien and Kavan 2013), the projective-dynamics solver
/// of backward Euler for springs. A step minimises
///
///   1/(2 h^2) |x - y|_M^2 + sum_s k_s / 2 |x_b - x_a - d_s|^2,   y = x0 + h v0 + h^2 g,
///
/// alternately over the spring directions d_s (local: d_s = l0 (x_b - x_a) / |x_b - x_a|) and
/// the positions (global: (M / h^2 + L) x = M y / h^2 + J d, one constant matrix per held-axis
/// pattern, factorised once per scene and step size and reused). Air drag and the isotropic
/// part of the spring dampers are in that matrix; the dampers' transverse remainder enters
/// the right-hand side at the last iterate's velocity (x - x0) / h. The dampers' directions
/// are frozen at the step's start, as in implicit-euler's line-search mode, so the
/// iterations' fixed point is that mode's backward-Euler step.

#include <memory>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/simulator.hpp"
#include "cloth/model/types.hpp"
#include "cloth/solvers/solver_options.hpp"

namespace cloth {

/// The prefactored global system and scratch of one scene.
class ProjectiveSolver {
 public:
  explicit ProjectiveSolver(const Model& m);
  ~ProjectiveSolver();
  /// One step of h seconds on x and v (each 3 by #P), o.iterations local/global iterations;
  /// returns the energy the dampers and drag took out (J), from the end velocities.
  double step(const Model& m, const SolverOptions& o, double h, Matrix3X& x, Matrix3X& v,
              Counters& counters);

 private:
  struct Factor;
  void factorise(const Model& m, double h);
  void add_velocity_forces(const Model& m, double h, const Matrix3X& x, Matrix3X& rhs) const;
  void add_projections(const Model& m, const Matrix3X& x, Matrix3X& rhs) const;

  double m_h = 0;                                  // the step size the factors are for (s)
  std::vector<std::unique_ptr<Factor>> m_factors;  // one per distinct held-axis pattern
  int m_factor_of_axis[3] = {0, 0, 0};
  Matrix3X m_x0, m_y, m_rhs;
  VectorX m_held, m_b, m_solution;  // one axis of the global solve
};

}  // namespace cloth
