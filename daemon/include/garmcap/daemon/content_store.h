#pragma once
// Content-addressed image store: each blob lives at <root>/<aa>/<sha256 hex> where aa is the first
// two hex digits. Writes go to <root>/tmp/, are fsynced, renamed into place and the directory is
// fsynced, all before the catalog row that names the blob is committed (so a crash leaves at most
// an unreferenced file, which sweepOrphans() removes at start-up, never a row without its file).
// Thread-safe: put() may run on worker threads; names are derived from content only.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <system_error>

namespace garmcap::daemon {

/// Lower-case hex SHA-256 of the bytes (nettle).
std::string sha256Hex(std::string_view bytes);
/// True for 64 lower-case hex digits (the only names the store ever opens).
bool isSha256Hex(std::string_view text);

class ContentStore {
 public:
  /// Creates <root> and <root>/tmp if missing. Throws std::runtime_error naming the path.
  explicit ContentStore(std::filesystem::path root);

  /// Stores the bytes durably and returns their sha256. Idempotent. Throws std::runtime_error
  /// with the path and errno text on I/O failure.
  std::string put(std::string_view bytes) const;
  /// The file of a blob; nullopt if `sha` is not a valid name or the file is absent.
  std::optional<std::filesystem::path> path(std::string_view sha) const;
  /// Reads a blob; nullopt if absent. Throws on a read error.
  std::optional<std::string> read(std::string_view sha) const;
  bool contains(std::string_view sha) const;
  /// Removes a blob whose row is gone (the orphan sweep, reclaiming); an absent blob is no error.
  std::error_code remove(std::string_view sha) const;

  /// All blob names on disk.
  std::set<std::string> list() const;
  /// Deletes temp files and blobs not in `referenced`; returns how many blobs were removed.
  std::size_t sweepOrphans(const std::set<std::string>& referenced) const;

  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
};

}  // namespace garmcap::daemon
