#pragma once
// Shop exports: catalog items in, file bytes out (Shopify product CSV, WooCommerce product CSV,
// Google Merchant Center TSV feed, size-guide HTML). Pure functions: no I/O, no catalog access,
// thread-safe. The daemon turns its catalog rows into ExportItem and serves the bytes.
//
// Units: every measurement is in cm (names as in the catalog: `bust_circ`, `waist_circ`,
// `garment_length`, ...). Column sets and their sources: docs/exports.md.

#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "garmcap/dsw/size_guide.h"

namespace garmcap::daemon {

/// An export refused its input (an item without SKU, a bad base URL, ...). The message names
/// the item and the field.
class ExportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One product image, published under `ShopOptions::publicBaseUrl` + "/" + `path`.
struct ExportImage {
  std::string path;  // relative, e.g. "images/SKU-123-product.jpg" (also its path in the ZIP)
  std::string alt;   // alt text; empty: the item's title
};

/// What the shop exports need to know about one catalog item: one piece, in one size.
struct ExportItem {
  std::string id;           // catalog id
  std::string sku;          // the piece's SKU; made-to-order sizes are `sku + "-" + size label`
  std::string title;        // UTF-8, any characters
  std::string description;  // plain text written by staff (escaped into HTML)
  std::string type;         // top | dress | skirt | pants
  std::map<std::string, std::string> attributes;  // sleeve, skirt, material, ...
  std::vector<std::string> colors;                // Google Merchant colour names, dominant first
  bool printed = false;         // a print (dots, stripes, florals), not a plain colour
  std::optional<double> price;  // in ShopOptions::currency; none: exported as a draft
  std::vector<std::string> tags;
  bool published = true;                         // false: exported as draft
  std::map<std::string, double> measurementsCm;  // as captured (the piece itself)
  std::optional<dsw::SizeGuide> sizeGuide;       // the piece's row and the graded run
  std::vector<ExportImage> images;               // first one is the main product photo
};

/// Merchant Center's accepted `size_system` values.
const std::vector<std::string>& merchantSizeSystems();

struct ShopOptions {
  std::string publicBaseUrl;              // where the ZIP's files are published (images under it)
  std::string storeUrl;                   // the shop's own address; product links are built on it
  std::string storePlatform = "shopify";  // whose product links: shopify | woocommerce
  std::string brand;                      // Merchant `brand`, Shopify `Vendor`
  std::string currency = "EUR";           // ISO 4217
  std::string sizeSystem;                 // Merchant size_system (merchantSizeSystems), "" none
  std::map<std::string, std::string> sizeLabels;  // chart size -> the shop's label ("55" -> "M")
  bool madeToOrder = false;       // also sell the graded run's other sizes, made to order
  bool allowLoopback = false;     // let links point at this machine (a shop on the same host)
  std::string gender = "female";  // Merchant Center gender: male | female | unisex
  std::string ageGroup = "adult";
  bool legacyShopifyHeader = false;  // Handle / Variant SKU column set (pre-2024 exports)
};

/// A shop file and what a person should know before importing it (items held back as drafts,
/// rows left out), each message naming the item.
struct ShopFile {
  std::string bytes;
  std::vector<std::string> warnings;
};

/// A title staff can keep: the dominant colour (or "Printed"), the cut and the type, e.g.
/// "Navy A-line skirt", "Printed short-sleeve top", "Black trousers". The one rule for a title
/// left empty: the API hands it to the web UI as `default_title`, the exports use it.
std::string defaultProductTitle(const ExportItem& item);

/// The same title from a catalog item's type and attributes ("color": "navy/white", dominant
/// first; "pattern": "print"; "sleeve"; "skirt").
std::string defaultProductTitle(const std::string& type,
                                const std::map<std::string, std::string>& attributes);

/// Shopify URL handle: lowercase ASCII letters, digits and dashes derived from the SKU.
std::string shopifyHandle(const ExportItem& item);

/// WooCommerce's product slug of the title, as WordPress derives it (lowercase, Latin accents
/// dropped, other characters to dashes).
std::string wooCommerceSlug(const ExportItem& item);

/// The page a shopper lands on: Shopify `store/products/<handle>`, WooCommerce
/// `store/product/<slug>/`. Throws ExportError on an empty or loopback store URL.
std::string productLink(const ExportItem& item, const ShopOptions& options);

/// The size guide as an HTML table (sizes as rows, measurements in cm as columns), safe to put
/// into a shop description: every text is HTML-escaped. Without made-to-order only the piece's
/// own row is shown (the other sizes are not for sale).
std::string sizeGuideHtml(const ExportItem& item, const ShopOptions& options);

/// Full product description HTML: the staff text (escaped, paragraphs) and the size guide.
std::string descriptionHtml(const ExportItem& item, const ShopOptions& options);

/// Shopify product CSV: one product per item. By default one variant, the piece in its own
/// size with tracked stock 1; with madeToOrder further untracked variants for the other sizes.
/// An item without price (or not published) is a draft. RFC 4180 quoting, CRLF line ends.
/// Throws ExportError for an item without SKU or title, or a missing/loopback image base URL.
ShopFile shopifyCsv(const std::vector<ExportItem>& items, const ShopOptions& options);

/// WooCommerce product CSV (built-in importer's columns): a `simple` product per item (stock
/// 1), or with madeToOrder a `variable` parent with the piece and the made-to-order sizes as
/// `variation`s (`Meta: <measurement>_cm` columns).
ShopFile wooCommerceCsv(const std::vector<ExportItem>& items, const ShopOptions& options);
/// Its `Meta: <measurement>_cm` columns: the measurement names of every variant of `items`.
std::set<std::string> wooCommerceMetaNames(const std::vector<ExportItem>& items,
                                           const ShopOptions& options);
/// The same file with the given meta columns (a file written in pages: the names of every
/// page, surveyed first). Throws ExportError for a measurement not among them.
ShopFile wooCommerceCsvWithColumns(const std::vector<ExportItem>& items, const ShopOptions& options,
                                   const std::set<std::string>& metaNames);

/// Google Merchant Center product feed (tab-separated): one row per variant, item_group_id =
/// SKU when there are several. Items without a price are left out with a warning (Merchant
/// refuses them). Throws ExportError without a brand or with a loopback store URL.
ShopFile merchantTsv(const std::vector<ExportItem>& items, const ShopOptions& options);

}  // namespace garmcap::daemon
