#pragma once
/// @file mesh_brute_force.hpp
/// Brute-force references over a triangle mesh that the self-intersection and self-contact
/// tests share: its edges, graph distances and the exact edge-triangle crossing rule.

#include <algorithm>
#include <limits>
#include <queue>
#include <set>
#include <utility>
#include <vector>

#include "cloth/analysis/exact_orient.hpp"
#include "cloth/model/types.hpp"

namespace clothbench::test {

/// The mesh's unique edges (lower index first), sorted.
inline std::vector<std::pair<int, int>> unique_edges(const std::vector<cloth::Triangle>& tris) {
  std::set<std::pair<int, int>> s;
  for (const cloth::Triangle& t : tris)
    for (int k = 0; k < 3; ++k) s.insert(std::minmax(t[k], t[(k + 1) % 3]));
  return {s.begin(), s.end()};
}

/// Graph distances over mesh edges from every vertex (breadth-first search), n by n.
inline std::vector<std::vector<int>> graph_distances(int n,
                                                     const std::vector<cloth::Triangle>& tris) {
  std::vector<std::vector<int>> adj(n);
  for (const auto& [p, q] : unique_edges(tris)) {
    adj[p].push_back(q);
    adj[q].push_back(p);
  }
  std::vector<std::vector<int>> dist(n, std::vector<int>(n, std::numeric_limits<int>::max()));
  for (int s = 0; s < n; ++s) {
    std::queue<int> open;
    dist[s][s] = 0;
    open.push(s);
    while (!open.empty()) {
      const int v = open.front();
      open.pop();
      for (int w : adj[v])
        if (dist[s][w] == std::numeric_limits<int>::max()) {
          dist[s][w] = dist[s][v] + 1;
          open.push(w);
        }
    }
  }
  return dist;
}

/// The crossing rule written out: edge (p, q) properly crosses triangle t's interior in
/// positions x (3 by #P, m), by five exact orientation signs.
inline bool edge_crosses(const cloth::Matrix3X& x, int p, int q, const cloth::Triangle& t) {
  using cloth::orient3d_sign;
  const cloth::Vector3 a = x.col(t[0]), b = x.col(t[1]), c = x.col(t[2]);
  const cloth::Vector3 xp = x.col(p), xq = x.col(q);
  const int sp = orient3d_sign(a, b, c, xp), sq = orient3d_sign(a, b, c, xq);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  const int s1 = orient3d_sign(xp, xq, a, b), s2 = orient3d_sign(xp, xq, b, c),
            s3 = orient3d_sign(xp, xq, c, a);
  return s1 != 0 && s1 == s2 && s2 == s3;
}

}  // namespace clothbench::test
