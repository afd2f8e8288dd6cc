// Pattern JSON reader/writer. The reader checks every object for unknown keys and every field
// for its type, so a file is never half-read with silent defaults (ARCHITECTURE.md contracts).
#include "garmcap/drafts/pattern_io.h"

#include <cmath>
#include <set>

#include "garmcap/drafts/file_io.h"

namespace garmcap::drafts {
namespace {

using nlohmann::json;

json pointJson(const Point2& p) {
  return json::array({p.x(), p.y()});
}

json polylineJson(const Polyline& pl) {
  json a = json::array();
  for (const auto& p : pl)
    a.push_back(pointJson(p));
  return a;
}

json lineJson(const DraftLine& l) {
  return json{
      {"name", l.name}, {"construction", l.construction}, {"points", polylineJson(l.points)}};
}

json edgeJson(const EdgeRef& e) {
  return json{{"panel", e.panel}, {"from", e.from}, {"to", e.to}};
}

// --- strict reading -------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& where, const std::string& reason) {
  throw ParseError(where + ": " + reason);
}

void onlyKeys(const json& obj, const std::string& where, std::initializer_list<const char*> keys) {
  if (!obj.is_object())
    fail(where, "must be an object");
  std::set<std::string> allowed(keys.begin(), keys.end());
  for (const auto& [k, v] : obj.items()) {
    if (!allowed.count(k))
      fail(where, "unknown field '" + k + "'");
  }
}

const json& field(const json& obj, const std::string& key, const std::string& where) {
  return requireField(obj, key, where);
}

double number(const json& v, const std::string& where) {
  if (!v.is_number())
    fail(where, "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d))
    fail(where, "must be finite");
  return d;
}

double numberField(const json& obj, const std::string& key, const std::string& where) {
  return number(field(obj, key, where), where + "/" + key);
}

std::string stringField(const json& obj, const std::string& key, const std::string& where) {
  const auto& v = field(obj, key, where);
  if (!v.is_string())
    fail(where + "/" + key, "must be a string");
  return v.get<std::string>();
}

bool boolField(const json& obj, const std::string& key, const std::string& where) {
  const auto& v = field(obj, key, where);
  if (!v.is_boolean())
    fail(where + "/" + key, "must be true or false");
  return v.get<bool>();
}

int intField(const json& obj, const std::string& key, const std::string& where) {
  const auto& v = field(obj, key, where);
  if (!v.is_number_integer())
    fail(where + "/" + key, "must be an integer");
  return v.get<int>();
}

const json& arrayField(const json& obj, const std::string& key, const std::string& where) {
  const auto& v = field(obj, key, where);
  if (!v.is_array())
    fail(where + "/" + key, "must be an array");
  return v;
}

Point2 readPoint(const json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 2)
    fail(where, "must be a point [x, y]");
  return Point2(number(v[0], where + "/0"), number(v[1], where + "/1"));
}

Polyline readPolyline(const json& v, const std::string& where) {
  if (!v.is_array())
    fail(where, "must be an array of points");
  Polyline pl;
  for (std::size_t i = 0; i < v.size(); ++i)
    pl.push_back(readPoint(v[i], where + "/" + std::to_string(i)));
  return pl;
}

DraftLine readLine(const json& v, const std::string& where) {
  onlyKeys(v, where, {"name", "construction", "points"});
  DraftLine l;
  l.name = stringField(v, "name", where);
  l.construction = boolField(v, "construction", where);
  l.points = readPolyline(field(v, "points", where), where + "/points");
  if (l.points.size() < 2)
    fail(where + "/points", "a line needs at least 2 points");
  return l;
}

EdgeRef readEdge(const json& v, const std::string& where) {
  onlyKeys(v, where, {"panel", "from", "to"});
  return EdgeRef{stringField(v, "panel", where), intField(v, "from", where),
                 intField(v, "to", where)};
}

Panel readPanel(const json& v, const std::string& where) {
  onlyKeys(v, where,
           {"name", "outline", "darts", "grainline", "notches", "internal_lines", "cut_count",
            "cut_on_fold", "seam_allowance", "draft_regions"});
  Panel p;
  p.name = stringField(v, "name", where);
  p.outline = readPolyline(field(v, "outline", where), where + "/outline");
  if (p.outline.size() < 3)
    fail(where + "/outline", "a closed outline needs at least 3 points");
  const auto& darts = arrayField(v, "darts", where);
  for (std::size_t i = 0; i < darts.size(); ++i) {
    const std::string w = where + "/darts/" + std::to_string(i);
    onlyKeys(darts[i], w, {"name", "apex", "leg1", "leg2"});
    p.darts.push_back(Dart{stringField(darts[i], "name", w),
                           readPoint(field(darts[i], "apex", w), w + "/apex"),
                           readPoint(field(darts[i], "leg1", w), w + "/leg1"),
                           readPoint(field(darts[i], "leg2", w), w + "/leg2")});
  }
  const auto& g = field(v, "grainline", where);
  onlyKeys(g, where + "/grainline", {"start", "end"});
  p.grainline.start =
      readPoint(field(g, "start", where + "/grainline"), where + "/grainline/start");
  p.grainline.end = readPoint(field(g, "end", where + "/grainline"), where + "/grainline/end");
  const auto& notches = arrayField(v, "notches", where);
  for (std::size_t i = 0; i < notches.size(); ++i) {
    const std::string w = where + "/notches/" + std::to_string(i);
    onlyKeys(notches[i], w, {"name", "position"});
    p.notches.push_back(Notch{stringField(notches[i], "name", w),
                              readPoint(field(notches[i], "position", w), w + "/position")});
  }
  const auto& lines = arrayField(v, "internal_lines", where);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    p.internalLines.push_back(readLine(lines[i], where + "/internal_lines/" + std::to_string(i)));
  }
  p.cutCount = intField(v, "cut_count", where);
  if (p.cutCount < 1)
    fail(where + "/cut_count", "must be at least 1");
  p.cutOnFold = boolField(v, "cut_on_fold", where);
  p.seamAllowanceCm = numberField(v, "seam_allowance", where);
  if (p.seamAllowanceCm < 0)
    fail(where + "/seam_allowance", "must not be negative");
  const auto& regions = arrayField(v, "draft_regions", where);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (!regions[i].is_string())
      fail(where + "/draft_regions/" + std::to_string(i), "must be a string");
    p.draftRegions.push_back(regions[i].get<std::string>());
  }
  return p;
}

}  // namespace

json patternToJsonValue(const Pattern& pattern) {
  json root;
  root["format"] = "garmcap-pattern";
  root["version"] = kPatternFormatVersion;
  root["units"] = "cm";
  root["type"] = pattern.type;
  json m = json::object();
  for (const auto& [k, v] : pattern.measurements.values())
    m[k] = v;
  root["measurements"] = m;
  json d = json::object();
  for (const auto& [k, v] : pattern.design)
    d[k] = v;
  root["design"] = d;
  json pts = json::object();
  for (const auto& [k, v] : pattern.points)
    pts[k] = pointJson(v);
  root["points"] = pts;
  json lines = json::array();
  for (const auto& l : pattern.lines)
    lines.push_back(lineJson(l));
  root["lines"] = lines;
  json regions = json::array();
  for (const auto& r : pattern.regions) {
    regions.push_back(json{{"name", r.name}, {"polygon", polylineJson(r.polygon)}});
  }
  root["regions"] = regions;
  json panels = json::array();
  for (const auto& p : pattern.panels) {
    json darts = json::array();
    for (const auto& dt : p.darts) {
      darts.push_back(json{{"name", dt.name},
                           {"apex", pointJson(dt.apex)},
                           {"leg1", pointJson(dt.leg1)},
                           {"leg2", pointJson(dt.leg2)}});
    }
    json notches = json::array();
    for (const auto& n : p.notches) {
      notches.push_back(json{{"name", n.name}, {"position", pointJson(n.position)}});
    }
    json internal = json::array();
    for (const auto& l : p.internalLines)
      internal.push_back(lineJson(l));
    panels.push_back(
        json{{"name", p.name},
             {"outline", polylineJson(p.outline)},
             {"darts", darts},
             {"grainline",
              {{"start", pointJson(p.grainline.start)}, {"end", pointJson(p.grainline.end)}}},
             {"notches", notches},
             {"internal_lines", internal},
             {"cut_count", p.cutCount},
             {"cut_on_fold", p.cutOnFold},
             {"seam_allowance", p.seamAllowanceCm},
             {"draft_regions", p.draftRegions}});
  }
  root["panels"] = panels;
  json seams = json::array();
  for (const auto& s : pattern.seams) {
    seams.push_back(
        json{{"name", s.name}, {"a", edgeJson(s.a)}, {"b", edgeJson(s.b)}, {"ease", s.easeCm}});
  }
  root["seams"] = seams;
  return root;
}

std::string patternToJson(const Pattern& pattern) {
  return patternToJsonValue(pattern).dump(2) + "\n";
}

Pattern patternFromJsonValue(const json& root, const std::string& what) {
  onlyKeys(root, what,
           {"format", "version", "units", "type", "measurements", "design", "points", "lines",
            "regions", "panels", "seams"});
  if (stringField(root, "format", what) != "garmcap-pattern") {
    fail(what + ": /format", "must be \"garmcap-pattern\"");
  }
  const int version = intField(root, "version", what);
  if (version != kPatternFormatVersion) {
    fail(what + ": /version", "unsupported version " + std::to_string(version) +
                                  " (this build reads " + std::to_string(kPatternFormatVersion) +
                                  ")");
  }
  if (stringField(root, "units", what) != "cm")
    fail(what + ": /units", "must be \"cm\"");
  Pattern p;
  p.type = stringField(root, "type", what);
  const auto& m = field(root, "measurements", what);
  if (!m.is_object())
    fail(what + ": /measurements", "must be an object");
  for (const auto& [k, v] : m.items())
    p.measurements.set(k, number(v, what + ": /measurements/" + k));
  const auto& d = field(root, "design", what);
  if (!d.is_object())
    fail(what + ": /design", "must be an object");
  for (const auto& [k, v] : d.items())
    p.design[k] = number(v, what + ": /design/" + k);
  const auto& pts = field(root, "points", what);
  if (!pts.is_object())
    fail(what + ": /points", "must be an object");
  for (const auto& [k, v] : pts.items())
    p.points[k] = readPoint(v, what + ": /points/" + k);
  const auto& lines = arrayField(root, "lines", what);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    p.lines.push_back(readLine(lines[i], what + ": /lines/" + std::to_string(i)));
  }
  const auto& regions = arrayField(root, "regions", what);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const std::string w = what + ": /regions/" + std::to_string(i);
    onlyKeys(regions[i], w, {"name", "polygon"});
    DraftRegion r{stringField(regions[i], "name", w),
                  readPolyline(field(regions[i], "polygon", w), w + "/polygon")};
    if (r.polygon.size() < 3)
      fail(w + "/polygon", "a region needs at least 3 points");
    p.regions.push_back(std::move(r));
  }
  const auto& panels = arrayField(root, "panels", what);
  std::set<std::string> names;
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const std::string w = what + ": /panels/" + std::to_string(i);
    p.panels.push_back(readPanel(panels[i], w));
    if (!names.insert(p.panels.back().name).second) {
      fail(w + "/name", "duplicate panel name '" + p.panels.back().name + "'");
    }
  }
  const auto& seams = arrayField(root, "seams", what);
  for (std::size_t i = 0; i < seams.size(); ++i) {
    const std::string w = what + ": /seams/" + std::to_string(i);
    onlyKeys(seams[i], w, {"name", "a", "b", "ease"});
    SeamPair s{stringField(seams[i], "name", w), readEdge(field(seams[i], "a", w), w + "/a"),
               readEdge(field(seams[i], "b", w), w + "/b"), numberField(seams[i], "ease", w)};
    for (const auto* e : {&s.a, &s.b}) {
      const std::string we = w + (e == &s.a ? "/a" : "/b");
      if (!names.count(e->panel))
        fail(we + "/panel", "no panel named '" + e->panel + "'");
      const int n = static_cast<int>(p.panel(e->panel).outline.size());
      if (e->from < 0 || e->from >= n || e->to < 0 || e->to >= n) {
        fail(we, "vertex index out of range 0.." + std::to_string(n - 1));
      }
    }
    p.seams.push_back(std::move(s));
  }
  return p;
}

Pattern patternFromJson(const std::string& text, const std::string& what) {
  return patternFromJsonValue(parseJson(text, what), what);
}

void writePatternJson(const std::filesystem::path& path, const Pattern& pattern) {
  writeFileAtomic(path, patternToJson(pattern));
}

Pattern readPatternJson(const std::filesystem::path& path) {
  return patternFromJson(readFile(path), path.string());
}

}  // namespace garmcap::drafts
