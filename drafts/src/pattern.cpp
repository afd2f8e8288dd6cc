#include "garmcap/drafts/pattern.h"

#include <stdexcept>

namespace garmcap::drafts {

const Panel& Pattern::panel(const std::string& name) const {
  for (const auto& p : panels) {
    if (p.name == name)
      return p;
  }
  std::string known;
  for (const auto& p : panels)
    known += (known.empty() ? "" : ", ") + p.name;
  throw std::out_of_range("pattern '" + type + "' has no panel '" + name + "' (panels: " + known +
                          ")");
}

const DraftRegion& Pattern::region(const std::string& name) const {
  for (const auto& r : regions) {
    if (r.name == name)
      return r;
  }
  std::string known;
  for (const auto& r : regions)
    known += (known.empty() ? "" : ", ") + r.name;
  throw std::out_of_range("pattern '" + type + "' has no draft region '" + name +
                          "' (regions: " + known + ")");
}

}  // namespace garmcap::drafts
