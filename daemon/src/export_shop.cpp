#include "garmcap/daemon/export_shop.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "garmcap/drafts/xml_escape.h"

namespace garmcap::daemon {
namespace {

// Measurement display order in size guides: the ones shoppers look for first.
const std::vector<std::string> kMeasurementOrder = {
    "bust_circ",    "waist_circ",    "hip_circ", "hem_circ", "garment_length",
    "skirt_length", "sleeve_length", "outseam",  "inseam",   "leg_opening_circ"};

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

// A size run always has at least one row: an item without a graded run sells as "One size"
// with its own measurements.
std::vector<ExportSize> sizeRows(const ExportItem& item) {
  if (!item.sizes.empty())
    return item.sizes;
  return {ExportSize{"One size", item.measurementsCm}};
}

// Measurement names present in any size, in display order (known ones first, then the rest
// alphabetically) so that every row of the guide has the same columns.
std::vector<std::string> measurementColumns(const ExportItem& item) {
  std::set<std::string> present;
  for (const auto& s : sizeRows(item))
    for (const auto& [name, v] : s.measurementsCm)
      present.insert(name);
  std::vector<std::string> cols;
  for (const auto& n : kMeasurementOrder)
    if (present.count(n))
      cols.push_back(n);
  for (const auto& n : present)
    if (std::find(kMeasurementOrder.begin(), kMeasurementOrder.end(), n) == kMeasurementOrder.end())
      cols.push_back(n);
  return cols;
}

void checkItem(const ExportItem& item, const ShopOptions& options) {
  const std::string who = "item " + (item.id.empty() ? std::string("(no id)") : item.id);
  if (item.sku.empty())
    throw ExportError(who + ": field 'sku' is empty; a shop needs a SKU");
  if (item.title.empty())
    throw ExportError(who + ": field 'title' is empty");
  if (!item.images.empty() && options.publicBaseUrl.empty())
    throw ExportError(who +
                      ": has images but the export option 'public_base_url' is empty; shops "
                      "fetch images from public URLs");
  for (const auto& s : item.sizes)
    if (s.label.empty())
      throw ExportError(who + ": a size of the graded run has no label");
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

std::string variantSku(const ExportItem& item, const ExportSize& size) {
  if (item.sizes.empty())
    return item.sku;
  std::string label;
  for (unsigned char c : size.label)
    label += std::isalnum(c) ? static_cast<char>(c) : '-';
  return item.sku + "-" + label;
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

std::string attribute(const ExportItem& item, const std::string& key) {
  auto it = item.attributes.find(key);
  return it == item.attributes.end() ? std::string() : it->second;
}

}  // namespace

std::string csvField(const std::string& value) {
  bool quote = value.find_first_of(",\"\r\n") != std::string::npos ||
               (!value.empty() && (value.front() == ' ' || value.back() == ' '));
  if (!quote)
    return value;
  std::string out = "\"";
  for (char c : value) {
    if (c == '"')
      out += '"';
    out += c;
  }
  out += '"';
  return out;
}

std::string measurementLabel(const std::string& name) {
  static const std::map<std::string, std::string> kLabels = {{"bust_circ", "Bust"},
                                                             {"waist_circ", "Waist"},
                                                             {"hip_circ", "Hip"},
                                                             {"hem_circ", "Hem"},
                                                             {"garment_length", "Length"},
                                                             {"skirt_length", "Skirt length"},
                                                             {"sleeve_length", "Sleeve length"},
                                                             {"outseam", "Outseam"},
                                                             {"inseam", "Inseam"},
                                                             {"leg_opening_circ", "Leg opening"}};
  auto it = kLabels.find(name);
  if (it != kLabels.end())
    return it->second;
  std::string out = name;
  for (char& c : out)
    if (c == '_')
      c = ' ';
  if (!out.empty())
    out[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(out[0])));
  return out;
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

std::string sizeGuideHtml(const ExportItem& item) {
  const auto cols = measurementColumns(item);
  std::ostringstream os;
  os << "<table class=\"size-guide\"><thead><tr><th>Size</th>";
  for (const auto& c : cols)
    os << "<th>" << drafts::xmlEscape(measurementLabel(c)) << " (cm)</th>";
  os << "</tr></thead><tbody>";
  for (const auto& s : sizeRows(item)) {
    os << "<tr><td>" << drafts::xmlEscape(s.label) << "</td>";
    for (const auto& c : cols) {
      auto it = s.measurementsCm.find(c);
      os << "<td>" << (it == s.measurementsCm.end() ? std::string("&ndash;") : formatCm(it->second))
         << "</td>";
    }
    os << "</tr>";
  }
  os << "</tbody></table>";
  return os.str();
}

std::string descriptionHtml(const ExportItem& item) {
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
  out += "<h3>Size guide</h3>" + sizeGuideHtml(item) +
         "<p>Garment measurements in cm, taken flat on the garment, not body sizes.</p>";
  return out;
}

std::string shopifyCsv(const std::vector<ExportItem>& items, const ShopOptions& options) {
  const bool legacy = options.legacyShopifyHeader;
  const auto& header = legacy ? kShopifyLegacyHeader : kShopifyHeader;
  CsvWriter w(',', true);
  w.row(header);
  for (const auto& item : items) {
    checkItem(item, options);
    const std::string handle = shopifyHandle(item);
    const auto sizes = sizeRows(item);
    const std::string price = item.price ? formatPrice(*item.price) : "";
    const std::string status = item.published ? "active" : "draft";
    size_t rows = std::max(sizes.size(), item.images.size());
    for (size_t i = 0; i < rows; ++i) {
      Row r;
      r[legacy ? "Handle" : "URL handle"] = handle;
      if (i == 0) {
        r["Title"] = item.title;
        r[legacy ? "Body (HTML)" : "Description"] = descriptionHtml(item);
        r["Vendor"] = options.vendor;
        r["Type"] = productTypeName(item.type);
        r["Tags"] = join(item.tags, ", ");
        r[legacy ? "Published" : "Published on online store"] = item.published ? "TRUE" : "FALSE";
        r["Status"] = status;
        r["Google Shopping / Gender"] = options.gender;
        r[legacy ? "Google Shopping / Age Group" : "Google Shopping / Age group"] =
            options.ageGroup;
        r["Google Shopping / Condition"] = "new";
        if (!legacy) {
          r["Google Shopping / Google product category"] = googleCategory(item.type);
          r["Color (product.metafields.shopify.color-pattern)"] = attribute(item, "color");
        }
      }
      if (i < sizes.size()) {
        const auto& s = sizes[i];
        r[legacy ? "Option1 Name" : "Option1 name"] = "Size";
        r[legacy ? "Option1 Value" : "Option1 value"] = s.label;
        r[legacy ? "Variant SKU" : "SKU"] = variantSku(item, s);
        r[legacy ? "Variant Price" : "Price"] = price;
        r[legacy ? "Variant Inventory Policy" : "Continue selling when out of stock"] =
            legacy ? "deny" : "DENY";
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
  return std::move(w).str();
}

std::string wooCommerceCsv(const std::vector<ExportItem>& items, const ShopOptions& options) {
  // Measurement meta columns: the union over all items, so every row has the same columns.
  std::set<std::string> metaNames;
  for (const auto& item : items)
    for (const auto& s : sizeRows(item))
      for (const auto& [n, v] : s.measurementsCm)
        metaNames.insert(n);
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

  CsvWriter w(',', true);
  w.row(header);
  for (const auto& item : items) {
    checkItem(item, options);
    const auto sizes = sizeRows(item);
    std::vector<std::string> labels;
    for (const auto& s : sizes)
      labels.push_back(s.label);
    std::vector<std::string> urls;
    for (const auto& img : item.images)
      urls.push_back(imageUrl(options, img));
    const std::string color = attribute(item, "color");

    Row parent;
    parent["Type"] = "variable";
    parent["SKU"] = item.sku;
    parent["Name"] = item.title;
    parent["Published"] = item.published ? "1" : "-1";
    parent["Is featured?"] = "0";
    parent["Visibility in catalog"] = "visible";
    parent["Short description"] = item.description;
    parent["Description"] = descriptionHtml(item);
    parent["Tax status"] = "taxable";
    parent["In stock?"] = "1";
    parent["Categories"] = productTypeName(item.type);
    parent["Tags"] = join(item.tags, ", ");
    parent["Images"] = join(urls, ", ");
    parent["Attribute 1 name"] = "Size";
    parent["Attribute 1 value(s)"] = join(labels, ", ");
    parent["Attribute 1 visible"] = "1";
    parent["Attribute 1 global"] = "1";
    parent["Attribute 1 default"] = item.sampleSize.empty() ? labels.front() : item.sampleSize;
    if (!color.empty()) {
      parent["Attribute 2 name"] = "Color";
      parent["Attribute 2 value(s)"] = color;
      parent["Attribute 2 visible"] = "1";
      parent["Attribute 2 global"] = "1";
    }
    w.row(ordered(header, parent));

    for (size_t i = 0; i < sizes.size(); ++i) {
      const auto& s = sizes[i];
      Row v;
      v["Type"] = "variation";
      v["SKU"] = item.sizes.empty() ? item.sku + "-ONE" : variantSku(item, s);
      v["Name"] = item.title + " - " + s.label;
      v["Published"] = item.published ? "1" : "-1";
      v["Tax status"] = "taxable";
      v["In stock?"] = "1";
      v["Regular price"] = item.price ? formatPrice(*item.price) : "";
      v["Parent"] = item.sku;
      v["Position"] = std::to_string(i + 1);
      v["Attribute 1 name"] = "Size";
      v["Attribute 1 value(s)"] = s.label;
      v["Attribute 1 global"] = "1";
      for (const auto& [n, cm] : s.measurementsCm)
        v["Meta: " + n + "_cm"] = formatCm(cm);
      w.row(ordered(header, v));
    }
  }
  return std::move(w).str();
}

std::string merchantTsv(const std::vector<ExportItem>& items, const ShopOptions& options) {
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
                                           "size",
                                           "size_system",
                                           "size_type",
                                           "product_detail"};
  if (!items.empty() && options.storeUrl.empty())
    throw ExportError(
        "merchant feed: export option 'store_url' is empty; every product needs a "
        "link to its page");
  CsvWriter w('\t', false);
  w.row(header);
  for (const auto& item : items) {
    checkItem(item, options);
    std::string store = options.storeUrl;
    while (!store.empty() && store.back() == '/')
      store.pop_back();
    const std::string link = store + "/products/" + shopifyHandle(item);
    std::vector<std::string> extra;
    for (size_t i = 1; i < item.images.size() && i <= 10; ++i)
      extra.push_back(imageUrl(options, item.images[i]));
    for (const auto& s : sizeRows(item)) {
      std::vector<std::string> details;
      for (const auto& [n, cm] : s.measurementsCm) {
        // product_detail is "section:attribute:value"; multiple entries are comma-separated,
        // so no label may contain ':' or ','.
        std::string label = measurementLabel(n);
        for (char& c : label)
          if (c == ':' || c == ',')
            c = ' ';
        details.push_back("Measurements:" + label + ":" + formatCm(cm) + " cm");
      }
      Row r;
      r["id"] = variantSku(item, s);
      r["item_group_id"] = item.sku;
      r["title"] = item.title + (item.sizes.empty() ? "" : " - " + s.label);
      std::string desc = item.description.empty() ? item.title : item.description;
      r["description"] = desc;
      r["link"] = link;
      if (!item.images.empty())
        r["image_link"] = imageUrl(options, item.images.front());
      r["additional_image_link"] = join(extra, ",");
      r["availability"] = "in_stock";
      if (item.price)
        r["price"] = formatPrice(*item.price) + " " + options.currency;
      r["brand"] = options.vendor;
      r["mpn"] = variantSku(item, s);
      r["condition"] = "new";
      r["google_product_category"] = googleCategory(item.type);
      r["product_type"] = "Apparel & Accessories > Clothing > " + productTypeName(item.type);
      r["gender"] = options.gender;
      r["age_group"] = options.ageGroup;
      r["color"] = attribute(item, "color");
      r["size"] = s.label;
      r["size_system"] = options.sizeSystem;
      r["size_type"] = "regular";
      r["product_detail"] = join(details, ",");
      w.row(ordered(header, r));
    }
  }
  return std::move(w).str();
}

}  // namespace garmcap::daemon
