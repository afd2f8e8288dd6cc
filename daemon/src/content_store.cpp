#include "garmcap/daemon/content_store.h"

#include <fcntl.h>
#include <nettle/sha2.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "garmcap/daemon/disk_full.h"

namespace garmcap::daemon {

namespace fs = std::filesystem;

std::string sha256Hex(std::string_view bytes) {
  sha256_ctx ctx;
  sha256_init(&ctx);
  sha256_update(&ctx, bytes.size(), reinterpret_cast<const std::uint8_t*>(bytes.data()));
  std::uint8_t digest[SHA256_DIGEST_SIZE];
  sha256_digest(&ctx, SHA256_DIGEST_SIZE, digest);
  static const char* kHex = "0123456789abcdef";
  std::string out;
  out.reserve(2 * SHA256_DIGEST_SIZE);
  for (std::uint8_t b : digest) {
    out.push_back(kHex[b >> 4]);
    out.push_back(kHex[b & 15]);
  }
  return out;
}

bool isSha256Hex(std::string_view text) {
  return text.size() == 64 && std::all_of(text.begin(), text.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

namespace {

[[noreturn]] void throwErrno(const std::string& what, const fs::path& path) {
  if (errno == ENOSPC || errno == EDQUOT)
    throw DiskFull("image store");
  throw std::runtime_error("content store: " + what + " " + path.string() + ": " +
                           std::strerror(errno));
}

void fsyncPath(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
  if (fd < 0)
    throwErrno("cannot open for fsync", path);
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0)
    throwErrno("fsync failed on", path);
}

}  // namespace

ContentStore::ContentStore(fs::path root) : root_(std::move(root)) {
  std::error_code ec;
  fs::create_directories(root_ / "tmp", ec);
  if (ec)
    throw std::runtime_error("content store: cannot create " + (root_ / "tmp").string() + ": " +
                             ec.message());
}

std::optional<fs::path> ContentStore::path(std::string_view sha) const {
  if (!isSha256Hex(sha))
    return std::nullopt;
  fs::path p = root_ / std::string(sha.substr(0, 2)) / std::string(sha);
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    return std::nullopt;
  return p;
}

bool ContentStore::contains(std::string_view sha) const {
  return path(sha).has_value();
}

std::string ContentStore::put(std::string_view bytes) const {
  const std::string sha = sha256Hex(bytes);
  if (contains(sha))
    return sha;
  const fs::path dir = root_ / sha.substr(0, 2);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error("content store: cannot create " + dir.string());
  // Unique temp name per writer: two threads may store the same blob at once.
  static std::atomic<unsigned> counter{0};
  std::ostringstream tmpName;
  tmpName << sha << '.' << ::getpid() << '.' << counter++ << ".tmp";
  const fs::path tmp = root_ / "tmp" / tmpName.str();
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640);
  if (fd < 0)
    throwErrno("cannot create", tmp);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      const int saved = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      errno = saved;
      throwErrno("cannot write", tmp);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int saved = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    errno = saved;
    throwErrno("fsync failed on", tmp);
  }
  ::close(fd);
  const fs::path final = dir / sha;
  if (::rename(tmp.c_str(), final.c_str()) != 0) {
    const int saved = errno;
    ::unlink(tmp.c_str());
    errno = saved;
    throwErrno("cannot rename into", final);
  }
  fsyncPath(dir, true);  // the rename itself must survive power loss before the row commits
  return sha;
}

std::optional<std::string> ContentStore::read(std::string_view sha) const {
  auto p = path(sha);
  if (!p)
    return std::nullopt;
  std::ifstream in(*p, std::ios::binary);
  if (!in)
    throw std::runtime_error("content store: cannot read " + p->string());
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::error_code ContentStore::remove(std::string_view sha) const {
  std::error_code ec;
  if (auto p = path(sha))
    fs::remove(*p, ec);
  return ec;
}

std::set<std::string> ContentStore::list() const {
  std::set<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator d(root_, ec), end; !ec && d != end; d.increment(ec)) {
    if (!d->is_directory() || d->path().filename() == "tmp")
      continue;
    std::error_code ec2;
    for (fs::directory_iterator f(d->path(), ec2); !ec2 && f != end; f.increment(ec2)) {
      const std::string name = f->path().filename().string();
      if (f->is_regular_file() && isSha256Hex(name))
        out.insert(name);
    }
  }
  return out;
}

std::size_t ContentStore::sweepOrphans(const std::set<std::string>& referenced) const {
  std::error_code ec;
  for (fs::directory_iterator t(root_ / "tmp", ec), end; !ec && t != end; t.increment(ec))
    fs::remove(t->path(), ec);
  std::size_t removed = 0;
  for (const std::string& sha : list()) {
    if (referenced.count(sha))
      continue;
    remove(sha);
    ++removed;
  }
  return removed;
}

}  // namespace garmcap::daemon
