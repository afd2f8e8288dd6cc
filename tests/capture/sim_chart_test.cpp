// Garments drafted for the sizes of the built-in charts, worn on the parametric form of the
// same size (what `garmcap rig make --chart` renders): every size of every chart, every type and
// attribute, is drafted and fits (checkGarmentFits), so a chart rig never fails on a size.

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "garmcap/calib/form_model.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/sim/form_generator.h"
#include "garmcap/sim/scene.h"

namespace garmcap::sim {
namespace {

TEST(SimChart, EveryChartSizeGarmentFitsTheFormOfItsSize) {
  using Attrs = std::map<std::string, std::string>;
  const std::vector<std::pair<std::string, Attrs>> garments = {
      {"top", {{"sleeve", "none"}}},
      {"top", {{"sleeve", "short"}}},
      {"top", {{"sleeve", "long"}}},
      {"dress", {{"sleeve", "none"}, {"skirt", "a_line"}}},
      {"dress", {{"sleeve", "short"}, {"skirt", "h_line"}}},
      {"dress", {{"sleeve", "long"}, {"skirt", "a_line"}}},
      {"skirt", {{"skirt", "a_line"}}},
      {"skirt", {{"skirt", "h_line"}}},
      {"pants", {}}};
  const cv::Size small(300, 400);
  for (const auto& chart : drafts::sizeCharts()) {
    for (std::size_t i = 0; i < chart.sizes.size(); ++i) {
      const sim::ParametricForm pf(chart.bodies[i]);
      calib::FormSidecar sidecar = pf.sidecar("form.obj");
      const calib::FormModel form(pf.mesh(), sidecar);
      const calib::FormView view(form, fitPose(form, small, 0.05), small);
      for (const auto& [type, attrs] : garments) {
        SCOPED_TRACE(chart.name + " " + chart.sizes[i] + " " + type + " " +
                     (attrs.count("sleeve") ? attrs.at("sleeve") : "") + " " +
                     (attrs.count("skirt") ? attrs.at("skirt") : ""));
        sim::GarmentSpec g;
        g.type = type;
        g.attributes = attrs;
        try {
          g.measurements = draftedGarment(g, chart.bodies[i], view);
          sim::checkGarmentFits(g, view);
        } catch (const std::exception& e) {
          ADD_FAILURE() << e.what();
        }
      }
    }
  }
}

}  // namespace
}  // namespace garmcap::sim
