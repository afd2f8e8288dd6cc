#pragma once
// Pattern JSON (see docs/formats.md, "Pattern JSON"): the draft a recipe drew (type,
// measurements, design parameters, named points, lines, regions) and the panels derived from it.
// Readers are strict: an unknown or missing field throws ParseError naming the file (`what`) and
// the JSON path of the field.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

/// Format version written into every file ("format": "garmcap-pattern", "version": 1).
inline constexpr int kPatternFormatVersion = 1;

nlohmann::json patternToJsonValue(const Pattern& pattern);
std::string patternToJson(const Pattern& pattern);
/// Throws ParseError "<what>: <json path>: <reason>".
Pattern patternFromJsonValue(const nlohmann::json& root, const std::string& what);
Pattern patternFromJson(const std::string& text, const std::string& what);

/// File variants (atomic write; reads name the path in errors).
void writePatternJson(const std::filesystem::path& path, const Pattern& pattern);
Pattern readPatternJson(const std::filesystem::path& path);

}  // namespace garmcap::drafts
