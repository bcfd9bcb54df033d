#pragma once
/// @file spring_set.hpp
/// The springs of a grid, stored as families of uniform index offsets.
///
/// Every spring of one direction (say structural along u) joins particle p to p + offset, so
/// a family is an offset plus, per anchor p in [0, #P - offset), a mask (1 where a spring
/// starts at p, 0 where the partner would wrap to another row) and a rest length. Kernels
/// then run one branch-free contiguous loop per family, which the compiler vectorises.

#include <string>
#include <vector>

#include "cloth/model/scene.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// The three spring kinds of the report.
enum class SpringKind { structural, shear, bend };

/// Name used in messages and CSV ("structural", "shear", "bend").
const char* spring_kind_name(SpringKind kind);

/// All springs joining (i, j) to (i + di, j + dj).
struct SpringFamily {
  SpringKind kind = SpringKind::structural;
  int di = 1;            // grid step along u
  int dj = 0;            // grid step along v
  int offset = 1;        // column offset of the partner: dj * nu + di (> 0)
  double stiffness = 0;  // N/m
  int count = 0;         // real springs in the family
  VectorX mask;          // (#P - offset) 1 where a spring is anchored, else 0
  VectorX rest;          // (#P - offset) rest length (m); 1 where there is no spring

  /// Number of anchor slots (#P - offset).
  int slots() const { return static_cast<int>(mask.size()); }
};

/// One particle pair, for code that wants a plain list (tests, the Bullet adapters).
struct SpringLink {
  int a = 0;             // particle index
  int b = 0;             // particle index, b > a
  double rest = 0;       // m
  double stiffness = 0;  // N/m
  SpringKind kind = SpringKind::structural;
};

/// Every spring of a cloth.
struct SpringSet {
  std::vector<SpringFamily> families;
  double damping = 0;  // N s/m, the same along every spring

  /// Total number of springs.
  int count() const;
  /// The springs as a plain list, family by family, anchors in increasing order.
  std::vector<SpringLink> links() const;
};

/// Calls visit(p, q, fi) for every spring, joining anchor p to q = p + offset in family fi:
/// family by family, anchors in order, the order of every per-spring array.
template <class Visit>
void for_each_spring(const SpringSet& springs, Visit&& visit) {
  for (size_t fi = 0; fi < springs.families.size(); ++fi) {
    const SpringFamily& fam = springs.families[fi];
    for (int p = 0; p < fam.slots(); ++p)
      if (fam.mask[p] != 0.0) visit(p, p + fam.offset, fi);
  }
}

/// Builds the families of a grid whose rest shape is x0.
/// @param c   grid size and stiffnesses (a kind with stiffness 0 gets no springs)
/// @param x0  3 by #P rest positions (m)
SpringSet build_springs(const ClothParams& c, const Matrix3X& x0);

}  // namespace cloth
