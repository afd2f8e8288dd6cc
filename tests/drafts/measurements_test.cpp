// Measurement vocabulary, measurements JSON and Valentina .vit files.

#include "garmcap/drafts/measurements.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <set>

#include "../common/temp_folder.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::drafts {
namespace {

using ::testing::HasSubstr;

// The message of the ParseError that `fn` throws ("" when it throws none).
template <typename Fn>
std::string parseErrorOf(Fn fn) {
  try {
    fn();
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

Measurements sample() {
  return Measurements({{"bust_circ", 85.0},
                       {"waist_circ", 65.0},
                       {"neck_back_to_waist_b", 39.0},
                       {"bustpoint_to_neck_side", 24.0},
                       {"skirt_length", 55.3},
                       {"shoulder_slope_neck_side_angle", 21.5},
                       {"arm_wrist_circ", 1.0 / 3.0}});
}

// One folder for the binary's files, removed when it exits.
std::filesystem::path tempDir() {
  static const garmcap::testing::TempFolder folder("garmcap_measurements_test");
  return folder.path();
}

TEST(MeasurementVocabulary, HasEveryValentinaNameAndTheProjectNames) {
  const auto& v = measurementVocabulary();
  int valentina = 0;
  for (const auto& m : v)
    valentina += m.valentinaKnown ? 1 : 0;
  EXPECT_EQ(valentina, 244);  // Valentina 0.7.52 known measurements
  for (const char* name : {"bust_circ",
                           "waist_circ",
                           "hip_circ",
                           "height",
                           "neck_back_to_waist_b",
                           "waist_to_hip_b",
                           "shoulder_length",
                           "shoulder_tip_to_shoulder_tip_b",
                           "shoulder_tip_to_shoulder_tip_f",
                           "across_back_b",
                           "across_chest_f",
                           "bustpoint_to_bustpoint",
                           "bustpoint_to_neck_side",
                           "neck_circ",
                           "armscye_circ",
                           "arm_shoulder_tip_to_wrist",
                           "arm_upper_circ",
                           "arm_wrist_circ",
                           "leg_waist_side_to_floor",
                           "leg_waist_side_to_knee",
                           "leg_crotch_to_floor",
                           "rise_length_side",
                           "crotch_length",
                           "leg_thigh_upper_circ",
                           "leg_knee_circ",
                           "leg_ankle_circ"}) {
    EXPECT_TRUE(isKnownMeasurement(name)) << name;
  }
  for (const char* name : {"skirt_length", "front_armhole_circ", "back_armhole_circ"}) {
    EXPECT_TRUE(isKnownMeasurement(name)) << name;
    const auto it = std::find_if(v.begin(), v.end(), [&](const auto& m) { return m.name == name; });
    ASSERT_NE(it, v.end());
    EXPECT_FALSE(it->valentinaKnown);
    EXPECT_FALSE(it->description.empty());
  }
  EXPECT_FALSE(isKnownMeasurement("bust"));
  // No name twice.
  std::set<std::string> names;
  for (const auto& m : v)
    EXPECT_TRUE(names.insert(m.name).second) << m.name;
}

TEST(Measurements, AccessAndScale) {
  const Measurements m = sample();
  EXPECT_EQ(m.get("bust_circ"), 85.0);
  EXPECT_FALSE(m.find("hip_circ"));
  try {
    m.get("hip_circ");
    FAIL() << "expected out_of_range";
  } catch (const std::out_of_range& e) {
    EXPECT_THAT(e.what(), HasSubstr("hip_circ"));
  }
  const Measurements s = m.scaled(2.0);
  EXPECT_EQ(s.get("bust_circ"), 170.0);
  EXPECT_EQ(s.get("shoulder_slope_neck_side_angle"), 21.5);  // angles keep their shape
}

TEST(MeasurementsJson, RoundTripIsExact) {
  const Measurements m = sample();
  EXPECT_EQ(measurementsFromJson(measurementsToJson(m), "mem"), m);
  const auto path = tempDir() / "body.json";
  writeMeasurementsJson(path, m);
  EXPECT_EQ(readMeasurementsJson(path), m);
  EXPECT_EQ(readMeasurementsFile(path), m);
  // Random bodies round-trip bit for bit.
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> d(0, 300);
  for (int k = 0; k < 20; ++k) {
    Measurements r;
    for (const auto& info : measurementVocabulary()) {
      if (gen() % 5 == 0)
        r.set(info.name, d(gen));
    }
    EXPECT_EQ(measurementsFromJson(measurementsToJson(r), "mem"), r);
  }
}

TEST(MeasurementsJson, StrictReader) {
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(
                    "{\"units\": \"cm\",\n \"measurements\": {\"bust_circ\": 85,}}", "body.json");
              }),
              AllOf(HasSubstr("body.json"), HasSubstr("line 2")));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "cm", "measurements": {"bust": 85}})", "b.json");
              }),
              AllOf(HasSubstr("b.json"), HasSubstr("unknown measurement"), HasSubstr("bust")));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "cm", "measurements": {"bust_circ": "85"}})",
                                     "b.json");
              }),
              AllOf(HasSubstr("b.json"), HasSubstr("bust_circ"), HasSubstr("number")));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "cm", "measurements": {"bust_circ": -85}})",
                                     "b.json");
              }),
              AllOf(HasSubstr("b.json"), HasSubstr("bust_circ"), HasSubstr("negative")));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "cm", "measurements": {"bust_circ": 1e999}})",
                                     "b.json");
              }),
              HasSubstr("b.json"));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "mm", "measurements": {"bust_circ": 850}})",
                                     "b.json");
              }),
              AllOf(HasSubstr("b.json"), HasSubstr("units")));
  EXPECT_THAT(parseErrorOf([] { measurementsFromJson(R"({"measurements": {}})", "b.json"); }),
              AllOf(HasSubstr("b.json"), HasSubstr("units")));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "cm", "measurements": {}, "extra": 1})",
                                     "b.json");
              }),
              AllOf(HasSubstr("b.json"), HasSubstr("extra")));
  EXPECT_THAT(parseErrorOf([] { measurementsFromJson(R"([1, 2])", "b.json"); }),
              HasSubstr("b.json"));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromJson(R"({"units": "cm", "measurements": [85]})", "b.json");
              }),
              AllOf(HasSubstr("b.json"), HasSubstr("measurements")));
  EXPECT_THROW(readMeasurementsJson("/nonexistent/garmcap/body.json"), FileError);
  // Writers refuse what readers would refuse.
  EXPECT_THROW(measurementsToJson(Measurements({{"bust", 1.0}})), std::invalid_argument);
  EXPECT_THROW(measurementsToJson(Measurements({{"bust_circ", std::nan("")}})),
               std::invalid_argument);
}

TEST(MeasurementsVit, RoundTripIncludingProjectNames) {
  const Measurements m = sample();
  const std::string xml = measurementsToVit(m);
  EXPECT_THAT(xml, HasSubstr("<m name=\"bust_circ\" value=\"85\"/>"));
  EXPECT_THAT(xml, HasSubstr("name=\"@skirt_length\""));  // custom measurement for Valentina
  EXPECT_EQ(measurementsFromVit(xml, "mem.vit"), m);
  const auto path = tempDir() / "body.vit";
  writeVit(path, m);
  EXPECT_EQ(readVit(path), m);
  EXPECT_EQ(readMeasurementsFile(path), m);
  EXPECT_THROW(readMeasurementsFile(tempDir() / "body.txt"), ParseError);
}

// A file as Valentina writes it (format 0.5.1, mm), with a custom measurement, a separator-like
// entry, comments, entities and an image child.
constexpr const char* kValentinaMm = R"(<?xml version="1.0" encoding="UTF-8"?>
<vit>
    <!--Measurements created with Valentina (https://valentinaproject.bitbucket.io/).-->
    <version>0.5.1</version>
    <read-only>false</read-only>
    <notes>Fitting &amp; notes &lt;1&gt; &#233;</notes>
    <unit>mm</unit>
    <pm_system>998</pm_system>
    <personal>
        <customer>A &quot;customer&quot;</customer>
        <birth-date>1990-01-01</birth-date>
        <gender>female</gender>
        <email/>
    </personal>
    <body-measurements>
        <m name="bust_circ" value="880"/>
        <m name='waist_circ' value=' 700 ' full_name="Waist"/>
        <m name="@my_note" value="12" full_name="private" description=""/>
        <m name="sep" type="separator"/>
        <m name="shoulder_slope_neck_side_angle" value="20"/>
        <m name="hip_circ" value="940"><image contentType="image/png">AAAA</image></m>
    </body-measurements>
</vit>
)";

TEST(MeasurementsVit, ReadsValentinaFileAndConvertsUnits) {
  const Measurements m = measurementsFromVit(kValentinaMm, "a.vit");
  EXPECT_NEAR(m.get("bust_circ"), 88.0, 1e-12);
  EXPECT_NEAR(m.get("waist_circ"), 70.0, 1e-12);
  EXPECT_NEAR(m.get("hip_circ"), 94.0, 1e-12);
  EXPECT_EQ(m.get("shoulder_slope_neck_side_angle"), 20.0);  // degrees stay degrees
  EXPECT_EQ(m.values().size(), 4u);                          // @my_note and the separator skipped
  std::string inch = kValentinaMm;
  inch.replace(inch.find("<unit>mm</unit>"), 15, "<unit>inch</unit>");
  EXPECT_NEAR(measurementsFromVit(inch, "a.vit").get("bust_circ"), 880 * 2.54, 1e-9);
}

TEST(MeasurementsVit, MalformedFilesNameFileAndPlace) {
  auto withBody = [](const std::string& body, const std::string& unit = "cm") {
    return "<?xml version=\"1.0\"?>\n<vit>\n<version>0.5.1</version>\n<unit>" + unit +
           "</unit>\n<body-measurements>\n" + body + "</body-measurements>\n</vit>\n";
  };
  EXPECT_EQ(measurementsFromVit(withBody("<m name=\"bust_circ\" value=\"85\"/>\n"), "x.vit")
                .get("bust_circ"),
            85.0);
  // Syntax errors: line and column.
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("<m name=\"bust_circ\" value=\"85\">\n"), "x.vit");
              }),
              AllOf(HasSubstr("x.vit"), HasSubstr("line 6"), HasSubstr("does not match")));
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("<m name=\"bust_circ value=\"85\"/>\n"), "x.vit");
              }),
              AllOf(HasSubstr("x.vit"), HasSubstr("line 6")));
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("<m name=\"a&b;\" value=\"85\"/>\n"), "x.vit");
              }),
              AllOf(HasSubstr("x.vit"), HasSubstr("line 6"), HasSubstr("entity")));
  EXPECT_THAT(parseErrorOf([] { measurementsFromVit("<vit>\n<version>", "x.vit"); }),
              AllOf(HasSubstr("x.vit"), HasSubstr("line 2")));
  EXPECT_THAT(parseErrorOf([] { measurementsFromVit("", "x.vit"); }), HasSubstr("x.vit"));
  EXPECT_THAT(parseErrorOf([] { measurementsFromVit("<vit/><vit/>", "x.vit"); }),
              AllOf(HasSubstr("x.vit"), HasSubstr("after the root")));
  EXPECT_THAT(parseErrorOf(
                  [] { measurementsFromVit("<!DOCTYPE vit [<!ENTITY a \"b\">]><vit/>", "x.vit"); }),
              HasSubstr("DOCTYPE"));
  EXPECT_THAT(parseErrorOf([] {
                std::string deep;
                for (int i = 0; i < 1000; ++i)
                  deep += "<a>";
                measurementsFromVit(deep, "x.vit");
              }),
              HasSubstr("deeper"));
  // Content errors: the element's line and the measurement.
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("<m name=\"bust\" value=\"85\"/>\n"), "x.vit");
              }),
              AllOf(HasSubstr("x.vit: line 6"), HasSubstr("unknown measurement 'bust'")));
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("\n<m name=\"bust_circ\" value=\"bust_circ*2\"/>\n"),
                                    "x.vit");
              }),
              AllOf(HasSubstr("x.vit: line 7"), HasSubstr("not a number")));
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("<m name=\"bust_circ\" value=\"-1\"/>\n"), "x.vit");
              }),
              AllOf(HasSubstr("line 6"), HasSubstr("negative")));
  EXPECT_THAT(parseErrorOf([&] {
                measurementsFromVit(withBody("<m name=\"bust_circ\" value=\"nan\"/>\n"), "x.vit");
              }),
              AllOf(HasSubstr("line 6"), HasSubstr("finite")));
  EXPECT_THAT(
      parseErrorOf([&] { measurementsFromVit(withBody("<m name=\"bust_circ\"/>\n"), "x.vit"); }),
      AllOf(HasSubstr("line 6"), HasSubstr("no value")));
  EXPECT_THAT(
      parseErrorOf([&] {
        measurementsFromVit(
            withBody("<m name=\"bust_circ\" value=\"1\"/>\n<m name=\"bust_circ\" value=\"2\"/>\n"),
            "x.vit");
      }),
      AllOf(HasSubstr("line 7"), HasSubstr("twice")));
  EXPECT_THAT(parseErrorOf([&] { measurementsFromVit(withBody("", "yard"), "x.vit"); }),
              AllOf(HasSubstr("line 4"), HasSubstr("yard")));
  EXPECT_THAT(
      parseErrorOf([] { measurementsFromVit("<vst><version>0.5.0</version></vst>", "x.vit"); }),
      AllOf(HasSubstr("line 1"), HasSubstr("<vit>")));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromVit(
                    "<vit><version>1.2.0</version><unit>cm</unit><body-measurements/></vit>",
                    "x.vit");
              }),
              HasSubstr("not supported"));
  EXPECT_THAT(parseErrorOf([] {
                measurementsFromVit("<vit><version>0.5.1</version><unit>cm</unit></vit>", "x.vit");
              }),
              HasSubstr("body-measurements"));
  EXPECT_THROW(readVit("/nonexistent/garmcap/body.vit"), FileError);
}

// Mutated files (bytes flipped, deleted, duplicated, truncated) are either read or refused
// with a ParseError; nothing else escapes and nothing crashes (run under ASan in CI).
TEST(MeasurementsVit, MutatedInputIsReadOrRefusedCleanly) {
  std::mt19937 gen(11);
  const std::string vit = kValentinaMm;
  const std::string json = measurementsToJson(sample());
  const std::string alphabet = "<>/=\"'&;#x!-?[] \n@amv0123456789.e";
  int refused = 0;
  for (int k = 0; k < 1500; ++k) {
    std::string text = (k % 2 == 0) ? vit : json;
    const int edits = 1 + int(gen() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const size_t at = gen() % text.size();
      switch (gen() % 4) {
        case 0:
          text[at] = alphabet[gen() % alphabet.size()];
          break;
        case 1:
          text.erase(at, 1 + gen() % 8);
          break;
        case 2:
          text.insert(at, text.substr(at / 2, gen() % 16));
          break;
        default:
          text.resize(at);
          break;
      }
    }
    try {
      const Measurements m = (k % 2 == 0) ? measurementsFromVit(text, "fuzz.vit")
                                          : measurementsFromJson(text, "fuzz.json");
      for (const auto& [name, v] : m.values()) {
        EXPECT_TRUE(isKnownMeasurement(name));
        EXPECT_TRUE(std::isfinite(v) && v >= 0);
      }
    } catch (const ParseError& e) {
      ++refused;
      EXPECT_THAT(e.what(), HasSubstr((k % 2 == 0) ? "fuzz.vit" : "fuzz.json"));
    }
  }
  EXPECT_GT(refused, 500);
}

}  // namespace
}  // namespace garmcap::drafts
