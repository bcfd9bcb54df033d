#include "reference/bullet/bullet_options.hpp"

namespace clothbench::reference {

const char* softbody_stiffness_name(SoftbodyStiffness s) {
  switch (s) {
    case SoftbodyStiffness::matched:
      return "matched";
    case SoftbodyStiffness::klst:
      return "klst";
  }
  return "?";
}

const std::vector<SoftbodyStiffness>& all_softbody_stiffnesses() {
  static const std::vector<SoftbodyStiffness> all = {SoftbodyStiffness::matched,
                                                     SoftbodyStiffness::klst};
  return all;
}

std::optional<SoftbodyStiffness> parse_softbody_stiffness(const std::string& name) {
  for (SoftbodyStiffness s : all_softbody_stiffnesses())
    if (name == softbody_stiffness_name(s)) return s;
  return std::nullopt;
}

}  // namespace clothbench::reference
