// garmcap render / garmcap rig make: the scene simulator and rig maker (capture/sim/).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/capture/rig.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/sim/rig_maker.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

namespace garmcap::cli {

namespace {

struct RenderArgs {
  std::string type, measurements, size, chart, form, out, sleeve, skirt;
  std::uint64_t seed = 1;
  int width = 1728, height = 2304;
  capture::RigImageOptions images;
};

// --image-format png|jpg and --jpeg-quality N of `render` and `rig make`. The format is kept as
// text until the callback so that both options are checked together, with messages that name them.
struct ImageArgs {
  std::string format = "png";
  int jpegQuality = capture::kDefaultJpegQuality;
  CLI::Option* qualityOption = nullptr;

  void add(CLI::App* cmd) {
    cmd->add_option("--image-format", format,
                    "png (default; lossless, the rig contract) or jpg (what MJPEG cameras "
                    "deliver; about a fifth of the size)");
    qualityOption = cmd->add_option("--jpeg-quality", jpegQuality,
                                    "JPEG quality 1..100 with --image-format jpg (default " +
                                        std::to_string(capture::kDefaultJpegQuality) + ")");
  }

  capture::RigImageOptions options() const {
    capture::RigImageOptions o;
    if (format != "png" && format != "jpg")
      throw std::invalid_argument("--image-format must be png or jpg, not '" + format + "'");
    o.format = capture::parseRigImageFormat(format);
    if (qualityOption != nullptr && qualityOption->count() > 0 &&
        o.format != capture::RigImageFormat::kJpeg)
      throw std::invalid_argument("--jpeg-quality applies to --image-format jpg only");
    if (jpegQuality < 1 || jpegQuality > 100)
      throw std::invalid_argument("--jpeg-quality must be 1..100, not " +
                                  std::to_string(jpegQuality));
    o.jpegQuality = jpegQuality;
    return o;
  }
};

// Garment measurements file: {"units": "cm", "measurements": {"bust_circ": 96, ...}} with the
// names of truth.json for the type. A dress may omit garment_length (derived on the form from
// skirt_length), a sleeveless garment sleeve_length.
std::map<std::string, double> readGarmentMeasurements(const std::string& path,
                                                      const std::string& type) {
  const nlohmann::json j = drafts::readJsonFile(path);
  if (drafts::requireString(j, "units", path) != "cm") {
    throw drafts::ParseError(path + ": field 'units' must be \"cm\"");
  }
  const auto& m = drafts::requireField(j, "measurements", path);
  if (!m.is_object())
    throw drafts::ParseError(path + ": field 'measurements' must be an object");
  const auto& names = sim::garmentMeasurementNames(type);
  std::map<std::string, double> out;
  for (const auto& [k, v] : m.items()) {
    if (std::find(names.begin(), names.end(), k) == names.end()) {
      throw drafts::ParseError(path + ": measurement '" + k + "' does not apply to a " + type);
    }
    if (!v.is_number())
      throw drafts::ParseError(path + ": measurement '" + k + "' must be a number");
    out[k] = v.get<double>();
  }
  return out;
}

// The bundled form: $GARMCAP_FORM, else shared/ beside the checkout, found from the working
// directory (the repository root) or from the executable (build*/bin/garmcap).
std::string defaultForm() {
  if (const char* env = std::getenv("GARMCAP_FORM"); env != nullptr && *env != '\0')
    return env;
  const std::filesystem::path rel = "shared/data/forms/garmentcode_mean_female/form.json";
  std::vector<std::filesystem::path> tried = {std::filesystem::current_path() / ".." / rel};
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec)
    tried.push_back(exe.parent_path() / ".." / ".." / ".." / rel);
  for (const auto& p : tried) {
    if (std::filesystem::is_regular_file(p))
      return std::filesystem::weakly_canonical(p).string();
  }
  throw std::invalid_argument("no --form given and no bundled form found (tried " +
                              tried.front().string() + "); set GARMCAP_FORM or pass --form");
}

void runRender(const RenderArgs& a) {
  const auto form = calib::FormModel::load(a.form);
  sim::RandomSceneOptions so;
  so.size = {a.width, a.height};
  so.hardFraction = 0;
  so.type = a.type;
  sim::Scene scene = sim::randomScene(form, a.form, a.seed, so);
  auto& g = scene.garment;
  if (!a.sleeve.empty()) {
    if (g.type != "top" && g.type != "dress")
      throw std::invalid_argument("--sleeve applies to top and dress only");
    if (a.sleeve != "none" && a.sleeve != "short" && a.sleeve != "long") {
      throw std::invalid_argument("--sleeve must be none, short or long, not '" + a.sleeve + "'");
    }
    g.attributes["sleeve"] = a.sleeve;
  }
  if (!a.skirt.empty()) {
    if (g.type != "skirt" && g.type != "dress")
      throw std::invalid_argument("--skirt applies to skirt and dress only");
    if (a.skirt != "a_line" && a.skirt != "h_line") {
      throw std::invalid_argument("--skirt must be a_line or h_line, not '" + a.skirt + "'");
    }
    g.attributes["skirt"] = a.skirt;
  }
  // Lengths that depend on the form are taken in a small view of it (they do not depend on the
  // image size).
  const calib::FormView probe(form, sim::fitPose(form, {300, 400}), {300, 400});
  std::map<std::string, double> m;
  if (!a.measurements.empty()) {
    m = readGarmentMeasurements(a.measurements, g.type);
    // A dress file may omit garment_length: it follows from its skirt_length on the form.
    if (g.type == "dress" && m.count("skirt_length") && !m.count("garment_length"))
      m["garment_length"] = probe.neckSideCm() - probe.waistCm() + m["skirt_length"];
    if ((g.type == "top" || g.type == "dress") && g.attributes["sleeve"] == "none")
      m["sleeve_length"] = 0;
  } else {
    std::string recipe;
    m = sim::draftedGarment(g, drafts::sizeChart(a.chart).body(a.size), probe, &recipe);
    scene.chart = a.chart;
    scene.chartSize = a.size;
    std::fprintf(stderr, "garmcap render: drafted with recipe '%s' for %s size %s\n",
                 recipe.c_str(), a.chart.c_str(), a.size.c_str());
  }
  for (const auto& n : sim::garmentMeasurementNames(g.type)) {
    if (!m.count(n))
      throw std::invalid_argument("no '" + n + "' for the " + g.type +
                                  " (give it in --measurements)");
  }
  g.measurements = m;
  const sim::SceneRenderer renderer(form, scene);
  sim::writeCase(renderer, a.out, a.images);
  std::printf("%s: %s %dx%d, truth.json written\n", a.out.c_str(), g.type.c_str(), a.width,
              a.height);
}

}  // namespace

void addCaptureCommands(CLI::App& app, CLI::App& rigGroup) {
  auto args = std::make_shared<RenderArgs>();
  auto renderImages = std::make_shared<ImageArgs>();
  auto* render = app.add_subcommand(
      "render", "Render a simulated bare-form/dressed frame pair with truth.json");
  render->add_option("--type", args->type, "Garment type: top, dress, skirt, pants")->required();
  auto* meas = render->add_option("--measurements", args->measurements,
                                  "Garment measurements JSON (cm; names of truth.json)");
  auto* size = render->add_option("--size", args->size, "Size of --chart to draft the garment for");
  auto* chart = render->add_option("--chart", args->chart, "Size chart name");
  size->needs(chart);
  chart->needs(size);
  meas->excludes(size);
  meas->excludes(chart);
  render->add_option("--form", args->form, "Dress form sidecar (.json) or mesh")->required();
  render->add_option("--seed", args->seed, "Seed for lighting, fabric, pose and noise");
  render->add_option("--width", args->width, "Image width in px");
  render->add_option("--height", args->height, "Image height in px");
  render->add_option("--sleeve", args->sleeve,
                     "none, short or long (top, dress; default from the seed)");
  render->add_option("--skirt", args->skirt,
                     "a_line or h_line (skirt, dress; default from the seed)");
  render->add_option("--out", args->out, "Case folder to write")->required();
  renderImages->add(render);
  render->callback([args, renderImages] {
    if (args->measurements.empty() && args->size.empty()) {
      throw std::invalid_argument("render: give --measurements M.json or --size S --chart C");
    }
    args->images = renderImages->options();
    runRender(*args);
  });

  CLI::App* rig = &rigGroup;
  auto ro = std::make_shared<sim::RigMakeOptions>();
  auto form = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto wh = std::make_shared<std::pair<int, int>>(960, 1280);
  auto* make = rig->add_subcommand("make", "Render a rig of simulated cases and write rig.json");
  make->add_option("--count", ro->count, "Number of cases")->required();
  make->add_option("--seed", ro->seed, "Seed of the rig")->required();
  make->add_option("--out", *out, "Rig folder to write")->required();
  make->add_option("--form", *form,
                   "Dress form sidecar (.json) or mesh (default: $GARMCAP_FORM, else the bundled "
                   "GarmentCode mean female in ../shared)");
  make->add_option("--width", wh->first, "Image width in px (default 960)");
  make->add_option("--height", wh->second, "Image height in px (default 1280)");
  make->add_option("--hard-fraction", ro->hardFraction, "Share of hard cases (0..1, default 0.3)");
  make->add_option("--chart", ro->chart,
                   "Draft every garment for a size of this chart (see `garmcap draft --charts`; "
                   "sizes drawn from the seed, those that do not fit the form skipped). Default: "
                   "ease sampled around the form");
  make->add_flag(
      "--torso",
      [ro](std::int64_t n) {
        ro->formKind = n > 0 ? sim::FormKind::kTorso : sim::FormKind::kMannequin;
      },
      "With --chart: render each size on a torso form on a pole (make-form --torso) instead of a "
      "full mannequin");
  auto makeImages = std::make_shared<ImageArgs>();
  makeImages->add(make);
  make->callback([ro, form, out, wh, makeImages] {
    ro->images = makeImages->options();
    const std::string formPath = form->empty() ? defaultForm() : *form;
    const auto model = calib::FormModel::load(formPath);
    ro->size = {wh->first, wh->second};
    ro->progress = [](int i, int n, const std::string& id) {
      std::fprintf(stderr, "rig make: %d/%d %s\n", i + 1, n, id.c_str());
    };
    const auto r = sim::makeRig(model, formPath, *out, *ro);
    std::printf("%s: %zu cases, rig.json written\n", out->c_str(), r.cases.size());
  });
}

}  // namespace garmcap::cli
