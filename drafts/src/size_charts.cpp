// Built-in size charts. Numbers and completion rules are documented in docs/size_charts.md.

#include "garmcap/drafts/size_charts.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace garmcap::drafts {

namespace {

// ---- completion rules ------------------------------------------------------------------------
// Measurements a chart lacks are completed from the ones it has by proportion to a reference
// body with every measurement published: size 44 of Donnanno's Italian women's chart (bust 96,
// stature 168; the chart is built in below). Widths and girths of the upper body scale with the
// bust, vertical lengths with the stature. The bi-shoulder width is built the way the Aldrich
// block builds the back shoulder line: two shoulder lengths plus two back neck widths of
// N/5 - 0.2 (research/drafting_blocks.md §1.2, step 3).
constexpr double kRefBust = 96.0;
constexpr double kRefHeight = 168.0;
constexpr double kRefNeck = 38.0;
constexpr double kRefAcrossChest = 38.9;
constexpr double kRefAcrossBack = 37.9;
constexpr double kRefShoulder = 13.5;
constexpr double kRefUpperArm = 30.0;
constexpr double kRefRise = 24.6;
constexpr double kRefWaistToFloor = 105.0;
constexpr double kRefWaistToKnee = 59.5;
constexpr double kRefWaistToHip = 20.4;
constexpr double kRefBackWaist = 40.9;

// Neck point to bust point (J02) by the bust, from Gilewska's French women's chart 34-48
// ("hauteur poitrine" 25.5 -> 29 for bust 80 -> 106; research/anchors_drafting.md §4.1),
// interpolated linearly and continued with its mean slope outside the table.
double bustpointToNeckSide(double bust) {
  static const std::vector<std::pair<double, double>> kTable = {
      {80, 25.5}, {84, 26}, {88, 26.5}, {92, 27}, {96, 27.5}, {100, 28}, {104, 28.5}, {106, 29}};
  const double slope =
      (kTable.back().second - kTable.front().second) / (kTable.back().first - kTable.front().first);
  if (bust <= kTable.front().first)
    return kTable.front().second + slope * (bust - kTable.front().first);
  if (bust >= kTable.back().first)
    return kTable.back().second + slope * (bust - kTable.back().first);
  for (size_t i = 1; i < kTable.size(); ++i) {
    if (bust <= kTable[i].first) {
      const auto [b0, v0] = kTable[i - 1];
      const auto [b1, v1] = kTable[i];
      return v0 + (v1 - v0) * (bust - b0) / (b1 - b0);
    }
  }
  return kTable.back().second;
}

double biShoulder(double shoulderLength, double neckCirc) {
  return 2 * shoulderLength + 2 * (neckCirc / 5 - 0.2);
}

// Completed values are rounded to 1 mm, the precision of a tape measure and of the charts.
void setIfMissing(Measurements& m, const std::string& name, double value) {
  if (!m.has(name))
    m.set(name, std::round(value * 10.0) / 10.0);
}

// Fills every measurement a recipe or the grading tests need and the chart does not give.
void complete(Measurements& m) {
  const double bust = m.get("bust_circ");
  const double height = m.get("height");
  const double b = bust / kRefBust;
  const double h = height / kRefHeight;
  setIfMissing(m, "neck_circ", kRefNeck * b);
  setIfMissing(m, "across_chest_f", kRefAcrossChest * b);
  setIfMissing(m, "across_back_b", kRefAcrossBack * b);
  setIfMissing(m, "shoulder_length", kRefShoulder * b);
  setIfMissing(m, "arm_upper_circ", kRefUpperArm * b);
  setIfMissing(m, "shoulder_tip_to_shoulder_tip_b",
               biShoulder(m.get("shoulder_length"), m.get("neck_circ")));
  setIfMissing(m, "bustpoint_to_neck_side", bustpointToNeckSide(bust));
  setIfMissing(m, "rise_length_side", kRefRise * h);
  setIfMissing(m, "leg_waist_side_to_floor", kRefWaistToFloor * h);
  setIfMissing(m, "leg_waist_side_to_knee", kRefWaistToKnee * h);
  setIfMissing(m, "waist_to_hip_b", kRefWaistToHip * h);
  if (m.has("front_armhole_circ") && m.has("back_armhole_circ")) {
    setIfMissing(m, "armscye_circ", m.get("front_armhole_circ") + m.get("back_armhole_circ"));
  }
}

// One row per measurement, one column per size.
struct Row {
  const char* name;
  std::vector<double> values;
};

std::vector<Measurements> bodiesFromRows(const std::vector<Row>& rows, size_t sizes) {
  std::vector<Measurements> bodies(sizes);
  for (const auto& row : rows) {
    for (size_t i = 0; i < sizes; ++i)
      bodies[i].set(row.name, row.values.at(i));
  }
  return bodies;
}

// Table 4.2's grading rule: one constant step per size for every row (44 -> 55 -> 66 -> 77 in
// the seed). Size 88 is 77 plus this step; no source gives an 88 of that series.
SizeChart koreanWomen() {
  SizeChart c;
  c.name = "korean_women";
  c.sizes = {"44", "55", "66", "77", "88"};
  c.source =
      "Korean women's sizes 44-88 from the dissertation (seed): sizes 44, 55, 66, 77 are the "
      "bodies of its grading experiment, Table 4.2 (all 13 rows), whose rows grow by one "
      "constant step per size (bust, waist, hip +5; waist back length, BP-BP, hip length, "
      "armholes, sleeve, wrist +0.6; neck point-BP +0.8; skirt length +1.9; height +1.5); size "
      "88 is 77 plus that step (an extrapolation by the table's own rule: no source gives an 88 "
      "of this series). Table 3.1's size 88 (bust 98, waist 78, hip 104, waist back length 42, "
      "BP-BP 18.8, neck point-BP 26.8) belongs to another series: Table 3.1 and Table 4.2 "
      "DISAGREE on sizes 44 and 66 too (Table 3.1: 44 = bust 82 / waist 62 / hip 88 / WBL 38 / "
      "NP-BP 24.4, 66 = 90 / 70 / 96 / 40 / 25.6; Table 4.2: 44 = 80 / 60 / 85 / 38.4 / 23.2, "
      "66 = 90 / 70 / 95 / 39.6 / 24.8), so splicing its 88 onto Table 4.2 made the 77 -> 88 "
      "step bust 3 and waist back length 1.8. Table 4.2's heights (169.5-174 cm) are the "
      "seed's, not the 1981 KS label's 150-165 cm. Measurements the tables lack (neck, across "
      "chest/back, shoulder length, upper arm, bi-shoulder width, rise, waist to floor/knee) are "
      "completed by proportion to Donnanno's Italian size 44 (widths with the bust, lengths with "
      "the height; bi-shoulder = 2 shoulder lengths + 2 Aldrich back neck widths N/5 - 0.2); "
      "armscye_circ = front + back armhole. See docs/size_charts.md.";
  const std::vector<Row> table42 = {
      {"bust_circ", {80.0, 85.0, 90.0, 95.0}},
      {"waist_circ", {60.0, 65.0, 70.0, 75.0}},
      {"hip_circ", {85.0, 90.0, 95.0, 100.0}},
      {"neck_back_to_waist_b", {38.4, 39.0, 39.6, 40.2}},
      {"bustpoint_to_bustpoint", {16.4, 17.0, 17.6, 18.2}},
      {"bustpoint_to_neck_side", {23.2, 24.0, 24.8, 25.6}},
      {"skirt_length", {53.4, 55.3, 57.2, 59.1}},
      {"waist_to_hip_b", {18.4, 19.0, 19.6, 20.2}},
      {"height", {169.5, 171.0, 172.5, 174.0}},
      {"front_armhole_circ", {19.6, 20.2, 20.8, 21.4}},
      {"back_armhole_circ", {20.8, 21.4, 22.0, 22.6}},
      {"arm_shoulder_tip_to_wrist", {56.4, 57.0, 57.6, 58.2}},
      {"arm_wrist_circ", {19.4, 20.0, 20.6, 21.2}},
  };
  std::vector<Row> rows = table42;
  // 88 = 77 + the row's own constant step, 77 - 66 (40.2 + 0.6 -> 40.8).
  for (auto& row : rows) {
    const double step = row.values[3] - row.values[2];
    row.values.push_back(std::round((row.values.back() + step) * 1000.0) / 1000.0);
  }
  c.bodies = bodiesFromRows(rows, c.sizes.size());
  for (auto& b : c.bodies)
    complete(b);
  return c;
}

SizeChart italianWomen() {
  SizeChart c;
  c.name = "italian_women";
  c.sizes = {"40", "42", "44", "46", "48", "50"};
  c.source =
      "Italian women's sizes 40-50 from A. Donnanno, Fashion Patternmaking Techniques vol. 1 "
      "(women's size chart, 21 measurements), as transcribed in the OpenPattern project's "
      "measurements/DonnannoW.csv; bust, waist and stature rows cross-checked against "
      "research/anchors_drafting.md §4.1. Published values are kept as published, including "
      "steps of 0 (wrist 44/46 and 48/50, BP span 48/50, shoulder 42/44, sleeve 48/50). Not in "
      "the chart and completed: shoulder_tip_to_shoulder_tip_b = 2 shoulder lengths + 2 Aldrich "
      "back neck widths N/5 - 0.2; bustpoint_to_neck_side from Gilewska's French chart by the "
      "bust (Donnanno's bust depth is vertical: neck_side_to_bust_f). Mapping of Donnanno's rows "
      "to Valentina names in "
      "docs/size_charts.md.";
  const std::vector<Row> rows = {
      {"highbust_circ", {84, 86, 89, 92, 96, 100}},
      {"bust_circ", {89, 92, 96, 100, 105, 110}},
      {"waist_circ", {66, 68, 72, 76, 81, 86}},
      {"hip_circ", {89, 92, 96, 100, 105, 110}},
      {"across_chest_f", {36.1, 37.1, 38.9, 40.5, 42.5, 44.5}},
      {"across_back_b", {35.2, 36.5, 37.9, 39.5, 41.5, 43.5}},
      {"neck_circ", {36, 37, 38, 39, 40, 41}},
      {"height", {164, 166, 168, 170, 172, 174}},
      {"bustpoint_to_bustpoint", {17, 18, 19, 20, 21, 21}},
      {"shoulder_length", {12, 13.5, 13.5, 14, 14.5, 15}},
      {"neck_back_to_waist_b", {39.1, 40, 40.9, 41.8, 42.7, 43.6}},
      {"neck_side_to_waist_bustpoint_f", {40.4, 41.5, 42.6, 43.7, 44.8, 45.9}},
      {"neck_side_to_bust_f", {21.8, 22.5, 23.2, 23.9, 24.6, 25.1}},
      {"waist_to_hip_b", {19.6, 20, 20.4, 20.8, 21.2, 21.6}},
      {"rise_length_side", {23.5, 24, 24.6, 25.2, 25.8, 26.5}},
      {"leg_waist_side_to_knee", {57.5, 58.5, 59.5, 60.5, 61.5, 62.5}},
      {"leg_waist_side_to_floor", {102, 104, 105, 106, 107, 108}},
      {"arm_upper_circ", {28, 29, 30, 31.5, 33, 35}},
      {"arm_wrist_circ", {18, 19, 20, 20, 21, 21}},
      {"arm_shoulder_tip_to_wrist", {57, 58, 59, 60, 61, 61}},
  };
  c.bodies = bodiesFromRows(rows, c.sizes.size());
  for (auto& b : c.bodies)
    complete(b);
  return c;
}

// Gilewska's chart gives no stature. The one vertical length it gives for every size is the
// back waist length, so the stature the other lengths are completed from scales with it, the
// way the completion rules scale lengths with the stature (Donnanno 44: back 40.9, stature 168).
double heightFromBackWaist(double backWaist) {
  return kRefHeight * backWaist / kRefBackWaist;
}

SizeChart frenchWomen() {
  SizeChart c;
  c.name = "french_women";
  c.sizes = {"34", "36", "38", "40", "42", "44", "46", "48"};
  c.source =
      "French women's sizes 34-48 from T. Gilewska, Le modelisme de mode vol. 1 (women's size "
      "chart), as recorded from the OpenPattern project's measurements database in "
      "research/anchors_drafting.md section 4.1: bust (tour de poitrine) 80, 84, ..., 104, 106; "
      "waist 58-86 and hip (tour de bassin) 84-112 in steps of 4; back waist length 41.25-43 "
      "in steps of 0.25; BP span 18.5-22 in steps of 0.5; bust height (hauteur poitrine, neck "
      "point to bust point) 25.5-29 in steps of 0.5; shoulder length 13.4-14.8 in steps of 0.2; "
      "wrist 15.25-17 in steps of 0.25. The sleeve length row is recorded only as the range "
      "59-60: taken as 59 at size 34 to 60 at size 48, linearly (an interpolation, not the "
      "book's per-size values). Completed (not in the recorded rows): height = 168 x back "
      "waist length / 40.9 (the chart has no stature), then hip length, rise, waist to "
      "floor/knee with the height and neck, across chest/back and upper arm with the bust, by "
      "proportion to Donnanno's Italian size 44; bi-shoulder = 2 shoulder lengths + 2 Aldrich "
      "back neck widths N/5 - 0.2. See docs/size_charts.md.";
  const std::vector<Row> rows = {
      {"bust_circ", {80, 84, 88, 92, 96, 100, 104, 106}},
      {"waist_circ", {58, 62, 66, 70, 74, 78, 82, 86}},
      {"hip_circ", {84, 88, 92, 96, 100, 104, 108, 112}},
      {"neck_back_to_waist_b", {41.25, 41.5, 41.75, 42, 42.25, 42.5, 42.75, 43}},
      {"bustpoint_to_bustpoint", {18.5, 19, 19.5, 20, 20.5, 21, 21.5, 22}},
      {"bustpoint_to_neck_side", {25.5, 26, 26.5, 27, 27.5, 28, 28.5, 29}},
      {"shoulder_length", {13.4, 13.6, 13.8, 14, 14.2, 14.4, 14.6, 14.8}},
      {"arm_wrist_circ", {15.25, 15.5, 15.75, 16, 16.25, 16.5, 16.75, 17}},
  };
  c.bodies = bodiesFromRows(rows, c.sizes.size());
  for (size_t i = 0; i < c.bodies.size(); ++i) {
    auto& b = c.bodies[i];
    const double t = static_cast<double>(i) / static_cast<double>(c.bodies.size() - 1);
    setIfMissing(b, "arm_shoulder_tip_to_wrist", 59.0 + t * (60.0 - 59.0));
    setIfMissing(b, "height", heightFromBackWaist(b.get("neck_back_to_waist_b")));
    complete(b);
  }
  return c;
}

}  // namespace

const Measurements& SizeChart::body(const std::string& size) const {
  for (size_t i = 0; i < sizes.size(); ++i) {
    if (sizes[i] == size)
      return bodies.at(i);
  }
  std::string known;
  for (const auto& s : sizes)
    known += (known.empty() ? "" : ", ") + s;
  throw std::invalid_argument("size chart '" + name + "' has no size '" + size +
                              "' (sizes: " + known + ")");
}

const std::vector<SizeChart>& sizeCharts() {
  static const std::vector<SizeChart> kCharts = {koreanWomen(), italianWomen(), frenchWomen()};
  return kCharts;
}

const SizeChart& sizeChart(const std::string& name) {
  for (const auto& c : sizeCharts()) {
    if (c.name == name)
      return c;
  }
  std::string known;
  for (const auto& c : sizeCharts())
    known += (known.empty() ? "" : ", ") + c.name;
  throw std::invalid_argument("unknown size chart '" + name + "' (known charts: " + known + ")");
}

}  // namespace garmcap::drafts
