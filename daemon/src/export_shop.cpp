#include "garmcap/daemon/export_shop.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "garmcap/drafts/xml_escape.h"
#include "garmcap/dsw/csv.h"

namespace garmcap::daemon {
namespace {

using dsw::csvField;
using dsw::measurementLabel;

// One decimal, halves rounded away from zero (58.25 -> 58.3) as people and spreadsheets do;
// printf alone rounds exact binary halves to even.
std::string formatCm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", std::round(v * 10.0) / 10.0);
  return buf;
}

std::string formatPrice(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", std::round(v * 100.0) / 100.0);
  return buf;
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i) {
    if (i)
      out += sep;
    out += parts[i];
  }
  return out;
}

std::string who(const ExportItem& item) {
  return "item " + (item.id.empty() ? std::string("(no id)") : item.id) +
         (item.sku.empty() ? std::string() : " (" + item.sku + ")");
}

// The host of an http(s) URL, lowercased, without port or brackets.
std::string urlHost(const std::string& url) {
  const auto scheme = url.find("://");
  std::string rest = scheme == std::string::npos ? url : url.substr(scheme + 3);
  rest = rest.substr(0, rest.find_first_of("/?#"));
  if (const auto at = rest.rfind('@'); at != std::string::npos)
    rest = rest.substr(at + 1);
  std::string host;
  if (!rest.empty() && rest.front() == '[')
    host = rest.substr(1, rest.find(']') - 1);
  else
    host = rest.substr(0, rest.find(':'));
  for (char& c : host)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return host;
}

// Loopback and unspecified addresses: a link there works on this machine only, so a shop that
// imports it shows broken images and dead product links.
bool isLoopbackHost(const std::string& host) {
  const auto dottedDigits = [](const std::string& h) {
    return !h.empty() && std::all_of(h.begin(), h.end(),
                                     [](unsigned char c) { return std::isdigit(c) || c == '.'; });
  };
  const std::string v4 = host.rfind("::ffff:", 0) == 0 ? host.substr(7) : host;
  return host == "localhost" || host.ends_with(".localhost") || host == "::1" || host == "::" ||
         (dottedDigits(v4) && (v4.rfind("127.", 0) == 0 || v4 == "0.0.0.0"));
}

void checkPublicUrl(const std::string& url, const std::string& option, const ShopOptions& options) {
  if (url.empty())
    throw ExportError("export option '" + option + "' is empty; set it in the [shop] section");
  if (url.rfind("http://", 0) != 0 && url.rfind("https://", 0) != 0)
    throw ExportError("export option '" + option + "' must start with http:// or https://, got '" +
                      url + "'");
  if (!options.allowLoopback && isLoopbackHost(urlHost(url)))
    throw ExportError("export option '" + option + "' is '" + url +
                      "', an address of this machine that no shop can reach; set the shop's "
                      "public address, or [shop] allow_loopback = true for a shop on this host");
}

void checkOptions(const ShopOptions& options) {
  if (!options.sizeSystem.empty()) {
    const auto& ok = merchantSizeSystems();
    if (std::find(ok.begin(), ok.end(), options.sizeSystem) == ok.end())
      throw ExportError("export option 'size_system' is '" + options.sizeSystem +
                        "'; Merchant Center accepts " + join(ok, ", ") +
                        " (or none for a chart that is none of them)");
  }
  if (options.storePlatform != "shopify" && options.storePlatform != "woocommerce")
    throw ExportError("export option 'store_platform' must be shopify or woocommerce, got '" +
                      options.storePlatform + "'");
}

void checkItem(const ExportItem& item, const ShopOptions& options) {
  if (item.sku.empty())
    throw ExportError(who(item) + ": field 'sku' is empty; a shop needs a SKU");
  if (item.title.empty())
    throw ExportError(who(item) + ": field 'title' is empty");
  if (!item.images.empty()) {
    try {
      checkPublicUrl(options.publicBaseUrl, "public_base_url", options);
    } catch (const ExportError& e) {
      throw ExportError(who(item) +
                        " has images, and shops fetch them from public URLs: " + e.what());
    }
  }
}

// What a shop sells of an item: the piece itself, and with made-to-order the graded run's
// other sizes.
struct Variant {
  std::string label;
  std::string sku;
  bool piece = false;  // the one garment on hand (stock 1); else made to order
  std::map<std::string, double> measurementsCm;
};

std::string shopLabel(const ShopOptions& options, const std::string& chartSize) {
  const auto it = options.sizeLabels.find(chartSize);
  return it == options.sizeLabels.end() ? chartSize : it->second;
}

std::string skuSuffix(const std::string& label) {
  std::string out;
  for (unsigned char c : label)
    out += std::isalnum(c) ? static_cast<char>(c) : '-';
  return out;
}

std::vector<Variant> variants(const ExportItem& item, const ShopOptions& options) {
  std::vector<Variant> out;
  if (!item.sizeGuide) {
    out.push_back({"One size", item.sku, true, item.measurementsCm});
    return out;
  }
  const dsw::SizeGuide& g = *item.sizeGuide;
  out.push_back({shopLabel(options, g.itemSize()), item.sku, true, g.item().garmentCm});
  if (!options.madeToOrder)
    return out;
  std::set<std::string> labels = {out.front().label};
  for (std::size_t i = 0; i < g.rows.size(); ++i) {
    if (i == g.itemRow)
      continue;
    const std::string label = shopLabel(options, g.rows[i].size);
    if (!labels.insert(label).second)
      throw ExportError(who(item) + ": two sizes of chart " + g.chart + " get the shop label '" +
                        label + "'; give each size its own label in [shop] size_labels");
    out.push_back({label, item.sku + "-" + skuSuffix(label), false, g.rows[i].garmentCm});
  }
  std::stable_sort(out.begin(), out.end(), [&](const Variant& a, const Variant& b) {
    auto rank = [&](const Variant& v) {
      for (std::size_t i = 0; i < g.rows.size(); ++i)
        if (shopLabel(options, g.rows[i].size) == v.label)
          return i;
      return g.rows.size();
    };
    return rank(a) < rank(b);
  });
  return out;
}

// A product without a price cannot be sold: it goes to the shop as a draft for a person to
// price, never as an active listing.
bool sellable(const ExportItem& item) {
  return item.published && item.price.has_value();
}

void noteDraft(const ExportItem& item, std::vector<std::string>& warnings) {
  if (!item.price)
    warnings.push_back(who(item) + ": no price; exported as a draft, set a price in the shop");
  else if (!item.published)
    warnings.push_back(who(item) + ": held back by staff; exported as a draft");
}

// Merchant's `color`: up to three names joined by '/', dominant first.
std::string colorText(const ExportItem& item) {
  std::vector<std::string> names;
  for (const auto& c : item.colors)
    if (!c.empty() && names.size() < 3)
      names.push_back(c);
  if (names.empty()) {
    const auto it = item.attributes.find("color");
    if (it != item.attributes.end())
      names.push_back(it->second);
  }
  return join(names, "/");
}

class CsvWriter {
 public:
  explicit CsvWriter(char sep, bool quoteAware) : sep_(sep), quoteAware_(quoteAware) {}
  void row(const std::vector<std::string>& fields) {
    for (size_t i = 0; i < fields.size(); ++i) {
      if (i)
        out_ += sep_;
      out_ += quoteAware_ ? csvField(fields[i]) : tsvField(fields[i]);
    }
    out_ += quoteAware_ ? "\r\n" : "\n";
  }
  std::string str() && { return std::move(out_); }

 private:
  // Merchant Center TSV has no quoting: a tab or line break inside a value would split it,
  // so they become spaces.
  static std::string tsvField(const std::string& v) {
    std::string out = v;
    for (char& c : out)
      if (c == '\t' || c == '\n' || c == '\r')
        c = ' ';
    return out;
  }
  char sep_;
  bool quoteAware_;
  std::string out_;
};

// A row as column name -> value, written in header order; a name not in the header is a bug.
using Row = std::map<std::string, std::string>;

std::vector<std::string> ordered(const std::vector<std::string>& header, const Row& row) {
  std::vector<std::string> out(header.size());
  std::set<std::string> used;
  for (size_t i = 0; i < header.size(); ++i) {
    auto it = row.find(header[i]);
    if (it != row.end()) {
      out[i] = it->second;
      used.insert(header[i]);
    }
  }
  if (used.size() != row.size()) {
    for (const auto& [k, v] : row)
      if (!used.count(k))
        throw std::logic_error("export: column '" + k + "' not in the header");
  }
  return out;
}

const std::vector<std::string> kShopifyHeader = {"Title",
                                                 "URL handle",
                                                 "Description",
                                                 "Vendor",
                                                 "Product category",
                                                 "Type",
                                                 "Tags",
                                                 "Published on online store",
                                                 "Status",
                                                 "SKU",
                                                 "Barcode",
                                                 "Option1 name",
                                                 "Option1 value",
                                                 "Option1 Linked To",
                                                 "Option2 name",
                                                 "Option2 value",
                                                 "Option2 Linked To",
                                                 "Option3 name",
                                                 "Option3 value",
                                                 "Option3 Linked To",
                                                 "Price",
                                                 "Compare-at price",
                                                 "Cost per item",
                                                 "Charge tax",
                                                 "Tax code",
                                                 "Unit price total measure",
                                                 "Unit price total measure unit",
                                                 "Unit price base measure",
                                                 "Unit price base measure unit",
                                                 "Inventory tracker",
                                                 "Inventory quantity",
                                                 "Continue selling when out of stock",
                                                 "Weight value (grams)",
                                                 "Weight unit for display",
                                                 "Requires shipping",
                                                 "Fulfillment service",
                                                 "Product image URL",
                                                 "Image position",
                                                 "Image alt text",
                                                 "Variant image URL",
                                                 "Gift card",
                                                 "SEO title",
                                                 "SEO description",
                                                 "Color (product.metafields.shopify.color-pattern)",
                                                 "Google Shopping / Google product category",
                                                 "Google Shopping / Gender",
                                                 "Google Shopping / Age group",
                                                 "Google Shopping / Manufacturer part number (MPN)",
                                                 "Google Shopping / Ad group name",
                                                 "Google Shopping / Ads labels",
                                                 "Google Shopping / Condition",
                                                 "Google Shopping / Custom product",
                                                 "Google Shopping / Custom label 0",
                                                 "Google Shopping / Custom label 1",
                                                 "Google Shopping / Custom label 2",
                                                 "Google Shopping / Custom label 3",
                                                 "Google Shopping / Custom label 4"};

const std::vector<std::string> kShopifyLegacyHeader = {"Handle",
                                                       "Title",
                                                       "Body (HTML)",
                                                       "Vendor",
                                                       "Product Category",
                                                       "Type",
                                                       "Tags",
                                                       "Published",
                                                       "Option1 Name",
                                                       "Option1 Value",
                                                       "Option2 Name",
                                                       "Option2 Value",
                                                       "Option3 Name",
                                                       "Option3 Value",
                                                       "Variant SKU",
                                                       "Variant Grams",
                                                       "Variant Inventory Tracker",
                                                       "Variant Inventory Qty",
                                                       "Variant Inventory Policy",
                                                       "Variant Fulfillment Service",
                                                       "Variant Price",
                                                       "Variant Compare At Price",
                                                       "Variant Requires Shipping",
                                                       "Variant Taxable",
                                                       "Variant Barcode",
                                                       "Image Src",
                                                       "Image Position",
                                                       "Image Alt Text",
                                                       "Gift Card",
                                                       "SEO Title",
                                                       "SEO Description",
                                                       "Google Shopping / Gender",
                                                       "Google Shopping / Age Group",
                                                       "Google Shopping / Condition",
                                                       "Variant Image",
                                                       "Variant Weight Unit",
                                                       "Variant Tax Code",
                                                       "Cost per item",
                                                       "Status"};

// Google product category "Apparel & Accessories > Clothing" (taxonomy id 1604) by garment type.
std::string googleCategory(const std::string& type) {
  if (type == "dress")
    return "2271";  // Clothing > Dresses
  if (type == "skirt")
    return "1581";  // Clothing > Skirts
  if (type == "pants")
    return "204";  // Clothing > Pants
  if (type == "top")
    return "212";  // Clothing > Shirts & Tops
  return "1604";
}

std::string productTypeName(const std::string& type) {
  if (type == "top")
    return "Tops";
  if (type == "dress")
    return "Dresses";
  if (type == "skirt")
    return "Skirts";
  if (type == "pants")
    return "Pants";
  return type;
}

std::string imageUrl(const ShopOptions& options, const ExportImage& image) {
  std::string base = options.publicBaseUrl;
  while (!base.empty() && base.back() == '/')
    base.pop_back();
  std::string path = image.path;
  while (!path.empty() && path.front() == '/')
    path.erase(path.begin());
  // Percent-encode what is not safe in a URL path (spaces, non-ASCII bytes of UTF-8 names).
  std::string enc;
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == '/') {
      enc += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      enc += buf;
    }
  }
  return base + "/" + enc;
}

// Latin letters with accents as WordPress's remove_accents() turns them into ASCII (the common
// ones of Western and Central European names; others become a dash).
std::string asciiFold(std::string_view utf8) {
  static const std::map<std::string, std::string> kFold = {
      {"à", "a"}, {"á", "a"},  {"â", "a"}, {"ã", "a"}, {"ä", "a"}, {"å", "a"}, {"æ", "ae"},
      {"ç", "c"}, {"è", "e"},  {"é", "e"}, {"ê", "e"}, {"ë", "e"}, {"ì", "i"}, {"í", "i"},
      {"î", "i"}, {"ï", "i"},  {"ñ", "n"}, {"ò", "o"}, {"ó", "o"}, {"ô", "o"}, {"õ", "o"},
      {"ö", "o"}, {"ø", "o"},  {"ù", "u"}, {"ú", "u"}, {"û", "u"}, {"ü", "u"}, {"ý", "y"},
      {"ÿ", "y"}, {"ß", "ss"}, {"À", "a"}, {"Á", "a"}, {"Â", "a"}, {"Ä", "a"}, {"Ç", "c"},
      {"È", "e"}, {"É", "e"},  {"Ê", "e"}, {"Ö", "o"}, {"Ü", "u"}, {"Ñ", "n"}, {"œ", "oe"}};
  std::string out;
  for (std::size_t i = 0; i < utf8.size();) {
    const unsigned char c = static_cast<unsigned char>(utf8[i]);
    const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : 4;
    const std::string ch(utf8.substr(i, n));
    if (n == 1) {
      out += ch;
    } else if (const auto it = kFold.find(ch); it != kFold.end()) {
      out += it->second;
    } else {
      out += ' ';
    }
    i += n;
  }
  return out;
}

std::string sizeGuideTable(const ExportItem& item, const ShopOptions& options) {
  std::vector<std::string> cols;
  std::vector<std::pair<std::string, const std::map<std::string, double>*>> rows;
  std::string pieceLabel;
  if (item.sizeGuide) {
    const auto& g = *item.sizeGuide;
    cols = g.measurements;
    pieceLabel = shopLabel(options, g.itemSize());
    for (std::size_t i = 0; i < g.rows.size(); ++i)
      if (options.madeToOrder || i == g.itemRow)
        rows.emplace_back(shopLabel(options, g.rows[i].size), &g.rows[i].garmentCm);
  } else {
    for (const auto& name : dsw::sizeGuideMeasurementNames())
      if (const auto it = item.measurementsCm.find(name);
          it != item.measurementsCm.end() && it->second > 0)
        cols.push_back(name);
    pieceLabel = "One size";
    rows.emplace_back(pieceLabel, &item.measurementsCm);
  }
  std::ostringstream os;
  os << "<table class=\"size-guide\"><thead><tr><th>Size</th>";
  for (const auto& c : cols)
    os << "<th>" << drafts::xmlEscape(measurementLabel(c)) << " (cm)</th>";
  os << "</tr></thead><tbody>";
  for (const auto& [label, cm] : rows) {
    os << "<tr><td>" << drafts::xmlEscape(label) << "</td>";
    for (const auto& c : cols) {
      auto it = cm->find(c);
      os << "<td>" << (it == cm->end() ? std::string("&ndash;") : formatCm(it->second)) << "</td>";
    }
    os << "</tr>";
  }
  os << "</tbody></table>";
  return os.str();
}

}  // namespace

const std::vector<std::string>& merchantSizeSystems() {
  static const std::vector<std::string> kSystems = {"AU", "BR", "CN",  "DE", "EU", "FR",
                                                    "IT", "JP", "MEX", "UK", "US"};
  return kSystems;
}

std::string shopifyHandle(const ExportItem& item) {
  std::string out;
  for (unsigned char c : item.sku) {
    if (std::isalnum(c)) {
      out += static_cast<char>(std::tolower(c));
    } else if (!out.empty() && out.back() != '-') {
      out += '-';
    }
  }
  while (!out.empty() && out.back() == '-')
    out.pop_back();
  if (out.empty())
    out = "item-" + item.id;
  return out;
}

std::string defaultProductTitle(const ExportItem& item) {
  std::map<std::string, std::string> attributes = item.attributes;
  if (item.colors.empty())
    attributes.erase("color");
  else
    attributes["color"] = item.colors.front();
  attributes["pattern"] = item.printed ? "print" : "solid";
  return defaultProductTitle(item.type, attributes);
}

std::string defaultProductTitle(const std::string& type,
                                const std::map<std::string, std::string>& attributes) {
  auto attr = [&](const std::string& k) {
    const auto it = attributes.find(k);
    return it == attributes.end() ? std::string() : it->second;
  };
  const std::string sleeve = attr("sleeve");
  const std::string sleeveWords = sleeve == "none"    ? "sleeveless "
                                  : sleeve == "short" ? "short-sleeve "
                                  : sleeve == "long"  ? "long-sleeve "
                                                      : "";
  std::string noun;
  if (type == "skirt")
    noun = attr("skirt") == "a_line"   ? "A-line skirt"
           : attr("skirt") == "h_line" ? "straight skirt"
                                       : "skirt";
  else if (type == "pants")
    noun = "trousers";
  else if (type == "top" || type == "dress")
    noun = sleeveWords + type;
  else
    noun = "garment";
  // "navy/white": the dominant colour names the piece.
  const std::string colours = attr("color");
  const std::string colour =
      attr("pattern") == "print" ? "Printed" : colours.substr(0, colours.find('/'));
  std::string title = colour.empty() ? noun : colour + " " + noun;
  if (!title.empty() && colour.empty() && noun[0] != 'A')
    title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
  return title;
}

std::string wooCommerceSlug(const ExportItem& item) {
  std::string out;
  for (unsigned char c : asciiFold(item.title)) {
    if (std::isalnum(c) || c == '_') {
      out += static_cast<char>(std::tolower(c));
    } else if (!out.empty() && out.back() != '-') {
      out += '-';
    }
  }
  while (!out.empty() && out.back() == '-')
    out.pop_back();
  return out.empty() ? shopifyHandle(item) : out;
}

std::string productLink(const ExportItem& item, const ShopOptions& options) {
  checkPublicUrl(options.storeUrl, "store_url", options);
  std::string store = options.storeUrl;
  while (!store.empty() && store.back() == '/')
    store.pop_back();
  if (options.storePlatform == "woocommerce")
    return store + "/product/" + wooCommerceSlug(item) + "/";
  return store + "/products/" + shopifyHandle(item);
}

std::string sizeGuideHtml(const ExportItem& item, const ShopOptions& options) {
  return sizeGuideTable(item, options);
}

std::string descriptionHtml(const ExportItem& item, const ShopOptions& options) {
  std::string out;
  if (!item.description.empty()) {
    out += "<p>";
    for (char c : drafts::xmlEscape(item.description)) {
      if (c == '\n')
        out += "<br>";
      else if (c != '\r')
        out += c;
    }
    out += "</p>";
  }
  out += "<h3>Size guide</h3>" + sizeGuideHtml(item, options) +
         "<p>Measurements of the garment in cm, not body sizes: widths all the way round "
         "(bust, waist, hip, hem), lengths from the top edge down.";
  if (options.madeToOrder && item.sizeGuide && item.sizeGuide->rows.size() > 1)
    out += " Sizes other than " +
           drafts::xmlEscape(shopLabel(options, item.sizeGuide->itemSize())) +
           " are made to order to the same design.";
  out += "</p>";
  return out;
}

ShopFile shopifyCsv(const std::vector<ExportItem>& items, const ShopOptions& options) {
  checkOptions(options);
  const bool legacy = options.legacyShopifyHeader;
  const auto& header = legacy ? kShopifyLegacyHeader : kShopifyHeader;
  ShopFile file;
  CsvWriter w(',', true);
  w.row(header);
  for (const auto& item : items) {
    checkItem(item, options);
    const std::string handle = shopifyHandle(item);
    const auto vars = variants(item, options);
    const std::string price = item.price ? formatPrice(*item.price) : "";
    const bool active = sellable(item);
    if (!active)
      noteDraft(item, file.warnings);
    size_t rows = std::max(vars.size(), item.images.size());
    for (size_t i = 0; i < rows; ++i) {
      Row r;
      r[legacy ? "Handle" : "URL handle"] = handle;
      if (i == 0) {
        r["Title"] = item.title;
        r[legacy ? "Body (HTML)" : "Description"] = descriptionHtml(item, options);
        r["Vendor"] = options.brand;
        r["Type"] = productTypeName(item.type);
        r["Tags"] = join(item.tags, ", ");
        r[legacy ? "Published" : "Published on online store"] = active ? "TRUE" : "FALSE";
        r["Status"] = active ? "active" : "draft";
        r["Google Shopping / Gender"] = options.gender;
        r[legacy ? "Google Shopping / Age Group" : "Google Shopping / Age group"] =
            options.ageGroup;
        r["Google Shopping / Condition"] = "new";
        if (!legacy) {
          r["Google Shopping / Google product category"] = googleCategory(item.type);
          r["Color (product.metafields.shopify.color-pattern)"] =
              item.printed ? "print" : (item.colors.empty() ? colorText(item) : item.colors[0]);
        }
      }
      if (i < vars.size()) {
        const auto& v = vars[i];
        r[legacy ? "Option1 Name" : "Option1 name"] = "Size";
        r[legacy ? "Option1 Value" : "Option1 value"] = v.label;
        r[legacy ? "Variant SKU" : "SKU"] = v.sku;
        r[legacy ? "Variant Price" : "Price"] = price;
        // The piece is one garment: tracked, stock 1, not sold twice. Made-to-order sizes
        // are not stocked.
        r[legacy ? "Variant Inventory Tracker" : "Inventory tracker"] = v.piece ? "shopify" : "";
        r[legacy ? "Variant Inventory Qty" : "Inventory quantity"] = v.piece ? "1" : "";
        r[legacy ? "Variant Inventory Policy" : "Continue selling when out of stock"] =
            v.piece ? (legacy ? "deny" : "DENY") : (legacy ? "continue" : "CONTINUE");
        r[legacy ? "Variant Fulfillment Service" : "Fulfillment service"] = "manual";
        r[legacy ? "Variant Requires Shipping" : "Requires shipping"] = "TRUE";
        r[legacy ? "Variant Taxable" : "Charge tax"] = "TRUE";
        if (legacy) {
          r["Variant Grams"] = "0";
          r["Variant Weight Unit"] = "g";
          r["Gift Card"] = "FALSE";
        } else {
          r["Gift card"] = "FALSE";
        }
      }
      if (i < item.images.size()) {
        const auto& img = item.images[i];
        r[legacy ? "Image Src" : "Product image URL"] = imageUrl(options, img);
        r[legacy ? "Image Position" : "Image position"] = std::to_string(i + 1);
        r[legacy ? "Image Alt Text" : "Image alt text"] = img.alt.empty() ? item.title : img.alt;
      }
      w.row(ordered(header, r));
    }
  }
  file.bytes = std::move(w).str();
  return file;
}

std::set<std::string> wooCommerceMetaNames(const std::vector<ExportItem>& items,
                                           const ShopOptions& options) {
  std::set<std::string> metaNames;
  for (const auto& item : items)
    for (const auto& v : variants(item, options))
      for (const auto& [n, cm] : v.measurementsCm)
        metaNames.insert(n);
  return metaNames;
}

ShopFile wooCommerceCsv(const std::vector<ExportItem>& items, const ShopOptions& options) {
  checkOptions(options);
  // Measurement meta columns: the union over all items, so every row has the same columns.
  return wooCommerceCsvWithColumns(items, options, wooCommerceMetaNames(items, options));
}

ShopFile wooCommerceCsvWithColumns(const std::vector<ExportItem>& items, const ShopOptions& options,
                                   const std::set<std::string>& metaNames) {
  checkOptions(options);
  for (const auto& n : wooCommerceMetaNames(items, options))
    if (!metaNames.count(n))
      throw ExportError("measurement '" + n + "' is not among the file's columns");
  std::vector<std::string> header = {"ID",
                                     "Type",
                                     "SKU",
                                     "Name",
                                     "Published",
                                     "Is featured?",
                                     "Visibility in catalog",
                                     "Short description",
                                     "Description",
                                     "Tax status",
                                     "In stock?",
                                     "Stock",
                                     "Backorders allowed?",
                                     "Regular price",
                                     "Categories",
                                     "Tags",
                                     "Images",
                                     "Parent",
                                     "Position",
                                     "Attribute 1 name",
                                     "Attribute 1 value(s)",
                                     "Attribute 1 visible",
                                     "Attribute 1 global",
                                     "Attribute 1 default",
                                     "Attribute 2 name",
                                     "Attribute 2 value(s)",
                                     "Attribute 2 visible",
                                     "Attribute 2 global"};
  for (const auto& n : metaNames)
    header.push_back("Meta: " + n + "_cm");

  ShopFile file;
  CsvWriter w(',', true);
  w.row(header);
  for (const auto& item : items) {
    checkItem(item, options);
    const auto vars = variants(item, options);
    std::vector<std::string> labels;
    for (const auto& v : vars)
      labels.push_back(v.label);
    std::vector<std::string> urls;
    for (const auto& img : item.images)
      urls.push_back(imageUrl(options, img));
    const std::string color = item.printed ? "Print" : colorText(item);
    const bool active = sellable(item);
    if (!active)
      noteDraft(item, file.warnings);
    const bool simple = vars.size() == 1;
    const auto& piece =
        *std::find_if(vars.begin(), vars.end(), [](const Variant& v) { return v.piece; });

    Row parent;
    parent["Type"] = simple ? "simple" : "variable";
    parent["SKU"] = item.sku;
    parent["Name"] = item.title;
    parent["Published"] = active ? "1" : "-1";  // -1: draft
    parent["Is featured?"] = "0";
    parent["Visibility in catalog"] = "visible";
    parent["Short description"] = item.description;
    parent["Description"] = descriptionHtml(item, options);
    parent["Tax status"] = "taxable";
    parent["In stock?"] = "1";
    parent["Categories"] = productTypeName(item.type);
    parent["Tags"] = join(item.tags, ", ");
    parent["Images"] = join(urls, ", ");
    parent["Attribute 1 name"] = "Size";
    parent["Attribute 1 value(s)"] = join(labels, ", ");
    parent["Attribute 1 visible"] = "1";
    parent["Attribute 1 global"] = "1";
    if (simple) {
      parent["Stock"] = "1";
      parent["Backorders allowed?"] = "0";
      parent["Regular price"] = item.price ? formatPrice(*item.price) : "";
      for (const auto& [n, cm] : piece.measurementsCm)
        parent["Meta: " + n + "_cm"] = formatCm(cm);
    } else {
      parent["Attribute 1 default"] = piece.label;
    }
    if (!color.empty()) {
      parent["Attribute 2 name"] = "Color";
      parent["Attribute 2 value(s)"] = color;
      parent["Attribute 2 visible"] = "1";
      parent["Attribute 2 global"] = "1";
    }
    w.row(ordered(header, parent));
    if (simple)
      continue;

    for (size_t i = 0; i < vars.size(); ++i) {
      const auto& v = vars[i];
      Row r;
      r["Type"] = "variation";
      r["SKU"] = v.sku == item.sku ? item.sku + "-" + skuSuffix(v.label) : v.sku;
      r["Name"] = item.title + " - " + v.label;
      r["Published"] = active ? "1" : "-1";
      r["Tax status"] = "taxable";
      r["In stock?"] = "1";
      // The piece: stock 1; a made-to-order size: no stock kept, orders taken.
      r["Stock"] = v.piece ? "1" : "";
      r["Backorders allowed?"] = v.piece ? "0" : "1";
      r["Regular price"] = item.price ? formatPrice(*item.price) : "";
      r["Parent"] = item.sku;
      r["Position"] = std::to_string(i + 1);
      r["Attribute 1 name"] = "Size";
      r["Attribute 1 value(s)"] = v.label;
      r["Attribute 1 global"] = "1";
      for (const auto& [n, cm] : v.measurementsCm)
        r["Meta: " + n + "_cm"] = formatCm(cm);
      w.row(ordered(header, r));
    }
  }
  file.bytes = std::move(w).str();
  return file;
}

ShopFile merchantTsv(const std::vector<ExportItem>& items, const ShopOptions& options) {
  checkOptions(options);
  const std::vector<std::string> header = {"id",
                                           "item_group_id",
                                           "title",
                                           "description",
                                           "link",
                                           "image_link",
                                           "additional_image_link",
                                           "availability",
                                           "price",
                                           "brand",
                                           "mpn",
                                           "condition",
                                           "google_product_category",
                                           "product_type",
                                           "gender",
                                           "age_group",
                                           "color",
                                           "pattern",
                                           "size",
                                           "size_system",
                                           "size_type",
                                           "product_detail"};
  if (!items.empty() && options.brand.empty())
    throw ExportError(
        "merchant feed: export option 'brand' is empty; Merchant Center requires a brand for "
        "apparel (set [shop] brand to the shop's or the label's name)");
  ShopFile file;
  CsvWriter w('\t', false);
  w.row(header);
  for (const auto& item : items) {
    checkItem(item, options);
    if (!sellable(item)) {
      file.warnings.push_back(who(item) + (item.price ? ": held back by staff" : ": no price") +
                              "; left out of the Merchant feed, which refuses unpriced or "
                              "unpublished products");
      continue;
    }
    const std::string link = productLink(item, options);
    const std::string color = colorText(item);
    if (color.empty())
      file.warnings.push_back(who(item) +
                              ": no colour; Merchant Center requires one for apparel in most "
                              "countries");
    std::vector<std::string> extra;
    for (size_t i = 1; i < item.images.size() && i <= 10; ++i)
      extra.push_back(imageUrl(options, item.images[i]));
    const auto vars = variants(item, options);
    for (const auto& v : vars) {
      std::vector<std::string> details;
      for (const auto& [n, cm] : v.measurementsCm) {
        // product_detail is "section:attribute:value"; multiple entries are comma-separated,
        // so no label may contain ':' or ','.
        std::string label = measurementLabel(n);
        for (char& c : label)
          if (c == ':' || c == ',')
            c = ' ';
        details.push_back("Measurements:" + label + ":" + formatCm(cm) + " cm");
      }
      Row r;
      r["id"] = v.sku;
      if (vars.size() > 1)
        r["item_group_id"] = item.sku;
      r["title"] = item.title + (vars.size() > 1 ? " - " + v.label : "");
      r["description"] = item.description.empty() ? item.title : item.description;
      r["link"] = link;
      if (!item.images.empty())
        r["image_link"] = imageUrl(options, item.images.front());
      r["additional_image_link"] = join(extra, ",");
      r["availability"] = "in_stock";
      r["price"] = formatPrice(*item.price) + " " + options.currency;
      r["brand"] = options.brand;
      r["mpn"] = v.sku;
      r["condition"] = "new";
      r["google_product_category"] = googleCategory(item.type);
      r["product_type"] = "Apparel & Accessories > Clothing > " + productTypeName(item.type);
      r["gender"] = options.gender;
      r["age_group"] = options.ageGroup;
      r["color"] = color;
      if (item.printed)
        r["pattern"] = "print";
      r["size"] = v.label;
      r["size_system"] = options.sizeSystem;
      r["size_type"] = "regular";
      r["product_detail"] = join(details, ",");
      w.row(ordered(header, r));
    }
  }
  file.bytes = std::move(w).str();
  return file;
}

}  // namespace garmcap::daemon
