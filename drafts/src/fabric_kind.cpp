#include "garmcap/drafts/fabric_kind.h"

#include <stdexcept>

namespace garmcap::drafts {

std::string fabricKindName(FabricKind kind) {
  switch (kind) {
    case FabricKind::kSolid:
      return "solid";
    case FabricKind::kStripes:
      return "stripes";
    case FabricKind::kChecks:
      return "checks";
    case FabricKind::kPrint:
      return "print";
  }
  return "solid";
}

FabricKind fabricKindFromName(const std::string& name) {
  if (name == "solid")
    return FabricKind::kSolid;
  if (name == "stripes")
    return FabricKind::kStripes;
  if (name == "checks")
    return FabricKind::kChecks;
  if (name == "print")
    return FabricKind::kPrint;
  throw std::invalid_argument("unknown fabric kind '" + name +
                              "' (expected solid, stripes, checks or print)");
}

}  // namespace garmcap::drafts
