// Simulator::set_state on the Bullet engines: a state taken from a run, set into a fresh engine
// or back into the run's own engine, steps to the state the run stepped to, bit for bit (the
// growth measurement's finite differences need the step map to be a function of the state).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cloth/model/model.hpp"
#include "harness/engines/engine_factory.hpp"

using namespace cloth;
using clothbench::EngineSpec;
using clothbench::make_engine;

namespace {

constexpr double kDt = 1e-3;      // s
constexpr double kRadius = 0.2;   // m, the sphere's
constexpr double kMargin = 0.01;  // m, its contact shell
/// Steps compared after a state is set: more than one, since Bullet's first step takes
/// constants (the rest lengths) from the nodes that the later steps use.
constexpr int kNext = 3;

struct Variant {
  const char* kind;
  bool implicit;
};

const Variant kVariants[] = {
    {"bullet-softbody", false}, {"bullet-deformable", false}, {"bullet-deformable", true}};

std::string variant_name(const Variant& v) {
  return std::string(v.kind) + (v.implicit ? " implicit" : "");
}

std::unique_ptr<Simulator> engine(const Variant& v, const Scene& s) {
  EngineSpec e;
  e.name = v.kind;
  e.kind = *clothbench::parse_engine_kind(v.kind);
  e.dt = kDt;
  e.bullet.implicit = v.implicit;
  return make_engine(e, s);
}

/// A 7 x 7 cloth, 0.6 m square, level, its lowest point gap above the contact shell of a
/// sphere at the origin that rises at 5 cm/s (a kinematic body, whose velocity Bullet takes
/// from its last pose), with friction and air drag; two corners pinned and one edge particle
/// held in x and z, so that held axes are projected too.
Scene falling_cloth(double gap) {
  Scene s;
  s.cloth.nu = 7;
  s.cloth.nv = 7;
  s.cloth.size_u = 0.6;
  s.cloth.size_v = 0.6;
  s.cloth.center = {0.0, kRadius + kMargin + gap, 0.0};
  s.cloth.plane = Plane::xz;
  s.cloth.particle_mass = 0.01;
  s.cloth.k_structural = 50.0;
  s.cloth.k_shear = 50.0;
  s.cloth.k_bend = 5.0;
  s.cloth.damping = 0.05;
  s.cloth.air_drag = 0.001;
  Sphere ball;
  ball.radius = kRadius;
  ball.margin = kMargin;
  ball.friction = 0.3;
  ball.velocity = {0.0, 0.05, 0.0};
  s.spheres.push_back(ball);
  s.held.assign(static_cast<size_t>(s.particle_count()), 0);
  s.held[static_cast<size_t>(particle_index(s.cloth, 0, 0))] = kHoldAll;
  s.held[static_cast<size_t>(particle_index(s.cloth, 6, 6))] = kHoldAll;
  s.held[static_cast<size_t>(particle_index(s.cloth, 3, 0))] = kHoldX | kHoldZ;
  return s;
}

struct State {
  Matrix3X x, v;
  double t = 0;
};

State state_of(const Simulator& e) {
  return {e.positions(), e.velocities(), e.time()};
}

/// Largest difference of a position or velocity component between e's state and s (m or m/s).
double off(const Simulator& e, const State& s) {
  return std::max((e.positions() - s.x).cwiseAbs().maxCoeff(),
                  (e.velocities() - s.v).cwiseAbs().maxCoeff());
}

/// The particle nearest the sphere's surface in state s.
int nearest(const Scene& scene, const State& s) {
  const Vector3 c = scene.spheres[0].center_at(s.t);
  const Eigen::RowVectorXd r = (s.x.colwise() - c).colwise().norm();
  Eigen::Index p = 0;
  r.minCoeff(&p);
  return static_cast<int>(p);
}

/// Distance of particle p from the sphere's contact shell in state s (m, negative inside).
double above_shell(const Scene& scene, const State& s, int p) {
  const Sphere& b = scene.spheres[0];
  return (s.x.col(p) - b.center_at(s.t)).norm() - b.radius - b.margin;
}

/// Steps e until its last step was the first in which a contact pushed the particle nearest
/// the sphere up (its vertical velocity rose, where gravity alone lowers it by g dt and the
/// springs of the falling cloth, barely stretched, cannot make up for that), and returns the
/// state before that step.
State before_first_push(Simulator& e, const Scene& scene) {
  for (int i = 0; i < 100; ++i) {
    const State s = state_of(e);
    const int p = nearest(scene, s);
    e.step(kDt);
    if (e.velocities()(1, p) > s.v(1, p)) return s;
  }
  FAIL("no contact within 100 steps");
  return {};
}

/// The run's next `count` states after e's current one (e steps on).
std::vector<State> next_states(Simulator& e, int count) {
  std::vector<State> next;
  for (int i = 0; i < count; ++i) {
    e.step(kDt);
    next.push_back(state_of(e));
  }
  return next;
}

/// Largest difference (m or m/s) between the states e steps to from its current one and next.
double off_along(Simulator& e, const std::vector<State>& next) {
  double most = 0.0;
  for (const State& n : next) {
    e.step(kDt);
    most = std::max(most, off(e, n));
  }
  return most;
}

/// The two checks on one state s of a run in engine a, whose next states are next: a fresh
/// engine set to s steps to them, and a, moved on and set back to s, twice, steps to them each
/// time.
void check_map(const Variant& v, const Scene& scene, Simulator& a, const State& s,
               const std::vector<State>& next) {
  REQUIRE((next.front().x - s.x).cwiseAbs().maxCoeff() > 0.0);
  auto b = engine(v, scene);
  b->set_state(s.x, s.v, s.t);
  CHECK(off(*b, s) == 0.0);
  CHECK(b->time() == s.t);
  CHECK(off_along(*b, next) == 0.0);
  CHECK(b->time() == next.back().t);
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < 5; ++i) a.step(kDt);
    a.set_state(s.x, s.v, s.t);
    CHECK(off_along(a, next) == 0.0);
  }
}

}  // namespace

TEST_CASE("a Bullet engine set to a run's state steps to the run's next state, clear of contact",
          "[bullet][set-state]") {
  const Variant v = GENERATE(from_range(std::begin(kVariants), std::end(kVariants)));
  INFO(variant_name(v));
  const Scene scene = falling_cloth(0.05);
  auto a = engine(v, scene);
  REQUIRE(a->can_set_state());
  for (int i = 0; i < 30; ++i) a->step(kDt);
  const State s = state_of(*a);
  const std::vector<State> next = next_states(*a, kNext);
  // 5 cm up, the cloth is still well clear of the shell after these steps
  const State& last = next.back();
  REQUIRE(above_shell(scene, last, nearest(scene, last)) > 0.03);
  check_map(v, scene, *a, s, next);
}

TEST_CASE("a Bullet engine with a handle set to a run's state steps to the run's next state",
          "[bullet][set-state]") {
  // the handle's node is put on its path at the end of every step, from the time
  const Variant v = GENERATE(from_range(std::begin(kVariants), std::end(kVariants)));
  INFO(variant_name(v));
  Scene scene = falling_cloth(0.05);
  Handle h;
  h.particles = {particle_index(scene.cloth, 6, 0)};
  h.motion.path = {{0.0, 0.0, 0.0, 0.0}, {0.02, 0.0, 0.002, 0.0}, {1.0, 0.1, 0.002, 0.0}};
  scene.handles.push_back(h);
  auto a = engine(v, scene);
  for (int i = 0; i < 30; ++i) a->step(kDt);
  const State s = state_of(*a);
  const std::vector<State> next = next_states(*a, kNext);
  check_map(v, scene, *a, s, next);
}

TEST_CASE("a Bullet engine set to a run's state steps to the run's next state, in contact",
          "[bullet][set-state]") {
  const Variant v = GENERATE(from_range(std::begin(kVariants), std::end(kVariants)));
  INFO(variant_name(v));
  // 5.5 mm up, the cloth meets the rising sphere after about 28 steps
  const Scene scene = falling_cloth(0.0055);
  SECTION("the step in which the contact starts") {
    auto a = engine(v, scene);
    const State s = before_first_push(*a, scene);
    // the push is the first of the next states; the run goes on from there
    std::vector<State> next = {state_of(*a)};
    for (const State& n : next_states(*a, kNext - 1)) next.push_back(n);
    INFO("pushed in step " << std::lround(next.front().t / kDt));
    check_map(v, scene, *a, s, next);
  }
  SECTION("a step three steps into the contact") {
    auto a = engine(v, scene);
    before_first_push(*a, scene);
    for (int i = 0; i < 3; ++i) a->step(kDt);
    const State s = state_of(*a);
    const std::vector<State> next = next_states(*a, kNext);
    const State& first = next.front();
    INFO("nearest particle " << above_shell(scene, first, nearest(scene, first))
                             << " m off the shell");
    check_map(v, scene, *a, s, next);
  }
}

TEST_CASE("a Bullet engine's set_state moves its kinematic sphere to the state's time",
          "[bullet][set-state]") {
  // A fresh engine's sphere is at its start; set to t = 30 ms, the sphere must be where it is
  // at t, with the last pose there too, else Bullet takes the jump as the sphere's velocity.
  // The state: the flat cloth at rest at t = 30 ms, its middle particle 0.1 mm inside the
  // shell over the sphere's top, where the rising sphere pushes it up.
  const Variant v = GENERATE(from_range(std::begin(kVariants), std::end(kVariants)));
  INFO(variant_name(v));
  const Scene scene = falling_cloth(0.05);
  const Model model = build_model(scene);
  auto b = engine(v, scene);
  const double t = 0.03;
  const int top = particle_index(scene.cloth, 3, 3);
  Matrix3X x = model.x0;
  x(1, top) = scene.spheres[0].center_at(t).y() + kRadius + kMargin - 1e-4;
  const Matrix3X v0 = Matrix3X::Zero(3, x.cols());
  b->set_state(x, v0, t);
  b->step(kDt);
  // it moved up, slower than the 30 ms x 5 cm/s / 1 ms = 1.5 m/s a sphere jumping from its
  // start would give it (measured: 0.05 m/s implicit, 0.13 m/s explicit, 0.37 m/s for the
  // classic soft body, whose contact projection runs in each of its 10 iterations; and 1.55 to
  // 1.85 m/s with the sphere left at its start)
  const double rise = b->positions()(1, top) - x(1, top);
  INFO("rise " << rise << " m in one step");
  CHECK(rise > 0.0);
  CHECK(b->velocities()(1, top) < 0.5);
}

TEST_CASE("a Bullet engine refuses a state of the wrong size", "[bullet][set-state]") {
  const Variant v = GENERATE(from_range(std::begin(kVariants), std::end(kVariants)));
  INFO(variant_name(v));
  auto b = engine(v, falling_cloth(0.05));
  const Matrix3X x = b->positions(), v0 = b->velocities();
  CHECK_THROWS_AS(b->set_state(x.leftCols(3), v0, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(b->set_state(x, v0.leftCols(3), 0.0), std::invalid_argument);
}
