#pragma once
/// @file self_contact.hpp
/// Cloth-on-cloth contact as a pass after each step, after Bridson, Fedkiw and Anderson,
/// "Robust treatment of collisions, contact and friction for cloth animation", SIGGRAPH 2002.
///
/// The pass replaces the step's average velocity vbar = (x - x_start) / h by a collision-free
/// vbar' in three stages:
///  1. proximity, at x_start, on vertex-triangle and edge-edge pairs more than two rings apart
///     (graph distance over mesh edges, the self-intersection meter's rule: a vertex-triangle
///     pair is left out when the vertex is within two edges of a triangle vertex, an edge-edge
///     pair when an endpoint of one is within two edges of an endpoint of the other) that are
///     closer than the thickness: an inelastic impulse that stops the approach, a repulsion
///     that raises the separating speed to 0.1 (rest_gap thickness - distance) / h but never by
///     more than the spring impulse h k (rest_gap thickness - distance) (the paper's limit,
///     k = repulsion_stiffness), and Coulomb friction that cuts the relative tangential speed by
///     at most mu times the normal speed change. The repulsion's rest distance lies just inside
///     the contact band (rest_gap = 0.99), so a resting pair stays in contact (and in friction)
///     instead of hopping out of the band when round-off lifts it to the thickness;
///  2. continuous collision check on x_start -> x_start + h vbar': the times the four points
///     are coplanar (a cubic, roots bracketed on its monotone pieces and bisected), the
///     distance at each such time, and the distance at the step's end. A pair collides when
///     it comes closer than min_gap times the thickness at a coplanar time, or ends closer
///     than that and closer than it started. A collision gets an inelastic impulse that aims
///     the pair's end separation along the collision normal at aim_gap times the thickness
///     (a positive gap, never an exact touch); at most ccd_iterations rounds. With
///     near_collisions (the default) this check covers every pair sharing no vertex, the
///     pairs within two rings included: the meter counts their crossings too, and at a few
///     edge lengths per step the impulses alone can fold a sheet through a neighbour
///     triangle. Without it the check keeps the two-ring rule;
///  3. rigid impact zones as the fail-safe: the vertices of still-colliding pairs merge into
///     zones whose velocities become one rigid motion, v_cm + w x (x_start - c), with the
///     zone's linear and angular momentum about its centre of mass c (so both are conserved
///     exactly); repeated until no pair collides, at most zone_iterations rounds. The
///     linearised rotation is an invertible affine map of the zone over the step, so no pair
///     inside a zone can cross. A zone holding an infinitely heavy vertex (inv_mass 0)
///     moves its free vertices with the mean vbar of its heavy ones (a resting or held layer
///     carries them along); if collisions remain after the last round, every free vertex
///     keeps x_start and resolved is false.
/// Impulses act on the pair's points with barycentric weights w (summing to zero over the
/// pair) scaled by the inverse masses, so linear momentum is conserved to round-off when no
/// vertex is infinitely heavy; normal impulses along the closest-point direction conserve
/// angular momentum too.
///
/// Broad phase: one candidate list serves every stage and every round, and is kept from call to
/// call. Each vertex gets an anchor (its position at the build) and a radius (half the
/// thickness plus 8 times its move over the path the list is built for); a uniform spatial hash
/// over boxes holding those balls (elements' boxes the unions of their vertices'; cells the
/// median triangle box, at least twice the thickness; a box over more than 64 cells is
/// checked against every element instead) gives the pairs that can come within the thickness,
/// and those farther apart at the anchors than the thickness plus both elements' largest
/// radius are dropped (inside the balls they never come that close). The list is rebuilt only
/// when a stage's path x_start -> end leaves a vertex's ball, so a slow or resting cloth
/// rebuilds it once in many steps. A stage skips the candidates that its vertices' distances
/// from their anchors prove apart, then keeps exactly the pairs a broad phase of its own would
/// keep (boxes of the stage's paths, the first element's inflated by the thickness or by
/// min_gap times it, overlapping), in the list's order: vertex-triangle pairs by vertex, then
/// edge-edge pairs by edge, each element's pairs by their vertices. So the result depends on
/// the positions alone, not on the cells or on what was cached. tests in the stats counts the
/// distance tests of the builds and the stages' narrow-phase tests. resolve() keeps its
/// buffers as members, so it allocates only when a call needs more room than every earlier
/// one (proximities() allocates).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "cloth/model/types.hpp"

namespace cloth {

/// Options of the self-contact pass.
struct SelfContactParams {
  double thickness = 0.004;              // m, distance kept between layers (> 0)
  double friction = 0.0;                 // Coulomb coefficient, cloth on cloth (>= 0)
  double repulsion_stiffness = 10000.0;  // N/m, k of the repulsion's spring limit (>= 0)
  double aim_gap = 0.1;                  // fraction of thickness a collision response aims at
  double min_gap = 0.01;                 // fraction of thickness closer than which is a collision
  double rest_gap = 0.99;                // fraction of thickness the repulsion lifts a pair to
  bool near_collisions = true;           // the continuous check also covers pairs within two
                                         // rings that share no vertex (see the file comment)
  int ccd_iterations = 5;                // rounds of collision impulses before the zones (>= 0)
  int zone_iterations = 100;             // rounds of impact-zone merging (>= 1)
};

/// What one pass did (all counts, for the run's counters).
struct SelfContactStats {
  int proximities = 0;     // vertex-triangle + edge-edge pairs within thickness at the start
  int ccd_collisions = 0;  // collisions the continuous check found (all iterations)
  int impact_zones = 0;    // zones the fail-safe rigidified
  std::int64_t tests = 0;  // narrow-phase pair tests (the work count)
  bool resolved = true;    // false if the pass could not make the step collision free
};

/// Which elements a pair joins.
enum class PairKind : std::uint8_t { kVertexTriangle, kEdgeEdge };

/// Two elements near each other: a vertex and a triangle (vertices = {v, a, b, c}) or two
/// edges (vertices = {p0, p1, q0, q1}), and their distance (m).
struct ProximityPair {
  PairKind kind = PairKind::kVertexTriangle;
  std::array<int, 4> vertices = {0, 0, 0, 0};
  double distance = 0;  // m
};

/// The self-contact pass of one triangle surface (any number of disconnected pieces).
class SelfContact {
 public:
  /// triangles over particle_count vertices. Throws std::invalid_argument on an index out of
  /// range, a triangle repeating a vertex or a parameter out of its range.
  SelfContact(int particle_count, std::vector<Triangle> triangles, SelfContactParams p);

  /// One step of h s: x_start (3 by #P, m) the crossing-free positions at the step's start,
  /// x (3 by #P, m) the integrator's end positions, v (3 by #P, m/s) its end velocities,
  /// inv_mass (#P, 1/kg; 0 = infinitely heavy: held, handled or resting on a collider).
  /// Replaces the step's average velocity vbar = (x - x_start)/h by a collision-free one
  /// vbar', sets x = x_start + h vbar' and v += vbar' - vbar.
  SelfContactStats resolve(double h, const Matrix3X& x_start, Matrix3X& x, Matrix3X& v,
                           const VectorX& inv_mass);

  /// Every pair more than two rings apart closer than the thickness in positions x (3 by #P,
  /// m), vertex-triangle pairs first, each in element order.
  std::vector<ProximityPair> proximities(const Matrix3X& x) const;

  /// The closest pair of elements more than two rings apart that are closer than the
  /// thickness in positions x (3 by #P, m), or nullopt if none.
  std::optional<ProximityPair> closest_violation(const Matrix3X& x) const;

  /// True when vertices v and w are at most two mesh edges apart (v == w included).
  bool within_two_rings(int v, int w) const;

  /// Drops the candidate list, so the next resolve() builds it afresh, as a new pass would
  /// (Simulator::set_state: the next step then depends on its inputs alone, counts included).
  void forget_candidates();

  /// The options the pass was built with.
  const SelfContactParams& params() const { return m_params; }

 private:
  struct Scratch;
  struct Pass;
  /// Candidate pairs into s.pairs: elements whose boxes, the unions of their vertices' boxes
  /// s.vert_box, come within pad (m), minus the two-ring pairs (rings) or only the pairs
  /// sharing a vertex; by first element, each element's by vertices.
  void collect_pairs(double pad, bool rings, Scratch& s) const;
  /// Rebuilds the candidates unless every vertex's path from a to b (3 by #P, m) lies in its
  /// ball of the last build (anchor and radius), keeping only pairs that can come within the
  /// thickness inside their balls; sets each vertex's distance from its anchor on the path.
  /// Returns the distance tests of a rebuild (0 without one).
  std::int64_t update_candidates(const Matrix3X& a, const Matrix3X& b, Scratch& s) const;
  /// Stage 1: proximity impulses, repulsion and friction at x_start.
  void proximity_pass(Pass& p);
  /// One continuous check of every candidate: impulses on the colliding pairs, or (impulses
  /// false) their vertices merged into zones; skip_rigid leaves out pairs inside a rigid zone.
  /// Returns the number of collisions found.
  int collision_round(Pass& p, bool impulses, bool skip_rigid);
  /// Stage 3: impact zones until collision free; false when the rounds ran out.
  bool zone_pass(Pass& p);
  /// Replaces the velocities of one zone (root, its vertices) by its rigid motion.
  void rigidify(Pass& p, int root, const std::vector<int>& members);
  /// True when the pair is left out: within two rings (rings) or sharing a vertex.
  bool excluded(PairKind kind, const std::array<int, 4>& q, bool rings) const;

  int m_count = 0;
  std::vector<Triangle> m_triangles;
  SelfContactParams m_params;
  std::vector<std::array<int, 2>> m_edges;  // #E unique edges (lo, hi), sorted
  std::vector<int> m_adj_start, m_adj;      // vertex neighbours, CSR, sorted
  /// The broad phase's buffers, reused between calls; a copy starts with empty ones.
  struct ScratchHolder {
    ScratchHolder();
    ~ScratchHolder();
    ScratchHolder(const ScratchHolder&);
    ScratchHolder& operator=(const ScratchHolder&);
    std::unique_ptr<Scratch> ptr;
  };
  ScratchHolder m_scratch;
  Matrix3X m_vbar;                        // 3 by #P, vbar' during a pass (m/s)
  std::vector<int> m_parent;              // #P impact-zone union-find (root: least index)
  std::vector<int> m_zone_start, m_fill;  // zones grouped by root, CSR over m_order
  std::vector<int> m_order, m_members;    // vertices by zone; one zone's vertices
  std::vector<char> m_rigid;              // #P: the zone of this root moves rigidly
};

}  // namespace cloth
