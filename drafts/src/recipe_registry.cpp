// The garment types, their required measurements and design parameters, input validation, and
// the dispatch to the recipe functions (recipe_*.cpp).
#include <algorithm>
#include <cmath>
#include <set>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts {
namespace {

using detail::DraftBuilder;

DesignParameter easeBust(double dflt, double lo, double hi) {
  return {"ease_bust", dflt, lo, hi,
          "cm added to bust_circ: garment bust = bust_circ + ease_bust (negative only for knits)"};
}
DesignParameter easeWaist(double dflt, double lo, double hi) {
  return {"ease_waist", dflt, lo, hi, "cm added to waist_circ: garment waist = waist_circ + ease"};
}
DesignParameter easeHip(double dflt, double lo, double hi) {
  return {"ease_hip", dflt, lo, hi, "cm added to hip_circ: garment hip = hip_circ + ease_hip"};
}
DesignParameter seamAllowance() {
  return {"seam_allowance", 1.0, 0.0, 3.0, "seam allowance of every panel, cm"};
}
DesignParameter skirtLength(double dflt) {
  return {"skirt_length", dflt, 20, 130,
          "skirt length from the waist to the hem at centre front, cm (photo: hem level)"};
}
DesignParameter hemFlare(double dflt, double lo, double hi) {
  return {"hem_flare", dflt, lo, hi,
          "cm the hem is widened at each side seam edge below the hip (A-line flare; negative "
          "tapers); the garment hem = hip + ease + 4 x hem_flare (approximately)"};
}
std::vector<DesignParameter> sleeveParams(double capEase, double lengthDefault, double lengthMin,
                                          double wristEase) {
  return {{"sleeve_length", lengthDefault, lengthMin, 1.1,
           "sleeve length as a fraction of arm_shoulder_tip_to_wrist: 0 = sleeveless; up to the "
           "cap height (~0.25) a cap sleeve, cut across the cap; ~0.3 = short; 1 = long (to the "
           "wrist); at least 2 cm"},
          {"sleeve_cap_ease", capEase, 0, 6,
           "cm the sleeve cap is longer than the armhole it is set into (eased in)"},
          {"ease_wrist", wristEase, 0, 40,
           "cm added to arm_wrist_circ for the hem opening of a full-length sleeve"}};
}

std::vector<GarmentTypeInfo> buildTypes() {
  std::vector<GarmentTypeInfo> t;
  t.push_back({"bodice",
               "Basic bodice block (Bunka-style): front and back to the waist, back shoulder "
               "dart, bust (armhole) dart, waist darts",
               {"bust_circ", "waist_circ", "neck_back_to_waist_b", "bustpoint_to_bustpoint",
                "bustpoint_to_neck_side"},
               {easeBust(12, 4, 30), easeWaist(6, 0, 30), seamAllowance()}});
  {
    GarmentTypeInfo d{"dress",
                      "One-piece dress with a waist seam (seed table 5.1 inputs): Bunka bodice "
                      "with the shoulder set by the bi-shoulder length, skirt below, set-in "
                      "sleeve",
                      {"bust_circ", "waist_circ", "hip_circ", "neck_back_to_waist_b",
                       "waist_to_hip_b", "bustpoint_to_bustpoint", "shoulder_tip_to_shoulder_tip_b",
                       "arm_shoulder_tip_to_wrist", "arm_wrist_circ"},
                      {easeBust(12, 4, 30), easeWaist(6, 0, 30), easeHip(4, 0, 30), skirtLength(55),
                       hemFlare(0, -3, 25)}};
    // Every skirt block of research/drafting_blocks.md §2.1 takes part of the waist-hip
    // difference at the side seam (Bunka [S9] a third of the front's, Gilewska and Donnanno
    // [S1] about a quarter of d = (H - W)/2, Aldrich [S2] (H - W)/4 - 2.5, Keiko [S7] 3 cm);
    // 1 cm is below all of them for the charts' bodies, so the darts keep the larger share.
    d.design.push_back({"skirt_side_intake", 1.0, 0, 3,
                        "smallest intake of each skirt side seam edge from the hip to the waist, "
                        "cm; where the bodice's waist darts leave less, the difference moves from "
                        "them into the bodice side seam"});
    for (auto& p : sleeveParams(3, 1.0, 0, 8))
      d.design.push_back(p);
    d.design.push_back(seamAllowance());
    t.push_back(d);
  }
  {
    // Ease defaults: a shift's waist is about its bust (the body's waist plus the bust-waist
    // difference), its hip a little over the body's.
    GarmentTypeInfo d{"dress_shift",
                      "Shift dress: one back and one front piece from the shoulder to the hem, "
                      "no waist seam, bust dart, the waist shaped at the side seam (fish-eye "
                      "darts when it takes in), A-line flare at the side below the hip",
                      {"bust_circ", "waist_circ", "hip_circ", "neck_back_to_waist_b",
                       "waist_to_hip_b", "bustpoint_to_bustpoint", "shoulder_tip_to_shoulder_tip_b",
                       "arm_shoulder_tip_to_wrist", "arm_wrist_circ"},
                      {easeBust(10, 4, 30), easeWaist(24, 0, 60), easeHip(6, 0, 40),
                       skirtLength(50), hemFlare(0, -3, 25)}};
    for (auto& p : sleeveParams(3, 0.3, 0, 8))
      d.design.push_back(p);
    d.design.push_back(seamAllowance());
    t.push_back(d);
  }
  t.push_back({"skirt_h",
               "Straight (H-line) skirt block: back and front, two darts each, side seam "
               "straight below the hip",
               {"waist_circ", "hip_circ", "waist_to_hip_b"},
               {easeWaist(1, 0, 10), easeHip(4, 0, 20), skirtLength(60), hemFlare(0, -4, 4),
                seamAllowance()}});
  t.push_back({"skirt_a",
               "A-line skirt: the H-line block flared at the side seams below the hip",
               {"waist_circ", "hip_circ", "waist_to_hip_b"},
               {easeWaist(1, 0, 10), easeHip(4, 0, 20), skirtLength(60), hemFlare(6, 1, 30),
                seamAllowance()}});
  t.push_back({"skirt_high_waist",
               "High-waist skirt: the skirt block continued above the waist along the bodice "
               "side seam and darts",
               {"bust_circ", "waist_circ", "hip_circ", "neck_back_to_waist_b", "waist_to_hip_b"},
               {easeWaist(1, 0, 10),
                easeHip(4, 0, 20),
                skirtLength(60),
                hemFlare(0, -4, 10),
                {"waist_raise", 6, 2, 12, "height of the top edge above the natural waist, cm"},
                seamAllowance()}});
  t.push_back(
      {"pants",
       "Trousers block (Bunka school): front and back with crease grainline, waist "
       "darts, crotch extensions",
       {"waist_circ", "hip_circ", "waist_to_hip_b", "rise_length_side", "leg_waist_side_to_floor"},
       {easeWaist(1, 0, 10),
        easeHip(4, 0, 20),
        {"pants_length", 0.96, 0.3, 1.05,
         "trouser length from the waist as a fraction of leg_waist_side_to_floor"},
        // Bunka's test vector (research/drafting_blocks.md §5.1): hemHalf 10.5 at H 90.
        {"hem_width", 21, 12, 50,
         "front leg hem width, cm (back is 2 cm wider); default 21 x hip_circ / 90 (Bunka's "
         "21 at hip 90), and grows with the hip when graded",
         "hip_circ", 90},
        seamAllowance()}});
  {
    GarmentTypeInfo s{"sleeve",
                      "Set-in sleeve (Bunka): cap fitted to the armhole of the basic bodice plus "
                      "the cap ease; the bodice is drawn in grey for reference",
                      {"bust_circ", "waist_circ", "neck_back_to_waist_b",
                       "arm_shoulder_tip_to_wrist", "arm_wrist_circ"},
                      {easeBust(12, 4, 30), easeWaist(6, 0, 30)}};
    for (auto& p : sleeveParams(3, 1.0, 0.04, 8))
      s.design.push_back(p);
    s.design.push_back(seamAllowance());
    t.push_back(s);
  }
  {
    GarmentTypeInfo b{"blouse",
                      "Woven blouse/shirt: the bodice widened and lowered at the underarm, "
                      "extended below the waist, fish-eye darts, lower sleeve cap",
                      {"bust_circ", "waist_circ", "hip_circ", "neck_back_to_waist_b",
                       "waist_to_hip_b", "bustpoint_to_bustpoint", "bustpoint_to_neck_side",
                       "arm_shoulder_tip_to_wrist", "arm_wrist_circ"},
                      {easeBust(16, 8, 40),
                       easeWaist(16, 0, 60),
                       easeHip(10, 0, 60),
                       {"blouse_length", 22, 5, 60, "length below the waist at centre front, cm"},
                       {"underarm_drop", 2, 0, 6, "underarm point lowered from the block, cm"}}};
    for (auto& p : sleeveParams(1.5, 1.0, 0, 8))
      b.design.push_back(p);
    b.design.push_back(seamAllowance());
    t.push_back(b);
  }
  {
    GarmentTypeInfo s{
        "sweater",
        "Knit sweater: no darts, front = back except the neckline, zero or negative "
        "ease, low sleeve cap without cap ease",
        {"bust_circ", "hip_circ", "neck_back_to_waist_b", "waist_to_hip_b",
         "arm_shoulder_tip_to_wrist", "arm_wrist_circ"},
        {easeBust(0, -12, 30),
         easeHip(0, -12, 30),
         {"sweater_length", 20, 0, 50, "length below the waist at centre front, cm"},
         {"armhole_drop", 1, 0, 8, "underarm lowered below the block bust line, cm"}}};
    for (auto& p : sleeveParams(0, 1.0, 0, 5))
      s.design.push_back(p);
    s.design.push_back(seamAllowance());
    t.push_back(s);
  }
  return t;
}

// Plausible body ranges (cm): wide enough for the 50 %/200 % body sweeps of the tests to be
// judged by the recipes' geometry, narrow enough to refuse nonsense (height 20, negative).
struct Range {
  double lo, hi;
};
const std::map<std::string, Range>& plausible() {
  static const std::map<std::string, Range> r{{"bust_circ", {30, 250}},
                                              {"waist_circ", {20, 250}},
                                              {"hip_circ", {30, 260}},
                                              {"neck_back_to_waist_b", {15, 90}},
                                              {"waist_to_hip_b", {5, 50}},
                                              {"bustpoint_to_bustpoint", {5, 45}},
                                              {"bustpoint_to_neck_side", {8, 60}},
                                              {"shoulder_tip_to_shoulder_tip_b", {15, 90}},
                                              {"arm_shoulder_tip_to_wrist", {20, 120}},
                                              {"arm_wrist_circ", {7, 45}},
                                              {"rise_length_side", {10, 60}},
                                              {"leg_waist_side_to_floor", {40, 200}},
                                              {"height", {60, 260}}};
  return r;
}

void validateBody(const GarmentTypeInfo& info, const Measurements& body) {
  for (const auto& name : info.measurements) {
    const auto v = body.find(name);
    if (!v) {
      throw DraftError("recipe '" + info.name + "' needs measurement '" + name +
                       "', which is missing");
    }
  }
  for (const auto& [name, value] : body.values()) {
    if (!std::isfinite(value) || value <= 0) {
      throw DraftError("recipe '" + info.name + "': measurement '" + name +
                       "' = " + std::to_string(value) + " must be a positive number of cm");
    }
    auto it = plausible().find(name);
    if (it != plausible().end() && (value < it->second.lo || value > it->second.hi)) {
      throw DraftError("recipe '" + info.name + "': measurement '" + name +
                       "' = " + std::to_string(value) + " cm is outside the plausible range " +
                       std::to_string(it->second.lo) + ".." + std::to_string(it->second.hi) +
                       " cm");
    }
  }
  const auto bust = body.find("bust_circ");
  const auto waist = body.find("waist_circ");
  const auto hip = body.find("hip_circ");
  if (bust && waist && *waist > 1.4 * *bust) {
    throw DraftError("recipe '" + info.name + "': waist_circ " + std::to_string(*waist) +
                     " cm is far above bust_circ " + std::to_string(*bust) + " cm");
  }
  if (hip && waist && *waist > 1.4 * *hip) {
    throw DraftError("recipe '" + info.name + "': waist_circ " + std::to_string(*waist) +
                     " cm is far above hip_circ " + std::to_string(*hip) + " cm");
  }
}

}  // namespace

const std::vector<GarmentTypeInfo>& garmentTypes() {
  static const std::vector<GarmentTypeInfo> types = buildTypes();
  return types;
}

const GarmentTypeInfo& garmentType(const std::string& name) {
  for (const auto& t : garmentTypes()) {
    if (t.name == name)
      return t;
  }
  std::string known;
  for (const auto& t : garmentTypes())
    known += (known.empty() ? "" : ", ") + t.name;
  throw DraftError("unknown garment type '" + name + "' (types: " + known + ")");
}

Pattern draftGarment(const std::string& type, const Measurements& body,
                     const std::map<std::string, double>& design) {
  const GarmentTypeInfo& info = garmentType(type);
  validateBody(info, body);
  Pattern p;
  p.type = type;
  // Keep only what the recipe uses, so the pattern states exactly the body it was drafted for.
  for (const auto& name : info.measurements)
    p.measurements.set(name, body.get(name));
  for (const auto& d : info.design) {
    p.design[d.name] = d.defaultValue;
    // A width designed for a reference body grows with this one (hem_width with the hip).
    if (d.gradesFrom > 0 && !d.gradesWith.empty()) {
      if (auto v = body.find(d.gradesWith))
        p.design[d.name] = std::clamp(d.defaultValue * *v / d.gradesFrom, d.minValue, d.maxValue);
    }
    // A design value the body chart also carries (skirt_length: seed table 4.2 lists it as a
    // primary body size) defaults to the body's value, so size runs grade it like the seed.
    if (auto v = body.find(d.name); v && !design.count(d.name)) {
      if (*v < d.minValue || *v > d.maxValue) {
        throw DraftError("recipe '" + type + "': measurement '" + d.name +
                         "' = " + std::to_string(*v) + " is outside " + std::to_string(d.minValue) +
                         ".." + std::to_string(d.maxValue));
      }
      p.design[d.name] = *v;
      p.measurements.set(d.name, *v);
    }
  }
  for (const auto& [name, value] : design) {
    const DesignParameter* found = nullptr;
    for (const auto& d : info.design) {
      if (d.name == name)
        found = &d;
    }
    if (!found) {
      std::string known;
      for (const auto& d : info.design)
        known += (known.empty() ? "" : ", ") + d.name;
      throw DraftError("recipe '" + type + "' has no design parameter '" + name +
                       "' (parameters: " + known + ")");
    }
    if (!std::isfinite(value) || value < found->minValue || value > found->maxValue) {
      throw DraftError("recipe '" + type + "': design parameter '" + name +
                       "' = " + std::to_string(value) + " is outside " +
                       std::to_string(found->minValue) + ".." + std::to_string(found->maxValue));
    }
    p.design[name] = value;
  }
  DraftBuilder b(p, type);
  if (type == "bodice")
    detail::recipeBodice(b);
  else if (type == "dress")
    detail::recipeDress(b);
  else if (type == "dress_shift")
    detail::recipeDressShift(b);
  else if (type == "skirt_h" || type == "skirt_a")
    detail::recipeSkirt(b);
  else if (type == "skirt_high_waist")
    detail::recipeSkirtHighWaist(b);
  else if (type == "pants")
    detail::recipePants(b);
  else if (type == "sleeve")
    detail::recipeSleeve(b);
  else if (type == "blouse")
    detail::recipeBlouse(b);
  else if (type == "sweater")
    detail::recipeSweater(b);
  else
    throw std::logic_error("garment type '" + type + "' has no recipe function");
  detail::finishPattern(b);
  return p;
}

}  // namespace garmcap::drafts
