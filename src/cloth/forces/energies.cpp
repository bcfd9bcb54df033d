#include "cloth/forces/energies.hpp"

#include "cloth/forces/spring_forces.hpp"

namespace cloth {

Energies compute_energies(const Model& m, const Matrix3X& x, const Matrix3X& v) {
  Energies e;
  e.kinetic = 0.5 * (v.colwise().squaredNorm().transpose().cwiseProduct(m.mass)).sum();
  e.gravity_potential = -((m.gravity.transpose() * x).transpose().cwiseProduct(m.mass)).sum();
  e.elastic_potential = elastic_energy(m.springs, x);
  return e;
}

}  // namespace cloth
