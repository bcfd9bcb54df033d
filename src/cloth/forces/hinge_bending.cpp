#include "cloth/forces/hinge_bending.hpp"

namespace cloth {

void add_bending_forces(const BendingForm& form, const Matrix3X& x, Matrix3X& f) {
  add_bending_product(form, x, 1.0, f);
}

double bending_energy(const BendingForm& form, const Matrix3X& x) {
  if (form.empty()) return 0.0;
  double e = 0.0;
  for (int r = 0; r < 3; ++r) e += x.row(r).dot((form.q * x.row(r).transpose()).transpose());
  return 0.5 * e;
}

void add_bending_product(const BendingForm& form, const Matrix3X& u, double alpha, Matrix3X& y) {
  if (form.empty()) return;
  // Q is symmetric: a row-major product per coordinate row
  for (int r = 0; r < 3; ++r) y.row(r).transpose() -= alpha * (form.q * u.row(r).transpose());
}

void add_bending_diagonal(const BendingForm& form, double alpha, Matrix3X& diag) {
  if (form.empty()) return;
  const VectorX d = form.q.diagonal();
  for (int r = 0; r < 3; ++r) diag.row(r) -= alpha * d.transpose();
}

}  // namespace cloth
