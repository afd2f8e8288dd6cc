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
  o.brand = "Atelier Test";
  o.sizeLabels = {{"M", "38"}, {"S", "36"}, {"L", "40"}};
  return o;
}

size_t col(const std::vector<std::string>& header, const std::string& name) {
  auto it = std::find(header.begin(), header.end(), name);
  EXPECT_NE(it, header.end()) << name;
  return static_cast<size_t>(it - header.begin());
}

std::vector<std::vector<std::string>> parseTsv(const std::string& tsv) {
  // Merchant's TSV has no quoting: split on tabs and LF only.
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
  return rows;
}

TEST(ShopifyCsv, ByDefaultOneVariantThePieceInItsOwnSizeWithStockOne) {
  const auto items = exports_test::sampleItems();
  const auto file = shopifyCsv(items, options());
  const auto rows = parseCsv(file.bytes);
  const auto& h = rows[0];
  for (const auto& r : rows)
    ASSERT_EQ(r.size(), h.size());
  // Item a: one variant, two images (two rows); item b: one variant, one image.
  ASSERT_EQ(rows.size(), 1u + 2u + 1u);
  EXPECT_EQ(rows[1][col(h, "Title")], items[0].title);
  EXPECT_EQ(rows[1][col(h, "URL handle")], "sk-1001");
  EXPECT_EQ(rows[2][col(h, "URL handle")], "sk-1001");
  EXPECT_EQ(rows[2][col(h, "SKU")], "");  // an image row, not a variant
  EXPECT_EQ(rows[1][col(h, "Option1 name")], "Size");
  EXPECT_EQ(rows[1][col(h, "Option1 value")], "38");  // chart size M, the shop's label
  EXPECT_EQ(rows[1][col(h, "SKU")], "SK-1001");
  EXPECT_EQ(rows[1][col(h, "Inventory tracker")], "shopify");
  EXPECT_EQ(rows[1][col(h, "Inventory quantity")], "1");
  EXPECT_EQ(rows[1][col(h, "Continue selling when out of stock")], "DENY");
  EXPECT_EQ(rows[1][col(h, "Price")], "59.90");
  EXPECT_EQ(rows[1][col(h, "Status")], "active");
  EXPECT_EQ(rows[1][col(h, "Vendor")], "Atelier Test");
  EXPECT_EQ(rows[1][col(h, "Color (product.metafields.shopify.color-pattern)")], "Navy");
  EXPECT_EQ(rows[1][col(h, "Tags")], "linen, summer, 2026");
  const std::string desc = rows[1][col(h, "Description")];
  EXPECT_NE(desc.find("<td>38</td><td>72.0</td><td>96.5</td><td>61.0</td>"), std::string::npos)
      << desc;
  EXPECT_EQ(desc.find("<td>36</td>"), std::string::npos) << "a size not for sale is shown";
  EXPECT_EQ(desc.find("taken flat"), std::string::npos);
  // Item b has no price: a draft, not published, and the file says so.
  EXPECT_EQ(rows[3][col(h, "URL handle")], "tp-2002");
  EXPECT_EQ(rows[3][col(h, "Option1 value")], "One size");
  EXPECT_EQ(rows[3][col(h, "SKU")], "TP 2002/ü");
  EXPECT_EQ(rows[3][col(h, "Status")], "draft");
  EXPECT_EQ(rows[3][col(h, "Published on online store")], "FALSE");
  EXPECT_EQ(rows[3][col(h, "Color (product.metafields.shopify.color-pattern)")], "print");
  EXPECT_EQ(rows[3][col(h, "Product image URL")],
            "https://cdn.shop.test/catalog/images/TP%202002-product.jpg");
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_NE(file.warnings[0].find("item 2 (TP 2002/ü): no price"), std::string::npos);
}

TEST(ShopifyCsv, MadeToOrderAddsTheOtherSizesUntracked) {
  auto o = options();
  o.madeToOrder = true;
  const auto rows = parseCsv(shopifyCsv(exports_test::sampleItems(), o).bytes);
  const auto& h = rows[0];
  ASSERT_EQ(rows.size(), 1u + 3u + 1u);
  EXPECT_EQ(rows[1][col(h, "Option1 value")], "36");
  EXPECT_EQ(rows[1][col(h, "SKU")], "SK-1001-36");
  EXPECT_EQ(rows[1][col(h, "Inventory tracker")], "");
  EXPECT_EQ(rows[1][col(h, "Continue selling when out of stock")], "CONTINUE");
  EXPECT_EQ(rows[2][col(h, "SKU")], "SK-1001");
  EXPECT_EQ(rows[2][col(h, "Inventory quantity")], "1");
  EXPECT_EQ(rows[3][col(h, "SKU")], "SK-1001-40");
  EXPECT_NE(rows[1][col(h, "Description")].find("<td>36</td><td>67.0</td>"), std::string::npos);
  // Two chart sizes on one label would make two variants the shop cannot tell apart.
  o.sizeLabels["L"] = "38";
  EXPECT_THROW(shopifyCsv(exports_test::sampleItems(), o), ExportError);
}

TEST(ShopifyCsv, LegacyHeader) {
  auto o = options();
  o.legacyShopifyHeader = true;
  const auto rows = parseCsv(shopifyCsv(exports_test::sampleItems(), o).bytes);
  const auto& h = rows[0];
  EXPECT_EQ(h[0], "Handle");
  EXPECT_EQ(rows[1][col(h, "Variant SKU")], "SK-1001");
  EXPECT_EQ(rows[1][col(h, "Variant Inventory Qty")], "1");
  EXPECT_EQ(rows[1][col(h, "Image Src")],
            "https://cdn.shop.test/catalog/images/SK-1001-product.jpg");
  EXPECT_NE(rows[1][col(h, "Body (HTML)")].find("size-guide"), std::string::npos);
}

TEST(ShopifyCsv, RefusesItemsShopsCannotTakeAndLoopbackLinks) {
  auto items = exports_test::sampleItems();
  items[0].sku.clear();
  EXPECT_THROW(shopifyCsv(items, options()), ExportError);
  auto o = options();
  o.publicBaseUrl.clear();
  EXPECT_THROW(shopifyCsv(exports_test::sampleItems(), o), ExportError);
  for (const std::string local :
       {"http://127.0.0.1:8080/api/export/files", "http://localhost/x", "http://[::1]:80/",
        "https://0.0.0.0/files", "http://user@127.0.0.5/"}) {
    o.publicBaseUrl = local;
    try {
      shopifyCsv(exports_test::sampleItems(), o);
      ADD_FAILURE() << local << " accepted";
    } catch (const ExportError& e) {
      EXPECT_NE(std::string(e.what()).find("public_base_url"), std::string::npos) << e.what();
    }
  }
  o.allowLoopback = true;
  EXPECT_NO_THROW(shopifyCsv(exports_test::sampleItems(), o));
  o.publicBaseUrl = "http://127.0.0.1.example.net/files";  // a real host that starts with 127.
  o.allowLoopback = false;
  EXPECT_NO_THROW(shopifyCsv(exports_test::sampleItems(), o));
}

TEST(WooCommerceCsv, SimpleProductWithStockOneOrVariableWhenMadeToOrder) {
  const auto rows = parseCsv(wooCommerceCsv(exports_test::sampleItems(), options()).bytes);
  const auto& h = rows[0];
  ASSERT_EQ(rows.size(), 1u + 1u + 1u);
  EXPECT_EQ(rows[1][col(h, "Type")], "simple");
  EXPECT_EQ(rows[1][col(h, "SKU")], "SK-1001");
  EXPECT_EQ(rows[1][col(h, "Stock")], "1");
  EXPECT_EQ(rows[1][col(h, "Regular price")], "59.90");
  EXPECT_EQ(rows[1][col(h, "Attribute 1 value(s)")], "38");
  EXPECT_EQ(rows[1][col(h, "Attribute 2 value(s)")], "Navy/White");
  EXPECT_EQ(rows[1][col(h, "Meta: hip_circ_cm")], "96.5");
  EXPECT_EQ(rows[1][col(h, "Images")],
            "https://cdn.shop.test/catalog/images/SK-1001-product.jpg, "
            "https://cdn.shop.test/catalog/images/SK-1001-cutout.png");
  EXPECT_EQ(rows[2][col(h, "Published")], "-1");  // no price: draft
  EXPECT_EQ(rows[2][col(h, "Meta: bust_circ_cm")], "94.0");

  auto o = options();
  o.madeToOrder = true;
  const auto mto = parseCsv(wooCommerceCsv(exports_test::sampleItems(), o).bytes);
  const auto& hm = mto[0];
  ASSERT_EQ(mto.size(), 1u + (1 + 3) + 1u);
  EXPECT_EQ(mto[1][col(hm, "Type")], "variable");
  EXPECT_EQ(mto[1][col(hm, "Attribute 1 value(s)")], "36, 38, 40");
  EXPECT_EQ(mto[1][col(hm, "Attribute 1 default")], "38");
  EXPECT_EQ(mto[3][col(hm, "SKU")], "SK-1001-38");
  EXPECT_EQ(mto[3][col(hm, "Stock")], "1");
  EXPECT_EQ(mto[4][col(hm, "SKU")], "SK-1001-40");
  EXPECT_EQ(mto[4][col(hm, "Stock")], "");
  EXPECT_EQ(mto[4][col(hm, "Backorders allowed?")], "1");
  EXPECT_EQ(mto[4][col(hm, "Meta: hip_circ_cm")], "101.5");
}

TEST(MerchantTsv, ThePieceWithColourBrandAndItsOwnLinks) {
  auto o = options();
  o.sizeSystem = "EU";
  const auto file = merchantTsv(exports_test::sampleItems(), o);
  const auto rows = parseTsv(file.bytes);
  const auto& h = rows[0];
  ASSERT_EQ(rows.size(), 1u + 1u);  // item b has no price: Merchant refuses it, so it is left out
  for (const auto& r : rows)
    ASSERT_EQ(r.size(), h.size());
  EXPECT_EQ(rows[1][col(h, "id")], "SK-1001");
  EXPECT_EQ(rows[1][col(h, "item_group_id")], "");
  EXPECT_EQ(rows[1][col(h, "size")], "38");
  EXPECT_EQ(rows[1][col(h, "size_system")], "EU");
  EXPECT_EQ(rows[1][col(h, "brand")], "Atelier Test");
  EXPECT_EQ(rows[1][col(h, "color")], "Navy/White");
  EXPECT_EQ(rows[1][col(h, "price")], "59.90 EUR");
  EXPECT_EQ(rows[1][col(h, "product_detail")],
            "Measurements:Hip:96.5 cm,Measurements:Skirt length:61.0 cm,"
            "Measurements:Waist:72.0 cm");
  EXPECT_EQ(rows[1][col(h, "description")], "Soft linen. Lined, with pockets; size M on the form.");
  EXPECT_EQ(rows[1][col(h, "link")], "https://shop.test/products/sk-1001");
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_NE(file.warnings[0].find("no price"), std::string::npos);

  o.storePlatform = "woocommerce";
  o.madeToOrder = true;
  const auto mto = parseTsv(merchantTsv(exports_test::sampleItems(), o).bytes);
  ASSERT_EQ(mto.size(), 1u + 3u);
  EXPECT_EQ(mto[1][col(h, "item_group_id")], "SK-1001");
  EXPECT_EQ(mto[1][col(h, "link")], "https://shop.test/product/linen-skirt-ete-blue/");

  o.sizeSystem = "KR";  // not one of Merchant's
  EXPECT_THROW(merchantTsv(exports_test::sampleItems(), o), ExportError);
  o.sizeSystem = "";
  o.brand.clear();
  EXPECT_THROW(merchantTsv(exports_test::sampleItems(), o), ExportError);
  o.brand = "B";
  o.storeUrl = "http://localhost:8080";
  EXPECT_THROW(merchantTsv(exports_test::sampleItems(), o), ExportError);
}

TEST(ProductTitle, FromColourCutAndType) {
  auto items = exports_test::sampleItems();
  EXPECT_EQ(defaultProductTitle(items[0]), "Navy A-line skirt");
  EXPECT_EQ(defaultProductTitle(items[1]), "Printed short-sleeve top");
  ExportItem p;
  p.type = "pants";
  EXPECT_EQ(defaultProductTitle(p), "Trousers");
  p.colors = {"Black"};
  EXPECT_EQ(defaultProductTitle(p), "Black trousers");
}

TEST(ProductTitle, FromStoredAttributesAsTheApiServesIt) {
  using Attrs = std::map<std::string, std::string>;
  EXPECT_EQ(defaultProductTitle("skirt", Attrs{{"color", "Navy/White"}, {"skirt", "a_line"}}),
            "Navy A-line skirt");
  EXPECT_EQ(defaultProductTitle("top",
                                Attrs{{"color", "Red"}, {"pattern", "print"}, {"sleeve", "short"}}),
            "Printed short-sleeve top");
  EXPECT_EQ(defaultProductTitle("dress", Attrs{{"sleeve", "none"}}), "Sleeveless dress");
  EXPECT_EQ(defaultProductTitle("skirt", Attrs{{"skirt", "h_line"}, {"color", "Light blue"}}),
            "Light blue straight skirt");
  EXPECT_EQ(defaultProductTitle("", Attrs{}), "Garment");
  // The export's rule and the API's agree on the same piece.
  ExportItem e;
  e.type = "skirt";
  e.attributes = {{"skirt", "a_line"}};
  e.colors = {"Navy", "White"};
  EXPECT_EQ(defaultProductTitle(e),
            defaultProductTitle("skirt", Attrs{{"color", "Navy/White"}, {"skirt", "a_line"}}));
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
