#include "garmcap/calib/form_model.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "garmcap/calib/errors.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::calib {

using drafts::ParseError;
using nlohmann::json;

double unitsToCm(const std::string& units) {
  if (units == "mm")
    return 0.1;
  if (units == "cm")
    return 1.0;
  if (units == "m")
    return 100.0;
  if (units == "in")
    return 2.54;
  throw std::invalid_argument("unknown length unit '" + units + "' (mm, cm, m or in)");
}

// ---------------------------------------------------------------------------------------------
// Sidecar

FormSidecar readFormSidecar(const std::filesystem::path& path) {
  const std::string what = path.string();
  const json j = drafts::readJsonFile(path);
  if (!j.is_object())
    throw ParseError(what + ": a form sidecar must be a JSON object");
  static const std::set<std::string> kKnown = {"mesh",         "mesh_units",       "units",
                                               "measurements", "landmark_heights", "name",
                                               "orientation",  "source",           "checked"};
  for (const auto& [key, value] : j.items()) {
    if (kKnown.count(key) == 0)
      throw ParseError(what + ": unknown field '" + key + "'");
  }
  FormSidecar s;
  s.mesh = path.parent_path() / drafts::requireString(j, "mesh", what);
  s.meshUnits = drafts::requireString(j, "mesh_units", what);
  try {
    unitsToCm(s.meshUnits);
  } catch (const std::invalid_argument& e) {
    throw ParseError(what + ": field 'mesh_units': " + e.what());
  }
  const std::string units = drafts::requireString(j, "units", what);
  if (units != "cm") {
    throw ParseError(what + ": field 'units' must be \"cm\" (measurements are in cm), got \"" +
                     units + "\"");
  }
  const json& m = drafts::requireField(j, "measurements", what);
  if (!m.is_object())
    throw ParseError(what + ": field 'measurements' must be an object");
  for (const auto& [name, value] : m.items()) {
    if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() <= 0) {
      throw ParseError(what + ": measurements." + name + " must be a positive number");
    }
    s.measurements.set(name, value.get<double>());
  }
  if (j.contains("landmark_heights")) {
    const json& l = j["landmark_heights"];
    if (!l.is_object())
      throw ParseError(what + ": field 'landmark_heights' must be an object");
    const auto& names = FormLandmarks::names();
    for (const auto& [name, value] : l.items()) {
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        throw ParseError(what + ": landmark_heights." + name +
                         " is not a landmark (neck_base, shoulder, armpit, bust, waist, hip, "
                         "crotch)");
      }
      if (!value.is_number()) {
        throw ParseError(what + ": landmark_heights." + name + " must be a number (cm)");
      }
      s.landmarkHeightsCm[name] = value.get<double>();
    }
  }
  for (const char* key : {"name", "orientation", "source", "checked"}) {
    if (j.contains(key)) {
      std::string v = drafts::requireString(j, key, what);
      if (std::string(key) == "name")
        s.name = v;
      if (std::string(key) == "orientation")
        s.orientation = v;
      if (std::string(key) == "source")
        s.source = v;
      if (std::string(key) == "checked")
        s.checked = v;
    }
  }
  return s;
}

void writeFormSidecar(const std::filesystem::path& path, const FormSidecar& s) {
  json j;
  if (!s.name.empty())
    j["name"] = s.name;
  j["mesh"] = s.mesh.filename().string();
  j["mesh_units"] = s.meshUnits;
  if (!s.orientation.empty())
    j["orientation"] = s.orientation;
  j["units"] = "cm";
  j["measurements"] = json::object();
  for (const auto& [k, v] : s.measurements.values())
    j["measurements"][k] = std::round(v * 100) / 100;
  if (!s.landmarkHeightsCm.empty()) {
    for (const auto& [k, v] : s.landmarkHeightsCm)
      j["landmark_heights"][k] = std::round(v * 100) / 100;
  }
  if (!s.source.empty())
    j["source"] = s.source;
  if (!s.checked.empty())
    j["checked"] = s.checked;
  drafts::writeJsonFile(path, j);
}

std::filesystem::path resolveFormSidecar(const std::filesystem::path& arg) {
  std::string ext = arg.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".json")
    return arg;
  if (ext != ".obj" && ext != ".ply") {
    throw drafts::FileError(arg.string() +
                            ": --form takes a form sidecar (.json) or a mesh (.obj, .ply)");
  }
  std::filesystem::path same = arg;
  same.replace_extension(".json");
  if (std::filesystem::exists(same))
    return same;
  const auto beside = arg.parent_path() / "form.json";
  if (std::filesystem::exists(beside))
    return beside;
  throw drafts::FileError(arg.string() + ": no sidecar found (looked for " + same.string() +
                          " and " + beside.string() + ")");
}

// ---------------------------------------------------------------------------------------------
// Landmarks

const std::vector<std::string>& FormLandmarks::names() {
  static const std::vector<std::string> kNames = {"neck_base", "shoulder", "armpit", "bust",
                                                  "waist",     "hip",      "crotch"};
  return kNames;
}

std::optional<double> FormLandmarks::get(const std::string& name) const {
  if (name == "neck_base")
    return neckBase;
  if (name == "shoulder")
    return shoulder;
  if (name == "armpit")
    return armpit;
  if (name == "bust")
    return bust;
  if (name == "waist")
    return waist;
  if (name == "hip")
    return hip;
  if (name == "crotch")
    return crotch;
  return std::nullopt;
}

std::map<std::string, double> FormLandmarks::toMap() const {
  std::map<std::string, double> m;
  for (const auto& n : names()) {
    if (auto v = get(n))
      m[n] = *v;
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// Sections

namespace {

struct Box {
  double minX, maxX, minZ, maxZ;
  bool overlaps(const Box& o) const {
    return minX <= o.maxX && o.minX <= maxX && minZ <= o.maxZ && o.minZ <= maxZ;
  }
};

Box boxOf(const SliceLoop& l) {
  Box b{1e300, -1e300, 1e300, -1e300};
  for (const auto& p : l) {
    b.minX = std::min(b.minX, p.x());
    b.maxX = std::max(b.maxX, p.x());
    b.minZ = std::min(b.minZ, p.y());
    b.maxZ = std::max(b.maxZ, p.y());
  }
  return b;
}

// Golden-section search of the extremum of f on [a, b] (f unimodal there).
template <class F>
double goldenSection(F f, double a, double b, bool maximise) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int i = 0; i < 40 && b - a > 1e-4; ++i) {
    if (maximise ? fc > fd : fc < fd) {
      b = d, d = c, fd = fc, c = b - g * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd, d = a + g * (b - a), fd = f(d);
    }
  }
  return (a + b) / 2;
}

// Index of the point of a curve (h_i, w_i) farthest from the chord between its ends: the knee.
std::optional<std::size_t> kneeIndex(const std::vector<double>& h, const std::vector<double>& w) {
  if (h.size() < 3)
    return std::nullopt;
  const Eigen::Vector2d a(h.front(), w.front()), b(h.back(), w.back());
  const Eigen::Vector2d dir = (b - a).normalized();
  double best = -1;
  std::size_t bestI = 0;
  for (std::size_t i = 1; i + 1 < h.size(); ++i) {
    const Eigen::Vector2d p = Eigen::Vector2d(h[i], w[i]) - a;
    const double d = std::abs(p.x() * dir.y() - p.y() * dir.x());
    if (d > best)
      best = d, bestI = i;
  }
  return bestI;
}

}  // namespace

FormSection FormModel::section(double heightCm) const {
  FormSection s;
  s.heightCm = heightCm;
  std::vector<SliceLoop> loops = sliceMesh(mesh_, heightCm);
  s.loopCount = static_cast<int>(loops.size());
  if (loops.empty())
    return s;
  std::vector<Box> boxes;
  for (const auto& l : loops)
    boxes.push_back(boxOf(l));
  s.totalMinXCm = 1e300;
  s.totalMaxXCm = -1e300;
  for (const auto& b : boxes) {
    s.totalMinXCm = std::min(s.totalMinXCm, b.minX);
    s.totalMaxXCm = std::max(s.totalMaxXCm, b.maxX);
  }
  // The torso is the largest loop straddling the body axis; loops overlapping its box belong to
  // it (legs or folds inside the hips). Arms are separate loops beside it and stay out.
  int primary = -1;
  double bestArea = 0;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const double area = std::abs(polygonArea(loops[i]));
    if (boxes[i].minX <= axisX_ && axisX_ <= boxes[i].maxX && area > bestArea) {
      primary = static_cast<int>(i);
      bestArea = area;
    }
  }
  std::vector<int> members;
  if (primary >= 0) {
    for (std::size_t i = 0; i < loops.size(); ++i) {
      if (boxes[i].overlaps(boxes[static_cast<std::size_t>(primary)])) {
        members.push_back(static_cast<int>(i));
      }
    }
  } else {
    // Below the crotch: the nearest loop on each side of the axis (the legs, not the hands).
    int left = -1, right = -1;
    for (std::size_t i = 0; i < loops.size(); ++i) {
      if (boxes[i].maxX < axisX_ &&
          (left < 0 || boxes[i].maxX > boxes[static_cast<std::size_t>(left)].maxX))
        left = static_cast<int>(i);
      if (boxes[i].minX > axisX_ &&
          (right < 0 || boxes[i].minX < boxes[static_cast<std::size_t>(right)].minX))
        right = static_cast<int>(i);
    }
    if (left >= 0)
      members.push_back(left);
    if (right >= 0)
      members.push_back(right);
  }
  if (members.empty())
    return s;
  s.minXCm = 1e300, s.maxXCm = -1e300;
  double minZ = 1e300, maxZ = -1e300;
  for (int i : members) {
    const Box& b = boxes[static_cast<std::size_t>(i)];
    s.minXCm = std::min(s.minXCm, b.minX);
    s.maxXCm = std::max(s.maxXCm, b.maxX);
    minZ = std::min(minZ, b.minZ);
    maxZ = std::max(maxZ, b.maxZ);
    s.torsoLoops.push_back(loops[static_cast<std::size_t>(i)]);
  }
  s.torsoLoopCount = static_cast<int>(members.size());
  s.widthCm = s.maxXCm - s.minXCm;
  s.depthCm = maxZ - minZ;
  s.circumferenceCm = polygonPerimeter(convexHull(s.torsoLoops));
  return s;
}

std::vector<FormSection> FormModel::profile(double stepCm) const {
  std::vector<FormSection> out;
  for (double h = minY_ + stepCm / 2; h < maxY_; h += stepCm)
    out.push_back(section(h));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Construction

FormModel::FormModel(TriMesh meshCm, FormSidecar sidecar)
    : mesh_(std::move(meshCm)), sidecar_(std::move(sidecar)) {
  const std::string what =
      sidecar_.mesh.empty() ? std::string("form mesh") : sidecar_.mesh.string();
  if (mesh_.faces.empty()) {
    throw CalibError(CalibErrorKind::kMeshNotClosed, what + ": the mesh has no faces");
  }
  if (const std::size_t open = openEdgeCount(mesh_); open != 0) {
    throw CalibError(CalibErrorKind::kMeshNotClosed,
                     what + ": the mesh is not closed (" + std::to_string(open) +
                         " edges are not shared by exactly two faces); a dress form must be a "
                         "closed surface so that its cross-sections are closed loops");
  }
  const Eigen::Vector3d lo = mesh_.minCorner(), hi = mesh_.maxCorner();
  minY_ = lo.y();
  maxY_ = hi.y();
  const double h = maxY_ - minY_;
  if (h < 30 || h > 250) {
    std::ostringstream msg;
    msg << what << ": the mesh is " << h << " cm tall after conversion from '" << sidecar_.meshUnits
        << "'; a dress form is 30 to 250 cm tall: is 'mesh_units' right "
        << "(a mesh in metres declared as cm, or the other way round)?";
    throw CalibError(CalibErrorKind::kMeshUnits, msg.str());
  }
  axisX_ = (lo.x() + hi.x()) / 2;
  // The axis depth: centroid z of the vertices in the middle band of the height (hips, belly).
  double sumZ = 0;
  std::size_t n = 0;
  for (const auto& v : mesh_.vertices) {
    if (v.y() > minY_ + 0.45 * h && v.y() < minY_ + 0.6 * h && std::abs(v.x() - axisX_) < 0.1 * h) {
      sumZ += v.z();
      ++n;
    }
  }
  axisZ_ = n > 0 ? sumZ / static_cast<double>(n) : (lo.z() + hi.z()) / 2;
  findLandmarks();
  deriveMeasurements();
  checkSidecar();
}

std::shared_ptr<const FormViewSections> FormModel::viewSections(
    const std::function<std::shared_ptr<const FormViewSections>()>& make) const {
  std::call_once(viewSections_->once, [&] { viewSections_->sections = make(); });
  return viewSections_->sections;
}

FormModel FormModel::load(const std::filesystem::path& formArgument) {
  const auto sidecarPath = resolveFormSidecar(formArgument);
  FormSidecar sidecar = readFormSidecar(sidecarPath);
  TriMesh mesh = readMesh(sidecar.mesh);
  mesh.scale(unitsToCm(sidecar.meshUnits));
  return FormModel(std::move(mesh), std::move(sidecar));
}

void FormModel::findLandmarks() {
  const double h = heightCm();
  const double step = 0.5;
  const std::string what =
      sidecar_.mesh.empty() ? std::string("form mesh") : sidecar_.mesh.string();

  // Crotch: the lowest surface point straight above the floor on the body axis, if it is well
  // above the floor (a torso form is hit at its own bottom instead).
  double lowestHit = 1e300;
  for (const auto& f : mesh_.faces) {
    const Eigen::Vector3d& a = mesh_.vertices[static_cast<std::size_t>(f[0])];
    const Eigen::Vector3d& b = mesh_.vertices[static_cast<std::size_t>(f[1])];
    const Eigen::Vector3d& c = mesh_.vertices[static_cast<std::size_t>(f[2])];
    const Eigen::Vector2d p(axisX_, axisZ_), pa(a.x(), a.z()), pb(b.x(), b.z()), pc(c.x(), c.z());
    const double det = (pb - pa).x() * (pc - pa).y() - (pb - pa).y() * (pc - pa).x();
    if (std::abs(det) < 1e-12)
      continue;
    const double u = ((p - pa).x() * (pc - pa).y() - (p - pa).y() * (pc - pa).x()) / det;
    const double v = ((pb - pa).x() * (p - pa).y() - (pb - pa).y() * (p - pa).x()) / det;
    if (u < 0 || v < 0 || u + v > 1)
      continue;
    lowestHit = std::min(lowestHit, a.y() + u * (b.y() - a.y()) + v * (c.y() - a.y()));
  }
  if (lowestHit < 1e299 && lowestHit > minY_ + 0.2 * h && lowestHit < minY_ + 0.7 * h) {
    landmarks_.crotch = lowestHit;
  }
  double lower = landmarks_.crotch.value_or(minY_) + step;
  torsoBottom_ = landmarks_.crotch.value_or(minY_);
  if (!landmarks_.crotch) {
    // A form without a crotch may stand on a pole (a torso form): its torso is the longest run of
    // heights whose section is at least kTorsoWidthShare of the widest one. The stand's foot is
    // as wide but only a few cm tall, the pole far narrower; a form whose bottom is wide (no
    // stand) starts at its lowest point as before.
    constexpr double kTorsoWidthShare = 0.35;
    std::vector<double> ys, ws;
    for (double y = minY_ + 1.0; y < maxY_ - 0.5; y += 1.0) {
      ys.push_back(y);
      ws.push_back(section(y).widthCm);
    }
    const double maxW = ws.empty() ? 0.0 : *std::max_element(ws.begin(), ws.end());
    std::size_t bestLo = 0, bestLen = 0;
    for (std::size_t i = 0; i < ws.size();) {
      if (ws[i] < kTorsoWidthShare * maxW) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < ws.size() && ws[j] >= kTorsoWidthShare * maxW)
        ++j;
      if (j - i > bestLen)
        bestLo = i, bestLen = j - i;
      i = j;
    }
    if (bestLen > 0 && bestLo > 0) {
      // The torso's bottom to 0.05 cm between the last narrow sample and the first wide one.
      double a = ys[bestLo - 1], b = ys[bestLo];
      for (int it = 0; it < 5; ++it) {
        const double m = (a + b) / 2;
        (section(m).widthCm >= kTorsoWidthShare * maxW ? b : a) = m;
      }
      torsoBottom_ = b;
      lower = b + step;
    }
  }

  struct Row {
    double y;
    FormSection s;
    bool armsApart;
  };
  std::vector<Row> rows;
  for (double y = lower; y < maxY_ - step / 2; y += step) {
    FormSection s = section(y);
    // Arms apart: besides the torso, a loop entirely left and one entirely right of it.
    bool left = false, right = false;
    if (s.torsoLoopCount > 0) {
      for (const auto& l : sliceMesh(mesh_, y)) {
        const Box b = boxOf(l);
        if (b.maxX < s.minXCm)
          left = true;
        if (b.minX > s.maxXCm)
          right = true;
      }
    }
    rows.push_back({y, std::move(s), left && right});
  }
  if (rows.size() < 10) {
    throw CalibError(CalibErrorKind::kFormNotRecognised, what + ": too little torso to measure");
  }
  auto circAt = [&](double y) { return section(y).circumferenceCm; };

  // Armpit: the top of the lowest run of heights (reaching above 30% of crotch..top) where the
  // arms are separate loops beside the torso. Runs higher up are bumps of the arm tops sticking
  // out of a sloping shoulder, not armpits.
  std::optional<std::size_t> armpitRow;
  const double runTopMin = lower + 0.3 * (maxY_ - lower);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].armsApart)
      continue;
    std::size_t j = i;
    while (j + 1 < rows.size() && rows[j + 1].armsApart)
      ++j;
    if (rows[j].y > runTopMin && rows[j].y < minY_ + 0.9 * h) {
      armpitRow = j;
      break;
    }
    i = j;
  }
  double upper = maxY_ - 0.1 * h;
  if (armpitRow) {
    // Refine the split to 0.05 cm by bisection between the last apart row and the next one.
    double a = rows[*armpitRow].y, b = a + step;
    for (int it = 0; it < 4; ++it) {
      const double m = (a + b) / 2;
      FormSection s = section(m);
      bool left = false, right = false;
      for (const auto& l : sliceMesh(mesh_, m)) {
        const Box bx = boxOf(l);
        if (s.torsoLoopCount > 0 && bx.maxX < s.minXCm)
          left = true;
        if (s.torsoLoopCount > 0 && bx.minX > s.maxXCm)
          right = true;
      }
      (left && right ? a : b) = m;
    }
    landmarks_.armpit = a;
    upper = a;
  }

  // Neck: the narrowest torso section above the armpit, away from the top (the head's crown).
  std::optional<std::size_t> neckRow;
  const std::size_t firstUpper = armpitRow ? *armpitRow + 1 : rows.size();
  for (std::size_t i = firstUpper; i < rows.size(); ++i) {
    if (rows[i].y > maxY_ - 0.05 * h || rows[i].s.circumferenceCm <= 0)
      continue;
    if (!neckRow || rows[i].s.circumferenceCm < rows[*neckRow].s.circumferenceCm)
      neckRow = i;
  }
  if (armpitRow && neckRow && *neckRow > *armpitRow + 4) {
    // Shoulder tip: the knee of the front-view width between armpit and neck (arms slope at the
    // A-pose angle, the trapezius much flatter). Neck base: the knee between shoulder and neck.
    std::vector<double> ys, ws;
    for (std::size_t i = *armpitRow; i <= *neckRow; ++i) {
      ys.push_back(rows[i].y);
      ws.push_back(rows[i].s.totalMaxXCm - rows[i].s.totalMinXCm);
    }
    if (auto k = kneeIndex(ys, ws)) {
      landmarks_.shoulder = ys[*k];
      std::vector<double> ys2(ys.begin() + static_cast<long>(*k), ys.end());
      std::vector<double> ws2(ws.begin() + static_cast<long>(*k), ws.end());
      if (auto k2 = kneeIndex(ys2, ws2))
        landmarks_.neckBase = ys2[*k2];
    }
  }

  // An armless form (a torso form: its section closes over the shoulders like a dress form's
  // armhole plates) has no arm to part from the torso. Its neck is the narrowest section of the
  // upper 40% (the highest of equals, so that a neck cap's straight neck counts from its top),
  // its shoulder tip the widest section between the middle of the torso and the neck (the top
  // of the armhole plate, where the shoulder slopes in towards the neck), its neck base the knee
  // of the width between the two. The armpit follows from the bust below.
  std::optional<std::size_t> armlessShoulderRow;
  if (!armpitRow) {
    std::optional<std::size_t> neck;
    double minC = 1e300;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i].y > lower + 0.6 * (maxY_ - lower) && rows[i].y < maxY_ - step &&
          rows[i].s.circumferenceCm > 0)
        minC = std::min(minC, rows[i].s.circumferenceCm);
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i].y > lower + 0.6 * (maxY_ - lower) && rows[i].y < maxY_ - step &&
          rows[i].s.circumferenceCm > 0 && rows[i].s.circumferenceCm <= minC * 1.01)
        neck = i;
    std::optional<std::size_t> shoulder;
    if (neck) {
      const double from = lower + 0.5 * (rows[*neck].y - lower);
      for (std::size_t i = 0; i < *neck; ++i)
        if (rows[i].y > from && (!shoulder || rows[i].s.widthCm > rows[*shoulder].s.widthCm))
          shoulder = i;
    }
    if (!neck || !shoulder || *neck < *shoulder + 4) {
      throw CalibError(CalibErrorKind::kFormNotRecognised,
                       what +
                           ": the form has no arms, and no shoulders and neck were found "
                           "above its torso");
    }
    armlessShoulderRow = shoulder;
    landmarks_.shoulder = rows[*shoulder].y;
    std::vector<double> ys, ws;
    for (std::size_t i = *shoulder; i <= *neck; ++i) {
      ys.push_back(rows[i].y);
      ws.push_back(rows[i].s.widthCm);
    }
    if (auto k = kneeIndex(ys, ws))
      landmarks_.neckBase = ys[*k];
    upper = rows[*shoulder].y;
  }

  // Waist: the narrowest torso between crotch and armpit (middle part of that span); hip: the
  // widest below it; bust: the widest above it. Each refined by golden-section search.
  const double span = upper - lower;
  std::optional<std::size_t> waistRow, hipRow, bustRow;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double y = rows[i].y;
    const double c = rows[i].s.circumferenceCm;
    if (c <= 0 || rows[i].s.torsoLoopCount == 0)
      continue;
    if (y > lower + 0.35 * span && y < upper - 0.1 * span &&
        (!waistRow || c < rows[*waistRow].s.circumferenceCm))
      waistRow = i;
  }
  if (!waistRow) {
    throw CalibError(CalibErrorKind::kFormNotRecognised,
                     what + ": no waist found between crotch and armpit");
  }
  // The bust point is the front-most point of the chest; the bust girth is the first maximum of
  // the circumference at or above it. Taking the overall maximum below the armpit would pick the
  // rise of the back and armpit folds just under the arms (seen on the GarmentCode body).
  std::optional<std::size_t> bustPointRow;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double c = rows[i].s.circumferenceCm;
    if (i < *waistRow && (!hipRow || c > rows[*hipRow].s.circumferenceCm))
      hipRow = i;
    if (i > *waistRow && rows[i].y < upper) {
      double front = -1e300;
      for (const auto& l : rows[i].s.torsoLoops)
        for (const auto& p : l)
          front = std::max(front, p.y());
      rows[i].s.depthCm = front;  // reused below as the front z of this row
      if (!bustPointRow || front > rows[*bustPointRow].s.depthCm)
        bustPointRow = i;
    }
  }
  if (bustPointRow) {
    std::size_t i = *bustPointRow;
    while (i + 1 < rows.size() && rows[i + 1].y < upper &&
           rows[i + 1].s.circumferenceCm >= rows[i].s.circumferenceCm)
      ++i;
    bustRow = i;
    bustPointHeight_ = rows[*bustPointRow].y;
  }
  auto refine = [&](std::size_t i, bool maximise) {
    const double a = std::max(lower, rows[i].y - step);
    const double b = std::min(upper - 1e-3, rows[i].y + step);
    return goldenSection(circAt, a, b, maximise);
  };
  landmarks_.waist = refine(*waistRow, false);
  if (hipRow)
    landmarks_.hip = refine(*hipRow, true);
  if (bustRow)
    landmarks_.bust = refine(*bustRow, true);

  if (armlessShoulderRow) {
    // Armpit of an armless form: a convention, kArmlessArmpitShare of the way from the bust up
    // to the shoulder tip. A smooth torso has no shape feature there (the knee of the chest's
    // depth was tried: 8-10 cm too high on the generator's table 4.2 bodies); the generator's
    // bodies put their armpit 26-30 % of the way, and a dress form's armhole plate starts about
    // there. The armpit bounds a bodice's armhole and the depth tables of the measurer.
    constexpr double kArmlessArmpitShare = 0.3;
    if (!bustRow || *armlessShoulderRow < *bustRow + 3) {
      throw CalibError(CalibErrorKind::kFormNotRecognised,
                       what +
                           ": the form has no arms and no bust below its shoulders, so no "
                           "armpit can be placed");
    }
    landmarks_.armpit =
        *landmarks_.bust + kArmlessArmpitShare * (*landmarks_.shoulder - *landmarks_.bust);
  }
}

void FormModel::deriveMeasurements() {
  const auto& L = landmarks_;
  // Stature is the floor to the top of the head; a torso form on a stand has neither, and its
  // mesh's height (floor to neck cap) would replace the size chart's body height in the drafts.
  if (!isTorsoForm())
    measurements_.set("height", heightCm());
  auto put = [&](const std::optional<double>& y, const char* circ, const char* width,
                 const char* heightName) {
    if (!y)
      return;
    const FormSection s = section(*y);
    if (circ)
      measurements_.set(circ, s.circumferenceCm);
    if (width)
      measurements_.set(width, s.widthCm);
    if (heightName)
      measurements_.set(heightName, *y - minY_);
  };
  put(L.bust, "bust_circ", "width_bust", nullptr);
  if (bustPointHeight_)
    measurements_.set("height_bustpoint", *bustPointHeight_ - minY_);
  put(L.waist, "waist_circ", "width_waist", "height_waist_side");
  put(L.hip, "hip_circ", "width_hip", "height_hip");
  put(L.neckBase, "neck_circ", nullptr, "height_neck_side");
  put(L.armpit, nullptr, nullptr, "height_armpit");
  put(L.shoulder, nullptr, nullptr, "height_shoulder_tip");
  if (L.crotch)
    measurements_.set("leg_crotch_to_floor", *L.crotch - minY_);
  if (L.waist && L.hip)
    measurements_.set("waist_to_hip_side", *L.waist - *L.hip);
}

namespace {
// The measurements a sidecar is checked against: these are defined without heuristics.
const std::vector<std::string> kCheckedMeasurements = {"height", "bust_circ", "waist_circ",
                                                       "hip_circ"};
}  // namespace

void FormModel::checkSidecar() const {
  std::ostringstream problems;
  const auto& derived = measurements_.values();
  const auto& given = sidecar_.measurements.values();
  for (const auto& name : kCheckedMeasurements) {
    auto d = derived.find(name);
    auto g = given.find(name);
    if (d == derived.end() || g == given.end())
      continue;
    const double rel = std::abs(d->second - g->second) / g->second;
    if (rel > 0.02) {
      problems << " " << name << ": sidecar " << g->second << " cm, mesh " << d->second << " cm ("
               << rel * 100 << "% off);";
    }
  }
  for (const auto& [name, value] : sidecar_.landmarkHeightsCm) {
    auto d = landmarks_.get(name);
    if (!d) {
      problems << " landmark " << name << ": in the sidecar but not found on the mesh;";
      continue;
    }
    const double off = std::abs(*d - value);
    if (off > 0.02 * heightCm()) {
      problems << " landmark " << name << ": sidecar " << value << " cm, mesh " << *d << " cm;";
    }
  }
  const std::string text = problems.str();
  if (!text.empty()) {
    throw CalibError(CalibErrorKind::kSidecar,
                     (sidecar_.mesh.empty() ? std::string("form") : sidecar_.mesh.string()) +
                         ": the sidecar disagrees with the mesh by more than 2%:" + text);
  }
}

std::string FormModel::reportJson() const {
  auto r2 = [](double v) { return std::round(v * 100) / 100; };
  json j;
  j["mesh"] = {{"path", sidecar_.mesh.string()},
               {"units", sidecar_.meshUnits},
               {"vertices", mesh_.vertices.size()},
               {"faces", mesh_.faces.size()},
               {"closed", true},
               {"height_cm", r2(heightCm())},
               {"axis_x_cm", r2(axisX_)},
               {"axis_z_cm", r2(axisZ_)}};
  j["units"] = "cm";
  j["measurements"] = json::object();
  for (const auto& [k, v] : measurements_.values())
    j["measurements"][k] = r2(v);
  j["landmark_heights"] = json::object();
  for (const auto& [k, v] : landmarks_.toMap())
    j["landmark_heights"][k] = r2(v);
  json cmp = json::object();
  for (const auto& [k, v] : sidecar_.measurements.values()) {
    json e = {{"sidecar", v}};
    auto d = measurements_.values().find(k);
    if (d != measurements_.values().end()) {
      e["derived"] = r2(d->second);
      e["diff_percent"] = std::round((d->second - v) / v * 1e4) / 100;
    } else {
      e["derived"] = nullptr;
    }
    cmp[k] = e;
  }
  j["sidecar_comparison"] = cmp;
  return j.dump(2);
}

}  // namespace garmcap::calib
