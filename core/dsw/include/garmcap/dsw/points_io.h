#pragma once
// The point files of `garmcap coords`: {"polygon": [[x, y], ...]} and {"points": [[x, y], ...]}
// in cm. Strict: the object must hold exactly the one field, every entry must be an array of
// two finite numbers.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

/// Reads `root[key]` as N×2 points. Throws drafts::ParseError "<what>: <key>[i]: <reason>" for
/// a missing or unknown field, a non-array, an entry that is not [x, y], or a non-finite number.
Points pointsFromJson(const nlohmann::json& root, const std::string& key, const std::string& what);

/// readJsonFile + pointsFromJson; errors name the file.
Points readPointsFile(const std::filesystem::path& path, const std::string& key);

/// {"weights": [[...], ...]} rows of a matrix, with full double precision.
nlohmann::json matrixToJson(const Eigen::MatrixXd& m);

}  // namespace garmcap::dsw
