#pragma once
// Shop exports: catalog items in, file bytes out (Shopify product CSV, WooCommerce product CSV,
// Google Merchant Center TSV feed, size-guide HTML). Pure functions: no I/O, no catalog access,
// thread-safe. The daemon turns its catalog rows into ExportItem and serves the bytes.
//
// Units: every measurement is in cm (names as in the catalog: `bust_circ`, `waist_circ`,
// `garment_length`, ...). Column sets and their sources: docs/exports.md.

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace garmcap::daemon {

/// An export refused its input (an item without SKU, a bad base URL, ...). The message names
/// the item and the field.
class ExportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One size of the graded run of an item: the garment measurements of that size.
struct ExportSize {
  std::string label;                             // "S", "M", "38", ...
  std::map<std::string, double> measurementsCm;  // garment measurements of this size
};

/// One product image, published under `ShopOptions::publicBaseUrl` + "/" + `path`.
struct ExportImage {
  std::string path;  // relative, e.g. "images/SKU-123-product.jpg" (also its path in the ZIP)
  std::string alt;   // alt text; empty: the item's title
};

/// What the shop exports need to know about one catalog item.
struct ExportItem {
  std::string id;           // catalog id
  std::string sku;          // base SKU; variant SKUs are `sku + "-" + size label`
  std::string title;        // UTF-8, any characters
  std::string description;  // plain text written by staff (escaped into HTML)
  std::string type;         // top | dress | skirt | pants
  std::map<std::string, std::string> attributes;  // sleeve, skirt, color, material, ...
  std::optional<double> price;                    // in ShopOptions::currency
  std::vector<std::string> tags;
  bool published = true;                         // false: exported as draft
  std::map<std::string, double> measurementsCm;  // as captured (the item's own size)
  std::string sampleSize;           // label of the captured size within `sizes` (may be empty)
  std::vector<ExportSize> sizes;    // graded run, smallest first; empty: one "One size" variant
  std::vector<ExportImage> images;  // first one is the main product photo
};

struct ShopOptions {
  std::string
      publicBaseUrl;     // where the ZIP's files are published, e.g. "https://cdn.example/shop"
  std::string storeUrl;  // product page base for Merchant Center `link` (handle appended)
  std::string vendor = "GarmCap Station";
  std::string currency = "EUR";   // ISO 4217
  std::string sizeSystem = "EU";  // Merchant Center size_system
  std::string gender = "female";  // Merchant Center gender: male | female | unisex
  std::string ageGroup = "adult";
  bool legacyShopifyHeader = false;  // Handle / Variant SKU column set (pre-2024 exports)
};

/// Human name of a measurement for size guides and shop columns ("bust_circ" -> "Bust").
std::string measurementLabel(const std::string& name);

/// Shopify URL handle: lowercase ASCII letters, digits and dashes derived from the SKU.
std::string shopifyHandle(const ExportItem& item);

/// The size guide as an HTML table (sizes as rows, measurements in cm as columns), safe to put
/// into a shop description: every text is HTML-escaped.
std::string sizeGuideHtml(const ExportItem& item);

/// Full product description HTML: the staff text (escaped, paragraphs) and the size guide.
std::string descriptionHtml(const ExportItem& item);

/// Shopify product CSV: one product per item, one row per size variant (option "Size"),
/// further rows for extra images. RFC 4180 quoting, CRLF line ends, UTF-8 without BOM.
/// Throws ExportError for an item without SKU or title, or an empty publicBaseUrl when an item
/// has images.
std::string shopifyCsv(const std::vector<ExportItem>& items, const ShopOptions& options);

/// WooCommerce product CSV (built-in importer's columns): a `variable` parent per item and one
/// `variation` per size with `Attribute 1` = Size and `Meta: <measurement>_cm` columns.
std::string wooCommerceCsv(const std::vector<ExportItem>& items, const ShopOptions& options);

/// Google Merchant Center product feed (tab-separated): one row per size, grouped by
/// item_group_id = SKU, with size, size_system, gender, age_group, color and product_detail
/// "Measurements:<label>:<value> cm" entries.
std::string merchantTsv(const std::vector<ExportItem>& items, const ShopOptions& options);

/// One CSV field quoted per RFC 4180 when it holds a comma, quote, CR, LF or edge spaces.
std::string csvField(const std::string& value);

}  // namespace garmcap::daemon
