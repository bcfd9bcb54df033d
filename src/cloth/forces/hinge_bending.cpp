#include "cloth/forces/hinge_bending.hpp"

namespace cloth {

void add_bending_forces(const BendingForm& form, const Matrix3X& x, Matrix3X& f) {
  add_bending_product(form, x, 1.0, f);
}

double bending_energy(const BendingForm& form, const Matrix3X& x) {
  if (form.empty()) return 0.0;
  // (Q x_r) column by column, dotted with x as it comes: no temporary vector
  double e = 0.0;
  for (int col = 0; col < form.q.outerSize(); ++col) {
    Vector3 qx = Vector3::Zero();
    for (Eigen::SparseMatrix<double>::InnerIterator it(form.q, col); it; ++it)
      qx += it.value() * x.col(it.row());
    e += qx.dot(x.col(col));
  }
  return 0.5 * e;
}

void add_bending_product(const BendingForm& form, const Matrix3X& u, double alpha, Matrix3X& y) {
  if (form.empty()) return;
  // y_r -= alpha Q u_r for the three rows in one pass over Q's columns: no temporary
  for (int col = 0; col < form.q.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(form.q, col); it; ++it) {
      const double q = alpha * it.value();
      for (int r = 0; r < 3; ++r) y(r, it.row()) -= q * u(r, col);
    }
}

void add_bending_diagonal(const BendingForm& form, double alpha, Matrix3X& diag) {
  if (form.empty()) return;
  for (int col = 0; col < form.q.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(form.q, col); it; ++it)
      if (it.row() == col) diag.col(col).array() -= alpha * it.value();
}

}  // namespace cloth
