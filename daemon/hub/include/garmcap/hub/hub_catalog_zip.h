#pragma once
// The chain's catalog.zip written as it is read (docs/hub.md, "Patterns and catalog.zip"): the
// station's catalog.zip (export_catalog.h: the same entries in the same order, the same bytes in
// each) over the approved items of a snapshot, sent as an HTTP/1.1 chunked download through a
// ZipWriter (zip_writer.h), never held whole. In order:
//   1. items, in keyset pages of 500: each item's photos and pattern files (catalogItemFiles),
//      its blobs and patterns read one item at a time from the snapshot, one chunk per item;
//   2. shopify.csv, woocommerce.csv (its measurement columns gathered in 1), merchant.tsv, each
//      an entry written in pieces (data descriptor), a page of the snapshot per chunk;
//   3. README.txt, its notes kept meanwhile in SpillBuffers (a temporary file past 1 MiB);
//   4. the central directory (Zip64 records where the counts or offsets need them).
// Each piece is made only once the previous one is on the wire (DownloadSink), so the hub holds
// one item's files or one page of a shop file. The notes are known only at the end, so the
// response carries no X-Export-Warnings header (the station's in-memory catalog.zip does); they
// are in README.txt.

#include <memory>
#include <string>

#include "garmcap/daemon/download_sink.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/hub/hub_store.h"

namespace garmcap::hub {

/// Sends the 200 header and starts the download; `slot` is released when the download ends
/// (written, cut by a failure, or its client gone). Failures after the header cut the
/// connection before the last chunk.
void streamChainCatalogZip(std::unique_ptr<ApprovedReader> reader, daemon::ShopOptions options,
                           std::string heading, std::shared_ptr<daemon::StreamSink> sink,
                           daemon::DownloadSink& download, std::shared_ptr<void> slot);

}  // namespace garmcap::hub
