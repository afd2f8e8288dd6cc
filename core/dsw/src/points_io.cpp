#include "garmcap/dsw/points_io.h"

#include <cmath>

#include "garmcap/drafts/file_io.h"

namespace garmcap::dsw {

Points pointsFromJson(const nlohmann::json& root, const std::string& key, const std::string& what) {
  if (!root.is_object())
    throw drafts::ParseError(what + ": expected a JSON object with field '" + key + "'");
  for (const auto& [name, value] : root.items()) {
    (void)value;
    if (name != key)
      throw drafts::ParseError(what + ": unknown field '" + name + "' (expected only '" + key +
                               "')");
  }
  const nlohmann::json& list = drafts::requireField(root, key, what);
  if (!list.is_array())
    throw drafts::ParseError(what + ": field '" + key + "' must be an array of [x, y]");
  Points out(static_cast<Eigen::Index>(list.size()), 2);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = what + ": " + key + "[" + std::to_string(i) + "]";
    const auto& p = list[i];
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw drafts::ParseError(where + ": expected [x, y] with two numbers");
    const double x = p[0].get<double>(), y = p[1].get<double>();
    if (!std::isfinite(x) || !std::isfinite(y))
      throw drafts::ParseError(where + ": coordinates must be finite");
    out(static_cast<Eigen::Index>(i), 0) = x;
    out(static_cast<Eigen::Index>(i), 1) = y;
  }
  return out;
}

Points readPointsFile(const std::filesystem::path& path, const std::string& key) {
  return pointsFromJson(drafts::readJsonFile(path), key, path.string());
}

nlohmann::json matrixToJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      row.push_back(m(i, j));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace garmcap::dsw
