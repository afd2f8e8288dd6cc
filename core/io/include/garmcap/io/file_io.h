#pragma once
// File I/O shared by every module: whole-file reads, crash-safe writes, and JSON parsing whose
// errors name the file and the place. Everything here throws garmcap::io::FileError (or
// ParseError) with a message that names the path; nothing is swallowed. It is the one library
// beneath both drafts and capture (which may not link each other), so it links no garmcap
// library itself (docs/architecture.md).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

namespace garmcap::io {

/// I/O failure on a named file (missing, unreadable, unwritable).
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Content of a file is malformed: the message names the file and the place (line:column,
/// JSON pointer or field name).
class ParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a whole file as bytes. Throws FileError naming the path when it cannot be read.
std::string readFile(const std::filesystem::path& path);

/// Writes `data` so that a power loss leaves either the old or the new file, never a torn one:
/// write to a temporary file in the same directory, fsync it, rename over the target, fsync the
/// directory. Creates missing parent directories. Throws FileError naming the path.
void writeFileAtomic(const std::filesystem::path& path, std::string_view data);

/// Parses JSON text; on a syntax error throws ParseError "<what>: line L, column C: <reason>".
/// `what` is usually the file name.
nlohmann::json parseJson(std::string_view text, const std::string& what);

/// readFile + parseJson.
nlohmann::json readJsonFile(const std::filesystem::path& path);

/// Writes JSON pretty-printed (2 spaces) with a trailing newline, atomically.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value);

/// Strict field access for readers: throws ParseError "<what>: missing field '<key>'" or
/// "<what>: field '<key>' must be a number" etc. so that a file is never read with silent
/// defaults.
const nlohmann::json& requireField(const nlohmann::json& object, const std::string& key,
                                   const std::string& what);
double requireNumber(const nlohmann::json& object, const std::string& key, const std::string& what);
std::string requireString(const nlohmann::json& object, const std::string& key,
                          const std::string& what);

}  // namespace garmcap::io
