#include "harness/sweeps/fit_reach.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "cloth/model/constants.hpp"
#include "cloth/model/model.hpp"
#include "harness/fabric/elastica.hpp"

namespace clothbench {

double cantilever_overhang(const Scenario& s) {
  if (s.test.kind != "cantilever") return NAN;
  const cloth::Model model = cloth::build_model(s.scene);
  const cloth::Matrix3X& x0 = model.x0;
  // the last held column at or below the edge, and the tip, by rest x
  double clamp = -std::numeric_limits<double>::infinity();
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (size_t(p) < s.scene.held.size() && s.scene.held[size_t(p)] && x0(0, p) <= s.test.edge)
      clamp = std::max(clamp, x0(0, p));
  const double tip = x0.cols() > 0 ? x0.row(0).maxCoeff() : NAN;
  return std::isfinite(clamp) && tip > clamp ? tip - clamp : NAN;
}

std::optional<std::string> unmeasurable_target(const std::string& metric, double target,
                                               double tolerance, const Scenario& s) {
  if (metric != "bending_length" && metric != "flexural_rigidity") return std::nullopt;
  const double l = cantilever_overhang(s);
  if (!std::isfinite(l)) return std::nullopt;
  // the shortest c the elastica gives at this overhang, and the target's c
  const double c_min = l / kMaxElasticaLambda;
  const double weight = s.scene.cloth.areal_density * s.scene.gravity.norm();
  double c = target + tolerance;
  if (metric == "flexural_rigidity") {
    if (!(weight > 0.0)) return std::nullopt;
    c = std::cbrt((target + tolerance) / weight);
  }
  if (!(c < c_min)) return std::nullopt;
  const double chord = elastica_chord_angle(kMaxElasticaLambda) * 180.0 / cloth::kPi;
  const double c_target = metric == "bending_length" ? target : std::cbrt(target / weight);
  char text[512];
  std::snprintf(text, sizeof text,
                "%s %.4g lies below what the %.4g m overhang can show at any stiffness: a "
                "bending length under l / %.0f = %.4g m bends the chord past %.1f degrees, where "
                "the elastica gives no value; shorten the overhang (the strip beyond [test] "
                "edge) to at most %.0f c = %.4g m, or lengthen the target",
                metric.c_str(), target, l, kMaxElasticaLambda, c_min, chord, kMaxElasticaLambda,
                kMaxElasticaLambda * c_target);
  return std::string(text);
}

}  // namespace clothbench
