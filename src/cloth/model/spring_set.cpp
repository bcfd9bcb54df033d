#include "cloth/model/spring_set.hpp"

#include <algorithm>

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

void SpringList::push_back(const SpringLink& s) {
  a.push_back(s.a);
  b.push_back(s.b);
  rest.push_back(s.rest);
  stiffness.push_back(s.stiffness);
  kind.push_back(s.kind);
}

int SpringSet::count() const {
  int n = list.size();
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
  for (size_t s = 0; s < list.a.size(); ++s)
    out.push_back({list.a[s], list.b[s], list.rest[s], list.stiffness[s], list.kind[s]});
  return out;
}

SpringSet to_general(const SpringSet& springs) {
  SpringSet out;
  out.damping = springs.damping;
  out.bending = springs.bending;
  for (const SpringLink& l : springs.links()) out.list.push_back(l);
  return out;
}

namespace {

/// The round of each spring of links (sorted by a, then b): a particle with d springs by a puts
/// them in rounds 0 .. d - 1, one each. A spring (a, b) takes the round of (a - 1, b - 1) where
/// that is free, so that runs of consecutive a in a round mostly have consecutive b as well; the
/// other springs fill the free rounds in order of b.
std::vector<int> spring_rounds(const std::vector<SpringLink>& links) {
  std::vector<int> round(links.size(), -1);
  size_t prev = 0, first = 0;  // the springs of the previous particle: [prev, first)
  while (first < links.size()) {
    size_t last = first;
    while (last < links.size() && links[last].a == links[first].a) ++last;
    const int degree = int(last - first);
    std::vector<char> taken(size_t(degree), 0);
    // the round of the spring one particle back on both ends, where it is free
    const bool chained = first > 0 && links[prev].a == links[first].a - 1;
    for (size_t s = first; s < last && chained; ++s)
      for (size_t t = prev; t < first; ++t) {
        const int r = round[t];
        if (round[s] >= 0 || links[t].b != links[s].b - 1 || r >= degree || taken[size_t(r)])
          continue;
        round[s] = r;
        taken[size_t(r)] = 1;
      }
    // the rest in the free rounds, in order
    int r = 0;
    for (size_t s = first; s < last; ++s) {
      if (round[s] >= 0) continue;
      while (taken[size_t(r)]) ++r;
      round[s] = r;
      taken[size_t(r)] = 1;
    }
    prev = first;
    first = last;
  }
  return round;
}

}  // namespace

SpringSet renumbered(const SpringSet& springs, const std::vector<int>& new_of_old) {
  // each spring from its lower new end a to its upper one b, by a then b
  std::vector<SpringLink> links = springs.links();
  for (SpringLink& l : links) {
    const int a = new_of_old[size_t(l.a)], b = new_of_old[size_t(l.b)];
    l.a = std::min(a, b);
    l.b = std::max(a, b);
  }
  std::stable_sort(links.begin(), links.end(), [](const SpringLink& p, const SpringLink& q) {
    return p.a != q.a ? p.a < q.a : p.b < q.b;
  });
  // then in rounds: every particle's first spring, then every particle's second, ...; within
  // a round the springs' a are increasing, mostly consecutive particles
  const std::vector<int> round = spring_rounds(links);
  std::vector<size_t> order(links.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t p, size_t q) { return round[p] < round[q]; });
  SpringSet out;
  out.damping = springs.damping;
  out.bending = renumbered(springs.bending, new_of_old);
  for (size_t i : order) out.list.push_back(links[i]);
  return out;
}

namespace {

using Adjacency = std::vector<std::vector<int>>;

/// The particles a breadth-first search reaches, level by level.
struct Levels {
  std::vector<int> seen;  // in visiting order
  size_t last = 0;        // where the last level starts in seen
  int eccentricity = 0;   // number of levels less one
};

/// Breadth-first search from root over the particles not yet numbered; depth is -1 for every
/// particle before and after.
Levels reach(const Adjacency& adj, int root, const std::vector<char>& numbered,
             std::vector<int>& depth) {
  Levels out;
  out.seen.push_back(root);
  depth[size_t(root)] = 0;
  for (size_t head = 0; head < out.seen.size(); ++head) {
    const int v = out.seen[head];
    if (depth[size_t(v)] > out.eccentricity) {
      out.eccentricity = depth[size_t(v)];
      out.last = head;
    }
    for (int w : adj[size_t(v)])
      if (!numbered[size_t(w)] && depth[size_t(w)] < 0) {
        depth[size_t(w)] = depth[size_t(v)] + 1;
        out.seen.push_back(w);
      }
  }
  for (int v : out.seen) depth[size_t(v)] = -1;
  return out;
}

/// The particle of least degree in seen from index first on, the lowest index among equals.
int least_degree(const Adjacency& adj, const std::vector<int>& seen, size_t first) {
  int best = seen[first];
  for (size_t i = first; i < seen.size(); ++i) {
    const int v = seen[i];
    const size_t dv = adj[size_t(v)].size(), db = adj[size_t(best)].size();
    if (dv < db || (dv == db && v < best)) best = v;
  }
  return best;
}

/// A pseudo-peripheral particle of root's component (George and Liu, 1979): from the least
/// connected particle, jump to the least connected one of the last level while that lengthens
/// the search.
int peripheral(const Adjacency& adj, int root, const std::vector<char>& numbered,
               std::vector<int>& depth) {
  int r = least_degree(adj, reach(adj, root, numbered, depth).seen, 0);
  Levels lr = reach(adj, r, numbered, depth);
  for (int guard = 0; guard < 16; ++guard) {
    const int x = least_degree(adj, lr.seen, lr.last);
    Levels lx = reach(adj, x, numbered, depth);
    if (lx.eccentricity <= lr.eccentricity) break;
    r = x;
    lr = std::move(lx);
  }
  return r;
}

}  // namespace

std::vector<int> locality_order(int vertex_count, const std::vector<SpringLink>& links) {
  const size_t n = size_t(vertex_count);
  // neighbour lists, sorted, without repeats or self-links
  Adjacency adj(n);
  for (const SpringLink& l : links) {
    if (l.a == l.b) continue;
    adj[size_t(l.a)].push_back(l.b);
    adj[size_t(l.b)].push_back(l.a);
  }
  for (auto& row : adj) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  // cuthill-mckee, component by component: breadth first, neighbours by degree then index
  std::vector<char> numbered(n, 0);
  std::vector<int> depth(n, -1), order, next;
  order.reserve(n);
  for (size_t seed = 0; seed < n; ++seed) {
    if (numbered[seed]) continue;
    const int root = peripheral(adj, int(seed), numbered, depth);
    numbered[size_t(root)] = 1;
    order.push_back(root);
    for (size_t head = order.size() - 1; head < order.size(); ++head) {
      next.clear();
      for (int w : adj[size_t(order[head])])
        if (!numbered[size_t(w)]) next.push_back(w);
      std::sort(next.begin(), next.end(), [&](int p, int q) {
        const size_t dp = adj[size_t(p)].size(), dq = adj[size_t(q)].size();
        return dp != dq ? dp < dq : p < q;
      });
      for (int w : next) {
        numbered[size_t(w)] = 1;
        order.push_back(w);
      }
    }
  }
  // reversed, which shrinks the profile (George, 1971); order[new] = old
  std::vector<int> new_of_old(n);
  for (size_t i = 0; i < n; ++i) new_of_old[size_t(order[n - 1 - i])] = int(i);
  return new_of_old;
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
      {SpringKind::structural, 0, 1, c.structural_v()},
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
