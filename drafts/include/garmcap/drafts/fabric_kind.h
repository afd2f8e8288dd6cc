#pragma once
// The kinds of fabric a garment is made of, as the capture pipeline reads them off a garment and
// the scene simulator draws them: one vocabulary for both. It lives here because drafts is the
// one library both may include (the simulator may not include the pipeline, and the pipeline
// shares no model code with the simulator); only the names are shared, never how a kind is drawn
// or recognised.

#include <string>

namespace garmcap::drafts {

enum class FabricKind { kSolid, kStripes, kChecks, kPrint };

/// "solid", "stripes", "checks" or "print".
std::string fabricKindName(FabricKind kind);
/// Throws std::invalid_argument naming the value and the accepted names.
FabricKind fabricKindFromName(const std::string& name);

}  // namespace garmcap::drafts
