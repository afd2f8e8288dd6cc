// Tape corrections: the fit rules are in the header; here is why each step is as it is.

#include "garmcap/pipeline/measurement_correction.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace garmcap::pipeline {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

struct Line {
  double scale = 1, offset = 0;
};

double medianOffset(const std::vector<TapePair>& p) {
  std::vector<double> d;
  d.reserve(p.size());
  for (const auto& x : p)
    d.push_back(x.tapeCm - x.measuredCm);
  return median(std::move(d));
}

// Ordinary least squares of tape on measured; nullopt when the measured values do not vary
// (a slope of garments all of one size is undefined).
std::optional<Line> leastSquares(const std::vector<TapePair>& p) {
  const double n = static_cast<double>(p.size());
  double mx = 0, my = 0;
  for (const auto& x : p) {
    mx += x.measuredCm;
    my += x.tapeCm;
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (const auto& x : p) {
    sxx += (x.measuredCm - mx) * (x.measuredCm - mx);
    sxy += (x.measuredCm - mx) * (x.tapeCm - my);
  }
  if (!(sxx > 1e-9 * n))
    return std::nullopt;
  Line l;
  l.scale = sxy / sxx;
  l.offset = my - l.scale * mx;
  return l;
}

// Leave-one-out residuals of a fitting rule: pair i predicted by the rule fitted on the others.
// A fit that fails without the pair (too few distinct values left) counts that pair at its raw
// error, so a fragile rule is not flattered.
template <class Fit>
std::pair<double, double> looResiduals(const std::vector<TapePair>& p, Fit fit) {
  double sum = 0, max = 0;
  std::vector<TapePair> rest;
  for (std::size_t i = 0; i < p.size(); ++i) {
    rest.clear();
    for (std::size_t j = 0; j < p.size(); ++j)
      if (j != i)
        rest.push_back(p[j]);
    const std::optional<Line> l = fit(rest);
    const double predicted = l ? l->scale * p[i].measuredCm + l->offset : p[i].measuredCm;
    const double e = std::abs(p[i].tapeCm - predicted);
    sum += e;
    max = std::max(max, e);
  }
  return {sum / static_cast<double>(p.size()), max};
}

std::optional<Line> offsetFit(const std::vector<TapePair>& p) {
  if (p.empty())
    return std::nullopt;
  return Line{1, medianOffset(p)};
}

std::optional<Line> scaleFit(const std::vector<TapePair>& p) {
  if (p.size() < 2)
    return std::nullopt;
  auto l = leastSquares(p);
  if (!l || l->scale < kMinPlausibleScale || l->scale > kMaxPlausibleScale)
    return offsetFit(p);  // the same fallback as the full fit, so LOO judges the real rule
  return l;
}

// Two-sided 5 % critical value of Student's t with `df` degrees of freedom (df >= 1): the table
// to 30, then the Cornish-Fisher expansion about the normal's 1.96 (within 0.001 beyond 30).
double tCritical95(int df) {
  static constexpr double kTable[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306,
                                      2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120,
                                      2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
                                      2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (df <= 30)
    return kTable[std::max(df, 1) - 1];
  const double z = 1.959964, v = df;
  return z + (z * z * z + z) / (4 * v) +
         (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / (96 * v * v);
}

// Upper 5 % point of F(2, m): for two numerator degrees of freedom the tail is closed-form,
// P(F > f) = (1 + 2 f / m)^(-m / 2).
double fCritical95TwoParams(int m) {
  return 0.5 * m * (std::pow(0.05, -2.0 / m) - 1);
}

// Whether the pairs' data reject "no correction needed" at the 5 % level. An offset: Student's t
// on the differences tape - measured (is their mean bias distinguishable from zero given their
// spread?). A scale and offset: the F test of the fitted line against the identity (both
// parameters at once). A correction fitted on a handful of garments whose bias is small against
// its standard error is mostly their noise; the leave-one-out gain alone does not show that (it
// is itself an estimate from the same few pairs, positive about half the time with no bias).
bool significantAgainstNone(const std::vector<TapePair>& p, const Correction& c) {
  const int n = static_cast<int>(p.size());
  if (c.kind == CorrectionKind::kOffset) {
    double mean = 0;
    for (const auto& x : p)
      mean += x.tapeCm - x.measuredCm;
    mean /= n;
    double ss = 0;
    for (const auto& x : p)
      ss += (x.tapeCm - x.measuredCm - mean) * (x.tapeCm - x.measuredCm - mean);
    const double se = std::sqrt(ss / (n - 1) / n);
    return std::abs(mean) > tCritical95(n - 1) * se;
  }
  double rawSs = 0, rss = 0;
  for (const auto& x : p) {
    const double e = x.tapeCm - c.apply(x.measuredCm);
    rawSs += (x.tapeCm - x.measuredCm) * (x.tapeCm - x.measuredCm);
    rss += e * e;
  }
  return (rawSs - rss) / 2 > fCritical95TwoParams(n - 2) * rss / (n - 2);
}

}  // namespace

const char* toString(CorrectionKind kind) {
  return kind == CorrectionKind::kScaleOffset ? "scale_offset" : "offset";
}

std::optional<Correction> fitCorrection(const std::vector<TapePair>& all) {
  std::vector<TapePair> p;
  for (const auto& x : all)
    if (std::isfinite(x.measuredCm) && std::isfinite(x.tapeCm))
      p.push_back(x);
  if (static_cast<int>(p.size()) < kMinPairsForOffset)
    return std::nullopt;
  Correction c;
  c.n = static_cast<int>(p.size());
  for (const auto& x : p)
    c.rawMeanCm += std::abs(x.tapeCm - x.measuredCm);
  c.rawMeanCm /= static_cast<double>(p.size());

  c.offsetCm = medianOffset(p);
  std::tie(c.looMeanCm, c.looMaxCm) = looResiduals(p, offsetFit);
  // The same test once more against no correction at all: where the pipeline's errors on this
  // shop's garments have no bias (or one smaller than their spread), an offset or slope fitted
  // on a few of them moves every later reading by their noise.
  // And the bias (or line) must be significant at the 5 % level (significantAgainstNone).
  const auto judged = [&p](Correction& r) -> Correction& {
    r.significant = significantAgainstNone(p, r);
    r.helps = r.looMeanCm < r.rawMeanCm && r.significant;
    return r;
  };
  if (c.n < kMinPairsForScale)
    return judged(c);
  const auto line = leastSquares(p);
  if (!line || line->scale < kMinPlausibleScale || line->scale > kMaxPlausibleScale)
    return judged(c);
  // Six garments fit two parameters, but barely: a slope that does not predict the held-out
  // garments better than the offset does is noise, and the simpler correction is kept.
  const auto [looMean, looMax] = looResiduals(p, scaleFit);
  if (!(looMean < c.looMeanCm))
    return judged(c);
  c.kind = CorrectionKind::kScaleOffset;
  c.scale = line->scale;
  c.offsetCm = line->offset;
  c.looMeanCm = looMean;
  c.looMaxCm = looMax;
  return judged(c);
}

CorrectionTable fitCorrections(const std::vector<TapeRecord>& records) {
  std::map<CorrectionKey, std::vector<TapePair>> byKey;
  for (const auto& r : records)
    byKey[{r.type, r.name}].push_back({r.measuredCm, r.tapeCm});
  CorrectionTable t;
  for (const auto& [key, pairs] : byKey) {
    t.pairs[key] = static_cast<int>(pairs.size());
    if (auto c = fitCorrection(pairs))
      t.corrections[key] = *c;
  }
  return t;
}

namespace {
double round3(double v) {
  return std::round(v * 1000) / 1000;
}
}  // namespace

nlohmann::json correctionTableJson(const CorrectionTable& table) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [key, n] : table.pairs) {
    nlohmann::json row = {{"type", key.first}, {"measurement", key.second}, {"n", n}};
    const auto it = table.corrections.find(key);
    if (it == table.corrections.end()) {
      row["kind"] = "none";
      row["needs"] = kMinPairsForOffset - n;
    } else {
      const Correction& c = it->second;
      row["kind"] = c.helps ? toString(c.kind) : "none";
      if (!c.helps)
        row["reason"] = c.looMeanCm < c.rawMeanCm ? "not_significant" : "no_gain";
      row["offset_cm"] = round3(c.offsetCm);
      row["scale"] = round3(c.scale);
      row["residual_cm"] = round3(c.looMeanCm);
      row["residual_max_cm"] = round3(c.looMaxCm);
      row["raw_error_cm"] = round3(c.rawMeanCm);
    }
    out.push_back(row);
  }
  return out;
}

std::vector<std::string> applyCorrections(const CorrectionTable& table, const std::string& type,
                                          std::map<std::string, double>& measurements,
                                          nlohmann::json& result) {
  std::vector<std::string> applied;
  nlohmann::json corrections = nlohmann::json::object();
  for (auto& [name, value] : measurements) {
    const auto it = table.corrections.find({type, name});
    if (it == table.corrections.end())
      continue;
    const Correction& c = it->second;
    if (!c.helps)
      continue;
    const double corrected = c.apply(value);
    if (!(std::isfinite(corrected) && corrected > 0)) {
      if (result.is_object())
        result["warnings"].push_back("tape correction of " + name + " left out: it would make " +
                                     std::to_string(value) + " cm not positive");
      continue;
    }
    corrections[name] = {{"kind", toString(c.kind)},           {"offset_cm", round3(c.offsetCm)},
                         {"scale", round3(c.scale)},           {"n", c.n},
                         {"residual_cm", round3(c.looMeanCm)}, {"raw_cm", value}};
    value = corrected;
    applied.push_back(name);
    if (result.is_object())
      result["measurements"][name] = corrected;
  }
  if (result.is_object() && !applied.empty())
    result["corrections"] = corrections;
  return applied;
}

std::optional<double> rawMeasurement(const nlohmann::json& result, const std::string& name) {
  if (!result.is_object())
    return std::nullopt;
  const auto c = result.find("corrections");
  if (c != result.end() && c->is_object()) {
    const auto e = c->find(name);
    if (e != c->end() && e->is_object() && e->contains("raw_cm") && (*e)["raw_cm"].is_number())
      return (*e)["raw_cm"].get<double>();
  }
  const auto m = result.find("measurements");
  if (m != result.end() && m->is_object()) {
    const auto v = m->find(name);
    if (v != m->end() && v->is_number())
      return v->get<double>();
  }
  return std::nullopt;
}

}  // namespace garmcap::pipeline
