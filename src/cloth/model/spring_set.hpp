#pragma once
/// @file spring_set.hpp
/// The springs of a cloth: a grid's as families of uniform index offsets, any other cloth's
/// (a triangle mesh) as a plain list in structure-of-arrays form.
///
/// Every spring of one direction (say structural along u) joins particle p to p + offset, so
/// a family is an offset plus, per anchor p in [0, #P - offset), a mask (1 where a spring
/// starts at p, 0 where the partner would wrap to another row) and a rest length. Kernels
/// then run one branch-free contiguous loop per family, which the compiler vectorises.
/// The general list has no such structure: its kernels gather both ends of each spring, so it
/// is fast when the particles are numbered for locality (locality_order).
///
/// Springs are visited in groups: group g < families.size() is family g, whose slots are its
/// anchors; group families.size() is the general list, whose slots are its entries. Every
/// per-spring array of the kernels (linearisations, multipliers) is indexed by group and slot.

#include <string>
#include <vector>

#include "cloth/model/bending_form.hpp"
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
  int b = 0;             // particle index, b != a (b > a for a grid family's springs)
  double rest = 0;       // m
  double stiffness = 0;  // N/m
  SpringKind kind = SpringKind::structural;
};

/// Springs as a plain list, one entry per spring in every array (#S entries each). The two
/// ends may come in either order (a < b is not required) but must differ; the force on a is
/// along x_b - x_a, so swapping the ends of a spring changes nothing.
struct SpringList {
  std::vector<int> a;             // #S particle index of one end
  std::vector<int> b;             // #S particle index of the other end
  std::vector<double> rest;       // #S rest length (m), > 0
  std::vector<double> stiffness;  // #S stiffness (N/m)
  std::vector<SpringKind> kind;   // #S kind (bend springs are left out of stretch statistics)

  /// Number of springs, #S.
  int size() const { return static_cast<int>(a.size()); }
  /// True when the list holds no spring.
  bool empty() const { return a.empty(); }
  /// Appends one spring.
  void push_back(const SpringLink& s);
};

/// Every spring of a cloth: a grid's families, then the general list (either may be empty).
struct SpringSet {
  std::vector<SpringFamily> families;
  SpringList list;      // springs of no family (a mesh's), after the families
  double damping = 0;   // N s/m, the same along every spring
  BendingForm bending;  // the hinge model's bending, taken by every kernel here; else empty

  /// Total number of springs.
  int count() const;
  /// The springs as a plain list: family by family, anchors in increasing order, then the
  /// general list in its order.
  std::vector<SpringLink> links() const;
  /// Number of spring groups: one per family, then the general list (families.size() + 1).
  size_t groups() const { return families.size() + 1; }
  /// Stiffness (N/m) of the spring in slot s of group g (see the file comment).
  double stiffness(size_t g, int s) const {
    return g < families.size() ? families[g].stiffness : list.stiffness[size_t(s)];
  }
  /// Rest length (m) of the spring in slot s of group g.
  double rest(size_t g, int s) const {
    return g < families.size() ? families[g].rest[s] : list.rest[size_t(s)];
  }
  /// Kind of the spring in slot s of group g.
  SpringKind kind(size_t g, int s) const {
    return g < families.size() ? families[g].kind : list.kind[size_t(s)];
  }
};

/// Calls visit(p, q, g, s) for every spring, joining particle p to particle q, in slot s of
/// group g (see the file comment): family by family, anchors in order (q = p + offset, s = p),
/// then the general list in its order (s its index); the order of links() and of every
/// per-spring array.
template <class Visit>
void for_each_spring(const SpringSet& springs, Visit&& visit) {
  for (size_t fi = 0; fi < springs.families.size(); ++fi) {
    const SpringFamily& fam = springs.families[fi];
    for (int p = 0; p < fam.slots(); ++p)
      if (fam.mask[p] != 0.0) visit(p, p + fam.offset, fi, p);
  }
  const size_t g = springs.families.size();
  const SpringList& l = springs.list;
  for (int s = 0; s < l.size(); ++s) visit(l.a[size_t(s)], l.b[size_t(s)], g, s);
}

/// The same springs, in the order of links(), as a general list; no families.
SpringSet to_general(const SpringSet& springs);

/// The springs between renumbered particles, as a general list laid out for the kernels: each
/// spring from its lower new end a to its upper one b, in rounds (every particle's first
/// spring by a, then every particle's second, ...), so that consecutive springs mostly start
/// at consecutive particles, which the force kernel loads and updates as vectors. A spring
/// (a, b) goes in the round of (a - 1, b - 1) where it can, so that within a round the other
/// ends b are mostly consecutive as well.
/// @param new_of_old  #P, the new index of each old particle (a permutation)
SpringSet renumbered(const SpringSet& springs, const std::vector<int>& new_of_old);

/// A numbering of the particles that keeps each spring's ends close (small bandwidth), so that
/// the general kernels' gathers stay in cache: reverse Cuthill-McKee, component by component
/// (by lowest particle index), each started from a pseudo-peripheral particle; ties broken by
/// index, so the result depends on the links alone.
/// @param vertex_count  #P
/// @param links         springs between particles in [0, #P)
/// @return #P, the new index of each old particle (new_of_old): a permutation of 0 .. #P - 1
std::vector<int> locality_order(int vertex_count, const std::vector<SpringLink>& links);

/// Builds the families of a grid whose rest shape is x0.
/// @param c   grid size and stiffnesses (a kind with stiffness 0 gets no springs)
/// @param x0  3 by #P rest positions (m)
SpringSet build_springs(const ClothParams& c, const Matrix3X& x0);

}  // namespace cloth
