// Shop exports: CSV quoting, column sets, one variant per size, image URLs, ZIP archive.
#include "garmcap/daemon/export_shop.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "../exports/export_samples.h"
#include "csv_reader.h"
#include "garmcap/daemon/export_zip.h"

namespace garmcap::daemon {
namespace {

std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
  return garmcap::test::readCsvRecords(text, ',');
}

ShopOptions options() {
  ShopOptions o;
  o.publicBaseUrl = "https://cdn.shop.test/catalog/";
  o.storeUrl = "https://shop.test";
  return o;
}

size_t col(const std::vector<std::string>& header, const std::string& name) {
  auto it = std::find(header.begin(), header.end(), name);
  EXPECT_NE(it, header.end()) << name;
  return static_cast<size_t>(it - header.begin());
}

TEST(CsvField, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(csvField("plain"), "plain");
  EXPECT_EQ(csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csvField("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csvField(" padded"), "\" padded\"");
  EXPECT_EQ(csvField("Été ★"), "Été ★");
}

TEST(ShopifyCsv, OneProductPerItemOneVariantPerSize) {
  const auto items = exports_test::sampleItems();
  const auto rows = parseCsv(shopifyCsv(items, options()));
  const auto& h = rows[0];
  for (const auto& r : rows)
    ASSERT_EQ(r.size(), h.size());
  // Item a: 3 sizes (2 images fit in the variant rows); item b: one size, one image.
  ASSERT_EQ(rows.size(), 1u + 3u + 1u);
  EXPECT_EQ(rows[1][col(h, "Title")], items[0].title);
  EXPECT_EQ(rows[1][col(h, "URL handle")], "sk-1001");
  EXPECT_EQ(rows[2][col(h, "URL handle")], "sk-1001");
  EXPECT_EQ(rows[2][col(h, "Title")], "");
  EXPECT_EQ(rows[1][col(h, "Option1 name")], "Size");
  EXPECT_EQ(rows[1][col(h, "Option1 value")], "S");
  EXPECT_EQ(rows[3][col(h, "SKU")], "SK-1001-L");
  EXPECT_EQ(rows[1][col(h, "Price")], "59.90");
  EXPECT_EQ(rows[1][col(h, "Tags")], "linen, summer, 2026");
  EXPECT_EQ(rows[1][col(h, "Product image URL")],
            "https://cdn.shop.test/catalog/images/SK-1001-product.jpg");
  EXPECT_EQ(rows[2][col(h, "Image position")], "2");
  EXPECT_EQ(rows[3][col(h, "Product image URL")], "");
  const std::string desc = rows[1][col(h, "Description")];
  EXPECT_NE(desc.find("<th>Hip (cm)</th>"), std::string::npos) << desc;
  EXPECT_NE(desc.find("<td>101.5</td>"), std::string::npos);
  EXPECT_NE(desc.find("Lined, with pockets"), std::string::npos);
  // Item b: non-ASCII SKU gives an ASCII handle, a space in the image name is encoded.
  EXPECT_EQ(rows[4][col(h, "URL handle")], "tp-2002");
  EXPECT_EQ(rows[4][col(h, "Title")], "Bluse 'Grün' ★");
  EXPECT_EQ(rows[4][col(h, "Option1 value")], "One size");
  EXPECT_EQ(rows[4][col(h, "SKU")], "TP 2002/ü");
  EXPECT_EQ(rows[4][col(h, "Status")], "draft");
  EXPECT_EQ(rows[4][col(h, "Product image URL")],
            "https://cdn.shop.test/catalog/images/TP%202002-product.jpg");
}

TEST(ShopifyCsv, LegacyHeader) {
  auto o = options();
  o.legacyShopifyHeader = true;
  const auto rows = parseCsv(shopifyCsv(exports_test::sampleItems(), o));
  const auto& h = rows[0];
  EXPECT_EQ(h[0], "Handle");
  EXPECT_EQ(rows[2][col(h, "Variant SKU")], "SK-1001-M");
  EXPECT_EQ(rows[1][col(h, "Image Src")],
            "https://cdn.shop.test/catalog/images/SK-1001-product.jpg");
  EXPECT_NE(rows[1][col(h, "Body (HTML)")].find("size-guide"), std::string::npos);
}

TEST(ShopifyCsv, RefusesItemsShopsCannotTake) {
  auto items = exports_test::sampleItems();
  items[0].sku.clear();
  EXPECT_THROW(shopifyCsv(items, options()), ExportError);
  auto o = options();
  o.publicBaseUrl.clear();
  EXPECT_THROW(shopifyCsv(exports_test::sampleItems(), o), ExportError);
}

TEST(WooCommerceCsv, VariableParentAndVariations) {
  const auto rows = parseCsv(wooCommerceCsv(exports_test::sampleItems(), options()));
  const auto& h = rows[0];
  ASSERT_EQ(rows.size(), 1u + (1 + 3) + (1 + 1));
  EXPECT_EQ(rows[1][col(h, "Type")], "variable");
  EXPECT_EQ(rows[1][col(h, "Attribute 1 name")], "Size");
  EXPECT_EQ(rows[1][col(h, "Attribute 1 value(s)")], "S, M, L");
  EXPECT_EQ(rows[1][col(h, "Attribute 1 default")], "M");
  EXPECT_EQ(rows[1][col(h, "Images")],
            "https://cdn.shop.test/catalog/images/SK-1001-product.jpg, "
            "https://cdn.shop.test/catalog/images/SK-1001-cutout.png");
  EXPECT_EQ(rows[2][col(h, "Type")], "variation");
  EXPECT_EQ(rows[2][col(h, "Parent")], "SK-1001");
  EXPECT_EQ(rows[4][col(h, "SKU")], "SK-1001-L");
  EXPECT_EQ(rows[4][col(h, "Meta: hip_circ_cm")], "101.5");
  EXPECT_EQ(rows[4][col(h, "Meta: bust_circ_cm")], "");
  EXPECT_EQ(rows[6][col(h, "Meta: bust_circ_cm")], "94.0");
  EXPECT_EQ(rows[5][col(h, "Published")], "-1");
}

TEST(MerchantTsv, OneRowPerSizeWithApparelFields) {
  const std::string tsv = merchantTsv(exports_test::sampleItems(), options());
  std::vector<std::vector<std::string>> rows;
  size_t start = 0;
  while (start < tsv.size()) {
    size_t end = tsv.find('\n', start);
    std::string line = tsv.substr(start, end - start);
    std::vector<std::string> f;
    size_t s = 0;
    while (true) {
      size_t t = line.find('\t', s);
      f.push_back(line.substr(s, t == std::string::npos ? std::string::npos : t - s));
      if (t == std::string::npos)
        break;
      s = t + 1;
    }
    rows.push_back(f);
    start = end + 1;
  }
  const auto& h = rows[0];
  ASSERT_EQ(rows.size(), 1u + 3u + 1u);
  for (const auto& r : rows)
    ASSERT_EQ(r.size(), h.size());
  EXPECT_EQ(rows[2][col(h, "id")], "SK-1001-M");
  EXPECT_EQ(rows[2][col(h, "item_group_id")], "SK-1001");
  EXPECT_EQ(rows[2][col(h, "size")], "M");
  EXPECT_EQ(rows[2][col(h, "size_system")], "EU");
  EXPECT_EQ(rows[2][col(h, "gender")], "female");
  EXPECT_EQ(rows[2][col(h, "age_group")], "adult");
  EXPECT_EQ(rows[2][col(h, "color")], "blue");
  EXPECT_EQ(rows[2][col(h, "price")], "59.90 EUR");
  EXPECT_EQ(rows[2][col(h, "product_detail")],
            "Measurements:Hip:96.5 cm,Measurements:Skirt length:61.0 cm,"
            "Measurements:Waist:72.0 cm");
  // The description's line break must not split the row.
  EXPECT_EQ(rows[1][col(h, "description")], "Soft linen. Lined, with pockets; size M on the form.");
  EXPECT_EQ(rows[1][col(h, "link")], "https://shop.test/products/sk-1001");
}

TEST(StoreZip, UnzipReadsItBack) {
  const std::string bin(std::string("\x00\x01\xff\x89PNG", 7));
  const std::string zip =
      storeZip({{"shopify.csv", "a,b\r\n"}, {"images/Été.png", bin}, {"patterns/x.dxf", ""}});
  const auto dir =
      std::filesystem::temp_directory_path() / ("garmcap_zip_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "c.zip", std::ios::binary) << zip; }
  const std::string cmd = "cd '" + dir.string() + "' && unzip -q -o c.zip -d out 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream f(dir / "out" / "images" / "Été.png", std::ios::binary);
  std::string back((std::istreambuf_iterator<char>(f)), {});
  EXPECT_EQ(back, bin);
  EXPECT_EQ(std::filesystem::file_size(dir / "out" / "patterns" / "x.dxf"), 0u);
  EXPECT_EQ(std::system(("unzip -tq '" + (dir / "c.zip").string() + "' >/dev/null").c_str()), 0);
  std::filesystem::remove_all(dir);
}

TEST(StoreZip, RefusesBadPaths) {
  EXPECT_THROW(storeZip({{"../x", "a"}}), ExportError);
  EXPECT_THROW(storeZip({{"/etc/x", "a"}}), ExportError);
  EXPECT_THROW(storeZip({{"a", "1"}, {"a", "2"}}), ExportError);
  EXPECT_THROW(storeZip({{"a//b", "1"}}), ExportError);
}

}  // namespace
}  // namespace garmcap::daemon
