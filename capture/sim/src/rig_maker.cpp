#include "garmcap/sim/rig_maker.h"

#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>
#include <utility>

#include "garmcap/calib/mesh.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/sim/form_generator.h"
#include "garmcap/sim/garment_model.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

namespace garmcap::sim {

using capture::readRig;
using capture::Rig;
using capture::rigImageExtension;
using capture::RigImageFormat;

Rig makeRig(const calib::FormModel& form, const std::string& formPathArg,
            const std::filesystem::path& outDir, const RigMakeOptions& options) {
  // Cases name their form; a relative name would later be read relative to the case folder.
  const std::string formPath = std::filesystem::absolute(formPathArg).lexically_normal().string();
  if (options.count < 1)
    throw std::invalid_argument("rig make: --count must be at least 1");
  options.images.validate();
  if (!options.chart.empty())
    drafts::sizeChart(options.chart);  // an unknown chart is refused before anything is written
  std::filesystem::create_directories(outDir);
  // With a chart every case is a size of it, body and garment: the form is the parametric form
  // of that size's body (written once per size under forms/) and the garment is the draft for
  // the same body. The size is drawn from the case's seed.
  std::map<std::string, std::pair<std::string, calib::FormModel>> sizeForms;
  auto formOfSize =
      [&](const std::string& size) -> const std::pair<std::string, calib::FormModel>& {
    auto it = sizeForms.find(size);
    if (it == sizeForms.end()) {
      const auto& chart = drafts::sizeChart(options.chart);
      const ParametricForm pf(chart.body(size), options.formKind);
      const auto dir = outDir / "forms" / (chart.name + "_" + size);
      std::filesystem::create_directories(dir);
      calib::FormSidecar sidecar = pf.sidecar("form.obj");
      sidecar.name = chart.name + " size " + size;
      calib::writeObj(dir / "form.obj", pf.mesh(),
                      "garmcap parametric dress form, " + sidecar.name);
      calib::writeFormSidecar(dir / "form.json", sidecar);
      const std::string path = std::filesystem::absolute(dir / "form.json").lexically_normal();
      it = sizeForms.emplace(size, std::make_pair(path, calib::FormModel::load(path))).first;
    }
    return it->second;
  };
  nlohmann::json cases = nlohmann::json::array();
  // Pants are worn on legs: a form without a crotch (a torso form) gets the other types only.
  const bool legs = options.chart.empty() ? form.landmarks().crotch.has_value()
                                          : options.formKind == FormKind::kMannequin;
  std::vector<std::string> types;
  for (const auto& t : garmentTypeNames())
    if (legs || t != "pants")
      types.push_back(t);
  for (int i = 0; i < options.count; ++i) {
    char id[32];
    std::snprintf(id, sizeof id, "case_%03d", i);
    RandomSceneOptions so;
    so.size = options.size;
    so.hardFraction = options.hardFraction;
    so.type = types[static_cast<std::size_t>(i) % types.size()];
    so.chart = options.chart;
    const std::uint64_t caseSeed = options.seed * 1000003ULL + static_cast<std::uint64_t>(i);
    const calib::FormModel* caseForm = &form;
    std::string caseFormPath = formPath;
    if (!options.chart.empty()) {
      const auto& sizes = drafts::sizeChart(options.chart).sizes;
      so.chartSize = sizes[std::mt19937_64(caseSeed + 0x5173)() % sizes.size()];
      const auto& f = formOfSize(so.chartSize);
      caseFormPath = f.first;
      caseForm = &f.second;
    }
    Scene scene = randomScene(*caseForm, caseFormPath, caseSeed, so);
    const SceneRenderer renderer(*caseForm, std::move(scene));
    writeCase(renderer, outDir / id, options.images);
    const auto& g = renderer.scene().garment;
    nlohmann::json entry = {{"id", id},
                            {"dir", id},
                            {"type", g.type},
                            {"attributes", g.attributes},
                            {"hard", renderer.scene().hard}};
    if (!renderer.scene().chartSize.empty())
      entry["size"] = renderer.scene().chartSize;
    cases.push_back(std::move(entry));
    if (options.progress)
      options.progress(i, options.count, id);
  }
  nlohmann::json index = {{"format", "garmcap-rig"},
                          {"version", 1},
                          {"generator", "garmcap rig make (scene simulator, docs/simulator.md)"},
                          {"form", formPath},
                          {"width", options.size.width},
                          {"height", options.size.height},
                          {"seed", options.seed},
                          {"image_format", rigImageExtension(options.images.format)},
                          {"cases", cases}};
  if (options.images.format == RigImageFormat::kJpeg)
    index["jpeg_quality"] = options.images.jpegQuality;
  if (!options.chart.empty())
    index["chart"] = options.chart;
  drafts::writeJsonFile(outDir / "rig.json", index);
  return readRig(outDir);
}

}  // namespace garmcap::sim
