#include <catch2/catch.hpp>
#include <string>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/model.hpp"
#include "test_scenes.hpp"

using namespace cloth;

namespace {

/// A free 6 x 6 cloth, 1 m square, dropped from 2 cm above the shell of a sphere of radius
/// 0.3 m, with self-collision: within 30 steps of 5 ms its middle lands on the sphere.
Scene draped() {
  Scene s = clothbench::test::small_cloth(6, 20.0, 0.5);
  s.held.clear();
  s.cloth.self_collision = true;
  s.cloth.thickness = 0.02;
  Sphere b;
  b.radius = 0.3;
  s.spheres.push_back(b);
  s.cloth.center = {0.0, b.radius + b.margin + 0.02, 0.0};
  return s;
}

struct Snapshot {
  Matrix3X x, v;
  double t;
};

/// The engine's state after `steps` more steps of h.
Snapshot advance(MassSpringCloth& c, int steps, double h) {
  for (int i = 0; i < steps; ++i) c.step(h);
  return {c.positions(), c.velocities(), c.time()};
}

/// Bitwise equality of two states (NaN-free by construction).
bool same(const Snapshot& a, const Snapshot& b) {
  return a.x == b.x && a.v == b.v && a.t == b.t;
}

}  // namespace

TEST_CASE("after set_state the next steps depend on the state alone", "[integrator][growth]") {
  // every integrator, and implicit Euler's line-search mode with contacts in the solve
  const int variant = GENERATE(range(0, static_cast<int>(all_integrators().size()) + 1));
  SolverOptions o;
  std::string name = "line-search with contacts in the solve";
  if (variant < static_cast<int>(all_integrators().size())) {
    o.integrator = all_integrators()[static_cast<size_t>(variant)];
    name = integrator_name(o.integrator);
  } else {
    o = line_search_options();
    o.contacts = cloth::ContactMode::in_solve;
  }
  const double h = 0.005;
  const int later = 5;  // steps compared after the state is set
  MassSpringCloth a(draped(), o);
  const Snapshot s30 = advance(a, 30, h);
  INFO(name << ": " << a.contacts() << " contacts at step 30");
  REQUIRE(a.contacts() > 0);  // the cloth is on the sphere
  const Snapshot original = advance(a, later, h);
  // a set back to its own earlier state repeats its steps
  a.set_state(s30.x, s30.v, s30.t);
  const Snapshot again = advance(a, later, h);
  CHECK(same(again, original));
  // and a fresh engine set to that state makes the same steps as a, set to it once more
  a.set_state(s30.x, s30.v, s30.t);
  MassSpringCloth b(draped(), o);
  b.set_state(s30.x, s30.v, s30.t);
  CHECK(b.time() == s30.t);
  CHECK(same(advance(a, later, h), advance(b, later, h)));
}
