#include "cloth/model/spring_set.hpp"

namespace cloth {

const char* spring_kind_name(SpringKind kind) {
  switch (kind) {
    case SpringKind::structural:
      return "structural";
    case SpringKind::shear:
      return "shear";
    case SpringKind::bend:
      return "bend";
  }
  return "?";
}

int SpringSet::count() const {
  int n = 0;
  for (const auto& f : families) n += f.count;
  return n;
}

std::vector<SpringLink> SpringSet::links() const {
  std::vector<SpringLink> out;
  out.reserve(static_cast<size_t>(count()));
  for (const auto& f : families) {
    for (int p = 0; p < f.slots(); ++p) {
      if (f.mask[p] != 0.0) out.push_back({p, p + f.offset, f.rest[p], f.stiffness, f.kind});
    }
  }
  return out;
}

SpringSet build_springs(const ClothParams& c, const Matrix3X& x0) {
  struct Direction {
    SpringKind kind;
    int di, dj;
    double k;
  };
  // structural, shear (both diagonals) and bend directions; each joins (i,j) to (i+di, j+dj)
  const Direction dirs[] = {
      {SpringKind::structural, 1, 0, c.k_structural},
      {SpringKind::structural, 0, 1, c.k_structural},
      {SpringKind::shear, 1, 1, c.k_shear},
      {SpringKind::shear, -1, 1, c.k_shear},
      {SpringKind::bend, 2, 0, c.k_bend},
      {SpringKind::bend, 0, 2, c.k_bend},
  };
  const int n = c.nu * c.nv;
  SpringSet set;
  set.damping = c.damping;
  for (const auto& d : dirs) {
    const int offset = d.dj * c.nu + d.di;
    if (d.k <= 0.0 || offset <= 0 || offset >= n) continue;
    SpringFamily f;
    f.kind = d.kind;
    f.di = d.di;
    f.dj = d.dj;
    f.offset = offset;
    f.stiffness = d.k;
    f.mask = VectorX::Zero(n - offset);
    f.rest = VectorX::Ones(n - offset);
    // anchors whose partner lies inside the grid get a spring
    for (int p = 0; p < n - offset; ++p) {
      const int i = p % c.nu, j = p / c.nu;
      const int i2 = i + d.di, j2 = j + d.dj;
      if (i2 < 0 || i2 >= c.nu || j2 < 0 || j2 >= c.nv) continue;
      f.mask[p] = 1.0;
      f.rest[p] = (x0.col(p + offset) - x0.col(p)).norm();
      ++f.count;
    }
    if (f.count > 0) set.families.push_back(std::move(f));
  }
  return set;
}

}  // namespace cloth
