// Writes the sample exports and what they must contain (truth.json) into a folder, for the
// consumer checks in check_exports.mjs (independent parsers from npm read them back).
//   write_export_samples OUT_DIR
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "export_samples.h"

using namespace garmcap;

namespace {
void write(const std::filesystem::path& p, const std::string& data) {
  std::ofstream f(p, std::ios::binary);
  f << data;
  if (!f)
    throw std::runtime_error("cannot write " + p.string());
}

nlohmann::json mm(const drafts::Point2& p) {
  return {p.x() * 10.0, -p.y() * 10.0};
}

nlohmann::json pieces(const drafts::Pattern& pat, const std::string& size) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& p : pat.panels) {
    nlohmann::json outline = nlohmann::json::array(), notches = nlohmann::json::array();
    for (const auto& q : p.outline)
      outline.push_back(mm(q));
    for (const auto& n : p.notches)
      notches.push_back(mm(n.position));
    out[p.name + "_" + size] = {
        {"piece", p.name},        {"size", size},
        {"quantity", p.cutCount}, {"outline", outline},
        {"notches", notches},     {"grainline", {mm(p.grainline.start), mm(p.grainline.end)}}};
  }
  return out;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_export_samples OUT_DIR\n");
    return 2;
  }
  try {
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    daemon::ShopOptions o;
    o.publicBaseUrl = "https://cdn.shop.test/catalog";
    o.storeUrl = "https://shop.test";
    o.brand = "Atelier Test";
    o.sizeSystem = "EU";
    o.sizeLabels = {{"S", "36"}, {"M", "38"}, {"L", "40"}};
    const auto items = exports_test::sampleItems();
    write(dir / "shopify.csv", daemon::shopifyCsv(items, o).bytes);
    write(dir / "woocommerce.csv", daemon::wooCommerceCsv(items, o).bytes);
    write(dir / "merchant.tsv", daemon::merchantTsv(items, o).bytes);
    o.legacyShopifyHeader = true;
    write(dir / "shopify_legacy.csv", daemon::shopifyCsv(items, o).bytes);
    o.legacyShopifyHeader = false;
    o.madeToOrder = true;
    write(dir / "shopify_mto.csv", daemon::shopifyCsv(items, o).bytes);
    write(dir / "woocommerce_mto.csv", daemon::wooCommerceCsv(items, o).bytes);
    o.storePlatform = "woocommerce";
    write(dir / "merchant_mto.tsv", daemon::merchantTsv(items, o).bytes);

    const auto run = exports_test::skirtRun();
    write(dir / "skirt_M.dxf", drafts::patternDxf(run.patterns[1], {run.style, "M"}));
    write(dir / "graded.dxf", drafts::gradedDxf(run));
    write(dir / "graded.rul", drafts::gradeRuleTable(run));

    nlohmann::json truth;
    truth["base_url"] = o.publicBaseUrl;
    truth["store_url"] = o.storeUrl;
    nlohmann::json its = nlohmann::json::array();
    // What each file must say, from the sample items themselves (not from the writers).
    for (const auto& it : items) {
      auto label = [&](const std::string& s) {
        return o.sizeLabels.count(s) ? o.sizeLabels.at(s) : s;
      };
      nlohmann::json piece, others = nlohmann::json::array();
      if (it.sizeGuide) {
        piece = {{"label", label(it.sizeGuide->itemSize())},
                 {"measurements", it.sizeGuide->item().garmentCm}};
        for (std::size_t i = 0; i < it.sizeGuide->rows.size(); ++i)
          if (i != it.sizeGuide->itemRow)
            others.push_back({{"label", label(it.sizeGuide->rows[i].size)},
                              {"measurements", it.sizeGuide->rows[i].garmentCm}});
      } else {
        piece = {{"label", "One size"}, {"measurements", it.measurementsCm}};
      }
      nlohmann::json images = nlohmann::json::array();
      for (const auto& im : it.images)
        images.push_back(im.path);
      std::string color;
      for (const auto& c : it.colors)
        color += (color.empty() ? "" : "/") + c;
      its.push_back({{"sku", it.sku},
                     {"title", it.title},
                     {"description", it.description},
                     {"price", it.price ? nlohmann::json(*it.price) : nlohmann::json(nullptr)},
                     {"tags", it.tags},
                     {"piece", piece},
                     {"made_to_order", others},
                     {"images", images},
                     {"color", color},
                     {"printed", it.printed}});
    }
    truth["brand"] = o.brand;
    truth["size_system"] = o.sizeSystem;
    truth["items"] = its;
    truth["single"] = pieces(run.patterns[1], "M");
    nlohmann::json graded = nlohmann::json::object();
    for (size_t s = 0; s < run.sizes.size(); ++s)
      graded.update(pieces(run.patterns[s], run.sizes[s]));
    truth["graded"] = graded;
    truth["sizes"] = run.sizes;
    truth["sample_size"] = run.sampleSize;
    truth["pieces"] = {"skirt_front", "skirt_back"};
    write(dir / "truth.json", truth.dump(1));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_export_samples: %s\n", e.what());
    return 1;
  }
  return 0;
}
