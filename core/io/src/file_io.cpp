#include "garmcap/io/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

namespace garmcap::io {
namespace {

std::string errnoText() {
  return std::strerror(errno);
}

// Finds the 1-based line and column of a byte offset so JSON errors point at the place.
std::pair<std::size_t, std::size_t> lineColumn(std::string_view text, std::size_t offset) {
  std::size_t line = 1;
  std::size_t column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

void writeAll(int fd, std::string_view data, const std::filesystem::path& path) {
  const char* p = data.data();
  std::size_t left = data.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      throw FileError("cannot write " + path.string() + ": " + errnoText());
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

}  // namespace

std::string readFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw FileError("file not found: " + path.string());
  if (std::filesystem::is_directory(path, ec))
    throw FileError("expected a file but found a directory: " + path.string());
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw FileError("cannot open " + path.string() + ": " + errnoText());
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad())
    throw FileError("cannot read " + path.string());
  return buffer.str();
}

void writeFileAtomic(const std::filesystem::path& path, std::string_view data) {
  // A device or a pipe (/dev/null, /dev/stdout, a FIFO) is written into: a file renamed onto it
  // would replace the node itself (as root, `garmcap draft --out /dev/null` left /dev/null a
  // plain file, and every program that wrote to it afterwards failed).
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode))
      throw FileError("cannot write " + path.string() + ": it is a directory");
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0)
      throw FileError("cannot open " + path.string() + ": " + errnoText());
    try {
      writeAll(fd, data, path);
    } catch (...) {
      ::close(fd);
      throw;
    }
    ::close(fd);
    return;
  }
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw FileError("cannot write " + path.string() + ": cannot create directory " + dir.string() +
                    ": " + ec.message());
  }

  std::random_device rd;
  const std::filesystem::path tmp =
      dir / ("." + path.filename().string() + ".tmp" + std::to_string(rd()));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    throw FileError("cannot create " + tmp.string() + ": " + errnoText());
  try {
    writeAll(fd, data, tmp);
    if (::fsync(fd) != 0)
      throw FileError("cannot fsync " + tmp.string() + ": " + errnoText());
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = errnoText();
    ::unlink(tmp.c_str());
    throw FileError("cannot rename " + tmp.string() + " to " + path.string() + ": " + reason);
  }
  // The rename is durable only once the directory entry is on disk.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

nlohmann::json parseJson(std::string_view text, const std::string& what) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    const auto [line, column] = lineColumn(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string reason = e.what();
    // nlohmann's message repeats the position; keep only the part after "parse error ... : ".
    if (const auto pos = reason.find("syntax error"); pos != std::string::npos)
      reason = reason.substr(pos);
    throw ParseError(what + ": malformed JSON at line " + std::to_string(line) + ", column " +
                     std::to_string(column) + ": " + reason);
  } catch (const nlohmann::json::exception& e) {
    // e.g. out_of_range.406 for a number like 1e999: still the file's fault, so name it.
    throw ParseError(what + ": malformed JSON: " + e.what());
  }
}

nlohmann::json readJsonFile(const std::filesystem::path& path) {
  return parseJson(readFile(path), path.string());
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value) {
  writeFileAtomic(path, value.dump(2) + "\n");
}

const nlohmann::json& requireField(const nlohmann::json& object, const std::string& key,
                                   const std::string& what) {
  if (!object.is_object())
    throw ParseError(what + ": expected a JSON object");
  const auto it = object.find(key);
  if (it == object.end())
    throw ParseError(what + ": missing field '" + key + "'");
  return *it;
}

double requireNumber(const nlohmann::json& object, const std::string& key,
                     const std::string& what) {
  const auto& v = requireField(object, key, what);
  if (!v.is_number())
    throw ParseError(what + ": field '" + key + "' must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d))
    throw ParseError(what + ": field '" + key + "' is not finite");
  return d;
}

std::string requireString(const nlohmann::json& object, const std::string& key,
                          const std::string& what) {
  const auto& v = requireField(object, key, what);
  if (!v.is_string())
    throw ParseError(what + ": field '" + key + "' must be a string");
  return v.get<std::string>();
}

}  // namespace garmcap::io
