#include "garmcap/daemon/export_items.h"

#include <algorithm>

#include "garmcap/daemon/utf8.h"

namespace garmcap::daemon {
namespace {

// A URL given as an option: http(s), printable ASCII without spaces or quotes, bounded.
std::string urlOption(const RouteMatch& m, const std::string& key, const std::string& fallback) {
  auto v = m.queryValue(key);
  if (!v || v->empty())
    return fallback;
  const std::string& s = *v;
  if (s.size() > 500)
    throw BadRequest("query '" + key + "' is longer than 500 bytes");
  if (s.rfind("http://", 0) != 0 && s.rfind("https://", 0) != 0)
    throw BadRequest("query '" + key + "' must start with http:// or https://, got '" +
                     quoteInput(s) + "'");
  for (unsigned char c : s)
    if (c <= 32 || c >= 127 || c == '"' || c == '\'' || c == '<' || c == '>' || c == '\\')
      throw BadRequest("query '" + key + "' holds a character not allowed in a URL");
  return s;
}

std::string shortOption(const RouteMatch& m, const std::string& key, const std::string& fallback,
                        size_t maxLen) {
  auto v = m.queryValue(key);
  if (!v || v->empty())
    return fallback;
  if (v->size() > maxLen)
    throw BadRequest("query '" + key + "' is longer than " + std::to_string(maxLen) + " bytes");
  for (unsigned char c : *v)
    if (c < 32 || c == 127)
      throw BadRequest("query '" + key + "' holds a control character");
  return *v;
}

// The shop's settings come from the config ([shop]); a query value overrides one for this
// export. The shop's addresses come from the [shop] settings (or the request's explicit options),
// never from the request's Host header: the address a tablet reached the station by (127.0.0.1, a
// 192.168.x LAN address) is not one a shop's importer can fetch images or link products from, and
// an export built on it would publish dead links without a word. Left empty, the export refuses
// with the option's name (export_shop.cpp's checkPublicUrl).
}  // namespace

const std::vector<std::vector<std::string>>& shopImageSlots() {
  static const std::vector<std::vector<std::string>> kSlots = {{"product_ghost", "product"},
                                                               {"product_back"}};
  return kSlots;
}

std::string imageExtension(const std::string& mediaType) {
  if (mediaType == "image/jpeg")
    return "jpg";
  if (mediaType == "image/png")
    return "png";
  if (mediaType == "image/webp")
    return "webp";
  return "";
}

std::string exportImagePath(std::int64_t id, const std::string& kind,
                            const std::string& mediaType) {
  return "images/" + std::to_string(id) + "-" + kind + "." + imageExtension(mediaType);
}

std::optional<dsw::SizeGuide> storedSizeGuide(const Item& it,
                                              const std::optional<nlohmann::json>& j) {
  if (!j || j->is_null())
    return std::nullopt;
  return dsw::sizeGuideFromJson(j->dump(), "item " + std::to_string(it.id) + " size guide");
}

ExportItem toExportItem(const Item& it, const std::optional<nlohmann::json>& guide) {
  ExportItem e;
  e.id = std::to_string(it.id);
  e.sku = it.sku;
  e.description = it.notes;
  e.type = it.type;
  e.attributes = it.attributes;
  if (const auto c = it.attributes.find("color"); c != it.attributes.end()) {
    std::string rest = c->second;
    for (std::size_t at; !rest.empty(); rest = at == std::string::npos ? "" : rest.substr(at + 1)) {
      at = rest.find('/');
      if (at != 0)
        e.colors.push_back(rest.substr(0, at));
    }
  }
  if (const auto p = it.attributes.find("pattern"); p != it.attributes.end())
    e.printed = p->second == "print";
  e.title = it.title.empty() ? defaultProductTitle(e) : it.title;
  if (it.priceCents)
    e.price = static_cast<double>(*it.priceCents) / 100.0;
  e.tags = it.tags;
  e.published = true;
  e.measurementsCm = it.measurementsCm;
  e.sizeGuide = storedSizeGuide(it, guide);
  for (const auto& slot : shopImageSlots())
    for (const auto& kind : slot) {
      const auto im = std::find_if(it.images.begin(), it.images.end(), [&](const ImageRef& i) {
        return i.kind == kind && !imageExtension(i.mediaType).empty();
      });
      if (im != it.images.end()) {
        e.images.push_back({exportImagePath(it.id, im->kind, im->mediaType), ""});
        break;
      }
    }
  return e;
}

std::vector<ExportItem> shopItems(const std::vector<Item>& items,
                                  const std::vector<std::optional<nlohmann::json>>& guides,
                                  std::vector<std::string>& warnings,
                                  const std::function<std::string(const Item&)>& label) {
  std::vector<ExportItem> out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& it = items[i];
    if (it.sku.empty()) {
      warnings.push_back(label(it) +
                         " has no SKU; left out of the shop files (give it a SKU on its page)");
      continue;
    }
    out.push_back(toExportItem(it, i < guides.size() ? guides[i] : std::nullopt));
  }
  return out;
}

ShopOptions shopOptions(const RouteMatch& m, const ShopConfig& shop) {
  ShopOptions o;
  o.publicBaseUrl = urlOption(m, "base_url", shop.publicBaseUrl);
  o.storeUrl = urlOption(m, "store_url", shop.storeUrl);
  o.storePlatform = shortOption(m, "store_platform", shop.storePlatform, 16);
  o.brand = shortOption(m, "brand", shortOption(m, "vendor", shop.brand, 150), 150);
  o.currency = shortOption(m, "currency", shop.currency, 3);
  o.sizeSystem = shortOption(m, "size_system", shop.sizeSystem, 4);
  o.sizeLabels = shop.sizeLabels;
  o.madeToOrder = m.queryValue("made_to_order").value_or(shop.madeToOrder ? "1" : "0") == "1";
  o.allowLoopback = shop.allowLoopback;
  o.gender = shortOption(m, "gender", o.gender, 10);
  o.legacyShopifyHeader = m.queryValue("legacy").value_or("0") == "1";
  return o;
}

void setExportWarnings(Response& r, const std::vector<std::string>& warnings) {
  r.set("X-Export-Warnings", std::to_string(warnings.size()));
  if (warnings.empty())
    return;
  std::string text;
  for (const auto& w : warnings)
    text += (text.empty() ? "" : " | ") + w;
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) >= 127)
      c = '?';
  if (text.size() > 2000)
    text = text.substr(0, 1997) + "...";
  r.set("X-Export-Warning-Text", text);
}

Response downloadResponse(const std::string& contentType, std::string body,
                          const std::string& fileName) {
  Response r = textResponse(http::status::ok, contentType, std::move(body));
  r.set(http::field::content_disposition, "attachment; filename=\"" + fileName + "\"");
  r.set(http::field::cache_control, "no-store");
  return r;
}

}  // namespace garmcap::daemon
