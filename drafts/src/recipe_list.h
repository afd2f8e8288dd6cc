#pragma once
// One function per garment type (recipe_<type>.cpp); each reads its measurements and design
// parameters through the builder and draws into its Pattern.

#include "recipe_common.h"

namespace garmcap::drafts::detail {

void recipeBodice(DraftBuilder& b);
void recipeDress(DraftBuilder& b);
void recipeSkirt(DraftBuilder& b);  // skirt_h and skirt_a
void recipeSkirtHighWaist(DraftBuilder& b);
void recipePants(DraftBuilder& b);
void recipeSleeve(DraftBuilder& b);
void recipeBlouse(DraftBuilder& b);
void recipeDressShift(DraftBuilder& b);
void recipeSweater(DraftBuilder& b);

/// Common last step: seam allowance on every panel, checks that every outline and region is
/// closed and simple (a broken outline is a refusal, never a result).
void finishPattern(DraftBuilder& b);

}  // namespace garmcap::drafts::detail
