#include "garmcap/hub/hub_catalog_zip.h"

#include <spdlog/spdlog.h>

#include <array>
#include <map>
#include <set>

#include "garmcap/daemon/export_catalog.h"
#include "garmcap/daemon/export_items.h"
#include "garmcap/daemon/spill_buffer.h"
#include "garmcap/daemon/zip_writer.h"
#include "garmcap/hub/hub_exports.h"

namespace garmcap::hub {

namespace http = daemon::http;

namespace {

// Items read from the snapshot at a time (their files are made one item at a time).
constexpr int kPageItems = 500;
// The most of the central directory or of the notes sent in one chunk.
constexpr std::size_t kTailPiece = 64 * 1024;

std::string labelOf(const HubItem& h) {
  return "item " + std::to_string(h.id) + " (" + h.station + " #" + std::to_string(h.localId) + ")";
}

class ChainCatalogZipStream : public std::enable_shared_from_this<ChainCatalogZipStream> {
 public:
  ChainCatalogZipStream(std::unique_ptr<ApprovedReader> reader, daemon::ShopOptions options,
                        std::string heading, std::shared_ptr<daemon::StreamSink> sink,
                        daemon::DownloadSink& download, std::shared_ptr<void> slot)
      : reader_(std::move(reader)),
        options_(std::move(options)),
        heading_(std::move(heading)),
        sink_(std::move(sink)),
        download_(download),
        slot_(std::move(slot)) {}

  /// The next chunk, once the previous one is written; the last chunk ends the body. A failure
  /// closes the connection without it: the client sees a cut download, not a short archive.
  void next() {
    if (!sink_->open())
      return;
    try {
      std::string piece;
      while (piece.empty() && phase_ != Phase::kDone)
        piece = step();
      if (piece.empty()) {
        download_.writeThen("0\r\n\r\n", [sink = sink_] { sink->close(); });
        return;
      }
      download_.writeThen(daemon::httpChunk(piece), [self = shared_from_this()] { self->next(); });
    } catch (const std::exception& e) {
      spdlog::error("hub: catalog.zip failed half-way, the download is cut short: {}", e.what());
      sink_->close();
    }
  }

 private:
  enum class Phase { kItems, kShopFiles, kReadme, kNotes, kTail, kDone };

  // The next bytes of the archive ("" when a step made none: a page boundary, a file left out).
  std::string step() {
    switch (phase_) {
      case Phase::kItems:
        return itemStep();
      case Phase::kShopFiles:
        return shopStep();
      case Phase::kReadme: {
        std::string piece = zip_.begin("README.txt");
        const std::string head = daemon::catalogReadmeHead(heading_, exported_, options_);
        zip_.add(head);
        phase_ = Phase::kNotes;
        return piece + head;
      }
      case Phase::kNotes: {
        // The station's order: the items' notes, the pattern files', the shop files'.
        for (auto* notes : {&itemNotes_, &patternNotes_, &shopNotes_}) {
          std::string part = notes->read(kTailPiece);
          if (!part.empty()) {
            zip_.add(part);
            return part;
          }
        }
        phase_ = Phase::kTail;
        return zip_.end();
      }
      case Phase::kTail: {
        std::string piece = zip_.tail(kTailPiece);
        if (piece.empty())
          phase_ = Phase::kDone;
        return piece;
      }
      case Phase::kDone:
        break;
    }
    return {};
  }

  // One item's files; a new page first when the last one is done.
  std::string itemStep() {
    if (at_ == page_.size()) {
      page_ = reader_->next(kPageItems);
      at_ = 0;
      if (page_.empty()) {
        phase_ = Phase::kShopFiles;
        return {};
      }
      // The page's shop items: the notes of items left out or drafted, the count the README
      // gives, and WooCommerce's measurement columns (the union over every item).
      std::vector<std::string> notes;
      const auto items = shopPage(page_, notes);
      exported_ += items.size();
      for (const auto& n : notes)
        itemNotes_.append("Note: " + n + "\n");
      const auto names = daemon::wooCommerceMetaNames(items, options_);
      wooColumns_.insert(names.begin(), names.end());
    }
    const HubItem& h = page_[at_++];
    daemon::Item it = catalogItemOf(h);
    const auto patterns = reader_->patterns(h.id);
    for (const auto& [size, json] : patterns)
      it.sizes.push_back(size);
    std::vector<std::string> notes;
    const std::string label = labelOf(h);
    const auto files = daemon::catalogItemFiles(
        it, sizeGuideOf(h), patterns, [this](const std::string& sha) { return reader_->blob(sha); },
        [&label](const daemon::Item&) { return label; }, notes);
    for (const auto& n : notes)
      patternNotes_.append("Note: " + n + "\n");
    std::string piece;
    for (const auto& f : files)
      piece += zip_.file(f.path, f.data);
    return piece;
  }

  // One page of the current shop file, as an entry written in pieces.
  std::string shopStep() {
    const auto& file = daemon::catalogShopFiles()[shopFile_];
    if (!shopOpen_) {
      reader_->rewind();
      firstPage_ = true;
    }
    const auto page = reader_->next(kPageItems);
    if (page.empty() && !firstPage_)
      return endShopFile();
    std::vector<std::string> ignored;  // the items' notes, taken in the items' pass
    const auto items = shopPage(page, ignored);
    daemon::ShopFile f;
    try {
      f = shopFile_ == 1 ? daemon::wooCommerceCsvWithColumns(items, options_, wooColumns_)
                         : file.build(items, options_);
    } catch (const daemon::ExportError& e) {
      if (!firstPage_)
        throw;  // a page after the first: half-way, the download is cut
      // A file the settings cannot make (no public address) is left out, as at the station.
      shopNotes_.append("Note: " + std::string(file.name) + " left out: " + e.what() + "\n");
      nextShopFile();
      return {};
    }
    for (const auto& w : f.warnings)
      shopNotes_.append("Note: " + std::string(file.name) + ": " + w + "\n");
    // Every page is a whole file; the pages after the first lose their header line, which
    // must be the first's (the columns are fixed).
    const auto eol = f.bytes.find('\n');
    const std::string header =
        f.bytes.substr(0, eol == std::string::npos ? f.bytes.size() : eol + 1);
    std::string piece;
    std::string body;
    if (firstPage_) {
      piece = zip_.begin(file.name);
      shopOpen_ = true;
      firstPage_ = false;
      header_ = header;
      body = std::move(f.bytes);
    } else {
      if (header != header_)
        throw std::logic_error(std::string("a page of ") + file.name +
                               " has other columns than the first");
      body = f.bytes.substr(header.size());
    }
    zip_.add(body);
    piece += body;
    if (page.empty())  // no item at all: the header is the file
      piece += endShopFile();
    return piece;
  }

  std::string endShopFile() {
    std::string d = zip_.end();
    nextShopFile();
    return d;
  }
  void nextShopFile() {
    shopOpen_ = false;
    if (++shopFile_ == daemon::catalogShopFiles().size())
      phase_ = Phase::kReadme;
  }

  static std::vector<daemon::ExportItem> shopPage(const std::vector<HubItem>& page,
                                                  std::vector<std::string>& notes) {
    std::vector<daemon::Item> items;
    std::vector<std::optional<nlohmann::json>> guides;
    std::map<std::int64_t, std::string> labels;
    for (const auto& h : page) {
      items.push_back(catalogItemOf(h));
      guides.push_back(sizeGuideOf(h));
      labels[h.id] = labelOf(h);
    }
    return daemon::shopItems(items, guides, notes,
                             [&](const daemon::Item& it) { return labels.at(it.id); });
  }

  std::unique_ptr<ApprovedReader> reader_;
  daemon::ShopOptions options_;
  std::string heading_;
  std::shared_ptr<daemon::StreamSink> sink_;
  daemon::DownloadSink& download_;
  std::shared_ptr<void> slot_;

  daemon::ZipWriter zip_;
  Phase phase_ = Phase::kItems;
  std::vector<HubItem> page_;
  std::size_t at_ = 0;
  std::size_t exported_ = 0;
  std::set<std::string> wooColumns_;
  std::size_t shopFile_ = 0;
  bool shopOpen_ = false;
  bool firstPage_ = true;
  std::string header_;
  daemon::SpillBuffer itemNotes_, patternNotes_, shopNotes_;
};

}  // namespace

void streamChainCatalogZip(std::unique_ptr<ApprovedReader> reader, daemon::ShopOptions options,
                           std::string heading, std::shared_ptr<daemon::StreamSink> sink,
                           daemon::DownloadSink& download, std::shared_ptr<void> slot) {
  auto stream = std::make_shared<ChainCatalogZipStream>(
      std::move(reader), std::move(options), std::move(heading), sink, download, std::move(slot));
  daemon::Response head{http::status::ok, 11};
  head.set(http::field::content_disposition, "attachment; filename=\"catalog.zip\"");
  head.set(http::field::cache_control, "no-store");
  head.set(http::field::content_type, "application/zip");
  head.set(http::field::transfer_encoding, "chunked");
  sink->writeHeader(std::move(head));
  stream->next();
}

}  // namespace garmcap::hub
