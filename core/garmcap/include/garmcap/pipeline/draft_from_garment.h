#pragma once
// From what the photo measured (garment type, attributes, garment measurements in cm) to a
// parameterized draft (seed §5.2.6): the form is the body the garment was worn on, so ease is the
// garment's circumference minus the form's, and lengths come from the measured lengths.

#include <map>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::pipeline {

struct DraftChoice {
  std::string recipe;                    // drafts recipe name
  std::map<std::string, double> design;  // design parameters given to it
};

/// The recipe and design parameters for a captured garment. Values outside a parameter's range
/// are clamped and a warning says so. `sideNeckToWaistCm` is the form's vertical side-neck to
/// waist distance (top lengths are measured from the side neck, the blouse recipe's below the
/// waist). Throws std::invalid_argument for an unknown type.
DraftChoice chooseDraft(const std::string& type,
                        const std::map<std::string, std::string>& attributes,
                        const std::map<std::string, double>& garment,
                        const drafts::Measurements& body, double sideNeckToWaistCm,
                        std::vector<std::string>& warnings);

/// chooseDraft + drafts::draftGarment.
drafts::Pattern draftFromGarment(const std::string& type,
                                 const std::map<std::string, std::string>& attributes,
                                 const std::map<std::string, double>& garment,
                                 const drafts::Measurements& body, double sideNeckToWaistCm,
                                 std::vector<std::string>& warnings);

}  // namespace garmcap::pipeline
