#include "reference/bullet/bullet_options.hpp"

namespace clothbench::reference {

const char* softbody_stiffness_name(SoftbodyStiffness s) {
  return s == SoftbodyStiffness::klst ? "klst" : "matched";
}

std::optional<SoftbodyStiffness> parse_softbody_stiffness(const std::string& name) {
  for (SoftbodyStiffness s : {SoftbodyStiffness::matched, SoftbodyStiffness::klst})
    if (name == softbody_stiffness_name(s)) return s;
  return std::nullopt;
}

}  // namespace clothbench::reference
