#include "garmcap/dsw/base_draft.h"

#include "garmcap/drafts/recipes.h"
#include "garmcap/dsw/grading.h"

namespace garmcap::dsw {
using drafts::Point2;

Expected<std::vector<drafts::DraftRegion>> baseBlock(const drafts::Measurements& body,
                                                     double fallbackSkirtLengthCm) {
  auto need = [&](const char* name) -> std::optional<double> { return body.find(name); };
  for (const char* name : {"bust_circ", "waist_circ", "hip_circ", "neck_back_to_waist_b",
                           "waist_to_hip_b", "arm_wrist_circ", "arm_shoulder_tip_to_wrist"}) {
    if (!need(name))
      return Error{std::string("base draft: the body has no ") + name};
  }
  const double b = *need("bust_circ"), h = *need("hip_circ"), wbl = *need("neck_back_to_waist_b");
  // Bunka estimates the armhole as about half the bust when it is not measured.
  const double hl = *need("waist_to_hip_b"), ah = body.find("armscye_circ").value_or(b / 2);
  const double wrist = *need("arm_wrist_circ"), arm = *need("arm_shoulder_tip_to_wrist");
  const double skirt = body.find("skirt_length").value_or(fallbackSkirtLengthCm);
  const double yBust = std::min(b / 12 + 13.7, 0.9 * wbl);
  std::vector<drafts::DraftRegion> out;
  out.push_back({"base_top",
                 {Point2(0, 0), Point2(b / 4, 0), Point2(b / 2, 0), Point2(b / 2, yBust),
                  Point2(b / 2, wbl), Point2(b / 4, wbl), Point2(0, wbl), Point2(0, yBust)}});
  out.push_back({"base_skirt",
                 {Point2(0, wbl), Point2(h / 4, wbl), Point2(h / 2, wbl), Point2(h / 2, wbl + hl),
                  Point2(h / 2, wbl + skirt), Point2(h / 4, wbl + skirt), Point2(0, wbl + skirt),
                  Point2(0, wbl + hl)}});
  const double x0 = b / 2 + 10, cap = ah / 4 + 2.5;
  out.push_back(
      {"base_sleeve",
       {Point2(x0 + ah / 2, 0), Point2(x0 + ah, cap), Point2(x0 + ah / 2 + wrist / 2, arm),
        Point2(x0 + ah / 2 - wrist / 2, arm), Point2(x0, cap)}});
  return out;
}

Expected<drafts::Pattern> gradeWithBaseDraft(const drafts::Pattern& source,
                                             const drafts::Measurements& target,
                                             CoordMethod method) {
  const double fallbackSkirt =
      source.design.count("skirt_length") ? source.design.at("skirt_length") : 60.0;
  auto from = baseBlock(source.measurements, fallbackSkirt);
  if (!from)
    return Error{"source body: " + from.error().message};
  auto to = baseBlock(target, fallbackSkirt);
  if (!to)
    return Error{"target body: " + to.error().message};
  drafts::Pattern src = source;
  for (auto& panel : src.panels) {
    if (panel.name.find("sleeve") != std::string::npos)
      panel.draftRegions = {"base_sleeve"};
    else if (panel.name.find("skirt") != std::string::npos)
      panel.draftRegions = {"base_skirt"};
    else
      panel.draftRegions = {"base_top", "base_skirt"};
  }
  auto enc = encodePattern(src, *from, method);
  if (!enc)
    return enc.error();
  drafts::Pattern targetPattern;
  bool hasRecipe = false;
  for (const auto& t : drafts::garmentTypes())
    hasRecipe = hasRecipe || t.name == source.type;
  if (hasRecipe) {
    auto draft = targetDraft(source, target);
    if (draft)
      targetPattern = std::move(draft).value();
  }
  if (targetPattern.type.empty()) {
    targetPattern.type = source.type;
    targetPattern.design = source.design;
    targetPattern.points = source.points;
    targetPattern.lines = source.lines;
  }
  targetPattern.measurements = target;
  targetPattern.regions = *to;
  auto decoded = decodePattern(*enc, targetPattern);
  if (!decoded)
    return decoded.error();
  drafts::Pattern graded = std::move(decoded).value();
  // The panels keep their own region names (the base regions are a grading aid only).
  for (std::size_t i = 0; i < graded.panels.size(); ++i)
    graded.panels[i].draftRegions = source.panels[i].draftRegions;
  return graded;
}

}  // namespace garmcap::dsw
