#include "garmcap/calib/mesh.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_map>

#include "garmcap/drafts/file_io.h"

namespace garmcap::calib {

using drafts::FileError;
using drafts::ParseError;

Eigen::Vector3d TriMesh::minCorner() const {
  if (vertices.empty())
    return Eigen::Vector3d::Zero();
  Eigen::Vector3d m = vertices.front();
  for (const auto& v : vertices)
    m = m.cwiseMin(v);
  return m;
}

Eigen::Vector3d TriMesh::maxCorner() const {
  if (vertices.empty())
    return Eigen::Vector3d::Zero();
  Eigen::Vector3d m = vertices.front();
  for (const auto& v : vertices)
    m = m.cwiseMax(v);
  return m;
}

void TriMesh::scale(double factor) {
  for (auto& v : vertices)
    v *= factor;
}

void TriMesh::append(const TriMesh& other) {
  const int base = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& f : other.faces)
    faces.push_back(f + Eigen::Vector3i::Constant(base));
}

namespace {

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Parses the leading integer of an OBJ face token "i", "i/t", "i//n", "i/t/n".
bool parseFaceIndex(const std::string& token, long& index) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  const char* slash = std::find(begin, end, '/');
  auto [ptr, ec] = std::from_chars(begin, slash, index);
  return ec == std::errc() && ptr == slash && index != 0;
}

void checkIndices(const TriMesh& mesh, const std::string& what) {
  const auto n = static_cast<int>(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.faces[i][k] < 0 || mesh.faces[i][k] >= n) {
        throw ParseError(what + ": face " + std::to_string(i) + " refers to vertex " +
                         std::to_string(mesh.faces[i][k]) + " but there are " + std::to_string(n));
      }
    }
  }
  if (mesh.faces.empty())
    throw ParseError(what + ": mesh has no faces");
}

}  // namespace

TriMesh readObj(const std::filesystem::path& path) {
  const std::string text = drafts::readFile(path);
  const std::string what = path.string();
  TriMesh mesh;
  std::istringstream in(text);
  std::string line;
  std::size_t lineNo = 0;
  std::vector<long> poly;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.size() < 2)
      continue;
    if (line[0] == 'v' && line[1] == ' ') {
      std::istringstream ls(line.substr(2));
      Eigen::Vector3d v;
      if (!(ls >> v.x() >> v.y() >> v.z()) || !v.allFinite()) {
        throw ParseError(what + ": line " + std::to_string(lineNo) + ": bad vertex '" + line + "'");
      }
      mesh.vertices.push_back(v);
    } else if (line[0] == 'f' && line[1] == ' ') {
      std::istringstream ls(line.substr(2));
      std::string token;
      poly.clear();
      while (ls >> token) {
        long idx = 0;
        if (!parseFaceIndex(token, idx)) {
          throw ParseError(what + ": line " + std::to_string(lineNo) + ": bad face index '" +
                           token + "'");
        }
        // OBJ indices are 1-based; negative ones count back from the last vertex read.
        idx = idx > 0 ? idx - 1 : static_cast<long>(mesh.vertices.size()) + idx;
        poly.push_back(idx);
      }
      if (poly.size() < 3) {
        throw ParseError(what + ": line " + std::to_string(lineNo) +
                         ": face with fewer than 3 "
                         "vertices");
      }
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        mesh.faces.emplace_back(static_cast<int>(poly[0]), static_cast<int>(poly[k]),
                                static_cast<int>(poly[k + 1]));
      }
    }
  }
  checkIndices(mesh, what);
  return mesh;
}

namespace {

struct PlyProperty {
  std::string name, type, countType;  // countType set for lists
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> props;
};

std::size_t plyTypeSize(const std::string& t, const std::string& what) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8")
    return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16")
    return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32")
    return 4;
  if (t == "double" || t == "float64")
    return 8;
  throw ParseError(what + ": unknown PLY property type '" + t + "'");
}

double plyReadBinary(const char*& p, const char* end, const std::string& t,
                     const std::string& what) {
  const std::size_t n = plyTypeSize(t, what);
  if (static_cast<std::size_t>(end - p) < n)
    throw ParseError(what + ": PLY data truncated");
  double v = 0;
  auto get = [&](auto tag) {
    decltype(tag) x;
    std::memcpy(&x, p, sizeof x);
    v = static_cast<double>(x);
  };
  if (t == "char" || t == "int8")
    get(std::int8_t{});
  else if (t == "uchar" || t == "uint8")
    get(std::uint8_t{});
  else if (t == "short" || t == "int16")
    get(std::int16_t{});
  else if (t == "ushort" || t == "uint16")
    get(std::uint16_t{});
  else if (t == "int" || t == "int32")
    get(std::int32_t{});
  else if (t == "uint" || t == "uint32")
    get(std::uint32_t{});
  else if (t == "float" || t == "float32")
    get(float{});
  else
    get(double{});
  p += n;
  return v;
}

}  // namespace

TriMesh readPly(const std::filesystem::path& path) {
  const std::string data = drafts::readFile(path);
  const std::string what = path.string();
  const std::size_t headerEnd = data.find("end_header\n");
  if (data.rfind("ply", 0) != 0 || headerEnd == std::string::npos) {
    throw ParseError(what + ": not a PLY file (missing 'ply' magic or 'end_header')");
  }
  std::istringstream header(data.substr(0, headerEnd));
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "format") {
      ls >> format;
    } else if (kw == "element") {
      PlyElement e;
      if (!(ls >> e.name >> e.count))
        throw ParseError(what + ": PLY element line '" + line + "' is not 'element NAME COUNT'");
      elements.push_back(e);
    } else if (kw == "property") {
      if (elements.empty())
        throw ParseError(what + ": PLY property before any element");
      PlyProperty p;
      ls >> p.type;
      if (p.type == "list") {
        ls >> p.countType >> p.type;
      }
      ls >> p.name;
      elements.back().props.push_back(p);
    }
  }
  if (format != "ascii" && format != "binary_little_endian") {
    throw ParseError(what + ": unsupported PLY format '" + format +
                     "' (ascii and binary_little_endian are read)");
  }
  TriMesh mesh;
  const char* p = data.data() + headerEnd + std::strlen("end_header\n");
  const char* end = data.data() + data.size();
  std::istringstream ascii(format == "ascii" ? std::string(p, end) : std::string());
  auto readValue = [&](const std::string& type) {
    if (format == "ascii") {
      double v = 0;
      if (!(ascii >> v))
        throw ParseError(what + ": PLY ascii data truncated or malformed");
      return v;
    }
    return plyReadBinary(p, end, type, what);
  };
  // Counts and indices come from the file: every value takes at least one byte (binary) or one
  // character (ascii), so a count the remaining bytes cannot hold is a corrupt header, refused
  // before looping on it; indices are checked as integers before any conversion.
  auto boundedCount = [&](double n, const std::string& of) {
    if (!std::isfinite(n) || n < 0 || n != std::floor(n) ||
        n > static_cast<double>(end - data.data()))
      throw ParseError(what + ": PLY " + of + " count " + std::to_string(n) +
                       " is not a whole number the file can hold");
    return static_cast<long>(n);
  };
  auto vertexIndex = [&](double x) {
    if (!std::isfinite(x) || x != std::floor(x) || x < 0 ||
        x > static_cast<double>(std::numeric_limits<int>::max()))
      throw ParseError(what + ": PLY vertex index " + std::to_string(x) +
                       " is not a non-negative integer");
    return static_cast<long>(x);
  };
  for (const auto& e : elements) {
    if (!e.props.empty() && e.count > static_cast<std::size_t>(end - p) / e.props.size() + 1)
      throw ParseError(what + ": PLY element '" + e.name + "' declares " + std::to_string(e.count) +
                       " entries, more than the file holds");
    if (e.props.empty())
      continue;  // nothing to read for it
    for (std::size_t i = 0; i < e.count; ++i) {
      Eigen::Vector3d v = Eigen::Vector3d::Zero();
      std::vector<long> poly;
      for (const auto& prop : e.props) {
        if (!prop.countType.empty()) {
          const long n = boundedCount(readValue(prop.countType), "list");
          const bool indices =
              e.name == "face" && (prop.name == "vertex_indices" || prop.name == "vertex_index");
          std::vector<long> list;
          for (long k = 0; k < n; ++k) {
            const double x = readValue(prop.type);
            if (indices)
              list.push_back(vertexIndex(x));
          }
          if (indices)
            poly = list;
        } else {
          const double x = readValue(prop.type);
          if (e.name == "vertex") {
            if (prop.name == "x")
              v.x() = x;
            if (prop.name == "y")
              v.y() = x;
            if (prop.name == "z")
              v.z() = x;
          }
        }
      }
      if (e.name == "vertex")
        mesh.vertices.push_back(v);
      if (e.name == "face") {
        if (poly.size() < 3)
          throw ParseError(what + ": PLY face with fewer than 3 vertices");
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
          mesh.faces.emplace_back(static_cast<int>(poly[0]), static_cast<int>(poly[k]),
                                  static_cast<int>(poly[k + 1]));
        }
      }
    }
  }
  checkIndices(mesh, what);
  return mesh;
}

TriMesh readMesh(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".obj")
    return readObj(path);
  if (ext == ".ply")
    return readPly(path);
  throw FileError(path.string() + ": unknown mesh format '" + ext + "' (.obj and .ply are read)");
}

void writeObj(const std::filesystem::path& path, const TriMesh& mesh, const std::string& comment) {
  std::string out;
  out.reserve(mesh.vertices.size() * 40 + mesh.faces.size() * 24);
  std::istringstream cs(comment);
  std::string line;
  while (std::getline(cs, line))
    out += "# " + line + "\n";
  char buf[128];
  for (const auto& v : mesh.vertices) {
    std::snprintf(buf, sizeof buf, "v %.4f %.4f %.4f\n", v.x(), v.y(), v.z());
    out += buf;
  }
  for (const auto& f : mesh.faces) {
    std::snprintf(buf, sizeof buf, "f %d %d %d\n", f[0] + 1, f[1] + 1, f[2] + 1);
    out += buf;
  }
  drafts::writeFileAtomic(path, out);
}

std::size_t openEdgeCount(const TriMesh& mesh) {
  std::unordered_map<std::uint64_t, int> edges;
  edges.reserve(mesh.faces.size() * 2);
  std::size_t defects = 0;
  for (const auto& f : mesh.faces) {
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
      ++defects;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      auto a = static_cast<std::uint64_t>(f[k]);
      auto b = static_cast<std::uint64_t>(f[(k + 1) % 3]);
      if (a > b)
        std::swap(a, b);
      ++edges[(a << 32) | b];
    }
  }
  for (const auto& [key, n] : edges) {
    if (n != 2)
      ++defects;
  }
  return defects;
}

}  // namespace garmcap::calib
