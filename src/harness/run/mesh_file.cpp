#include "harness/run/mesh_file.hpp"

#include "harness/io/csv_writer.hpp"

namespace clothbench {

std::string rest_mesh_obj(const cloth::Model& model) {
  std::string s = "# the cloth's rest shape, written by clothbench run; units: metres\n";
  for (Eigen::Index p = 0; p < model.x0.cols(); ++p)
    s += "v " + format_double(model.x0(0, p)) + " " + format_double(model.x0(1, p)) + " " +
         format_double(model.x0(2, p)) + "\n";
  for (const cloth::Triangle& t : model.triangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
         std::to_string(t[2] + 1) + "\n";
  return s;
}

}  // namespace clothbench
