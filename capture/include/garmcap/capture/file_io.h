#pragma once
// The little file I/O capture needs for rigs: whole-file reads, crash-safe writes and strict
// JSON field access. capture keeps its own (instead of drafts' file_io.h) because it must not
// depend on drafts (docs/architecture.md); the messages are worded the same way, so a rig error
// reads alike whichever module reports it.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

namespace garmcap::capture {

/// I/O failure on a named file (missing, unreadable, unwritable, not encodable).
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Malformed content: the message names the file and the place (line:column or field name).
class ParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a whole file as bytes. Throws FileError "file not found: <path>", "expected a file but
/// found a directory: <path>", "cannot open <path>: <reason>", "cannot read <path>".
std::string readFile(const std::filesystem::path& path);

/// POSIX atomic write: a temporary file in the same directory, fsync, rename over `path`, fsync
/// of the directory, so that a power loss leaves the old or the new file, never a torn one.
/// Creates missing parent directories. Throws FileError naming the path and the reason.
void writeFileAtomic(const std::filesystem::path& path, std::string_view data);

/// readFile + JSON parse; a syntax error throws ParseError "<path>: malformed JSON at line L,
/// column C: <reason>".
nlohmann::json readJsonFile(const std::filesystem::path& path);

/// Pretty-printed (2 spaces) with a trailing newline, written with writeFileAtomic.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value);

/// Strict field access: ParseError "<what>: expected a JSON object", "<what>: missing field
/// '<key>'", "<what>: field '<key>' must be a number" / "... is not finite" / "... must be a
/// string".
const nlohmann::json& requireField(const nlohmann::json& object, const std::string& key,
                                   const std::string& what);
double requireNumber(const nlohmann::json& object, const std::string& key, const std::string& what);
std::string requireString(const nlohmann::json& object, const std::string& key,
                          const std::string& what);

}  // namespace garmcap::capture
