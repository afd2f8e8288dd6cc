// garmcap tape: the shop's tape measure on the station's catalog file (issue 15 part 7), for a
// station whose daemon is stopped or from a script on the station itself. The checks and the
// fit are the daemon's own (daemon/tape.h); SQLite's WAL and busy timeout let it write beside a
// running garmcapd, which fits the corrections afresh at every filing and caches nothing of them.
// Over the network use `garmcapctl tape` (the same body, through the API).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/tape.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::cli {

namespace {

struct TapeOptions {
  std::string data, json;
  std::int64_t item = 0, remove = 0;
  bool list = false;
};

nlohmann::json readBody(const std::string& source) {
  std::stringstream text;
  if (source == "-") {
    text << std::cin.rdbuf();
  } else {
    if (!std::filesystem::exists(source))
      throw std::runtime_error(source + ": no such file");
    return drafts::readJsonFile(source);
  }
  auto j = nlohmann::json::parse(text.str(), nullptr, false);
  if (j.is_discarded())
    throw std::runtime_error("stdin: not JSON");
  return j;
}

void printTable(const nlohmann::json& rows, std::size_t taped) {
  std::printf("%-6s %-18s %3s %-12s %8s %6s %9s\n", "type", "measurement", "n", "kind", "offset",
              "scale", "LOO (cm)");
  for (const auto& c : rows) {
    if (c["kind"] == "none" && c.contains("reason")) {
      // "not_significant": the left-out error may be below the raw one, the bias is still
      // within its noise (docs/measurement_model.md, Tape corrections).
      std::printf("%-6s %-18s %3d %-12s (not applied, %s: left-out error %.2f cm, raw %.2f cm)\n",
                  c["type"].get<std::string>().c_str(), c["measurement"].get<std::string>().c_str(),
                  c["n"].get<int>(), "none",
                  c["reason"] == "not_significant" ? "bias not significant" : "no gain",
                  c["residual_cm"].get<double>(), c["raw_error_cm"].get<double>());
      continue;
    }
    if (c["kind"] == "none") {
      std::printf("%-6s %-18s %3d %-12s (tape %d more)\n", c["type"].get<std::string>().c_str(),
                  c["measurement"].get<std::string>().c_str(), c["n"].get<int>(), "none",
                  c["needs"].get<int>());
      continue;
    }
    std::printf("%-6s %-18s %3d %-12s %+8.2f %6.3f %9.2f\n", c["type"].get<std::string>().c_str(),
                c["measurement"].get<std::string>().c_str(), c["n"].get<int>(),
                c["kind"].get<std::string>().c_str(), c["offset_cm"].get<double>(),
                c["scale"].get<double>(), c["residual_cm"].get<double>());
  }
  std::printf("%zu taped measurement(s)\n", taped);
}

void runTape(const TapeOptions& o) {
  const auto file = std::filesystem::path(o.data) / "catalog.sqlite";
  if (!std::filesystem::exists(file))
    throw std::runtime_error("no catalog at " + file.string() +
                             " (--data must be the station's data directory)");
  daemon::Catalog catalog(file);
  if (o.list) {
    printTable(pipeline::correctionTableJson(daemon::tapeCorrections(catalog)),
               catalog.tapes().size());
    return;
  }
  if (o.remove > 0) {
    const int n = catalog.deleteTape(o.remove);
    if (n == 0)
      throw std::runtime_error("item " + std::to_string(o.remove) + " has no tape measurements");
    std::printf("removed %d tape measurement(s) of item %lld\n", n,
                static_cast<long long>(o.remove));
    return;
  }
  if (o.json.empty())
    throw std::runtime_error(
        "tape: give --json FILE|- (with --item or an \"item\" in it), --list "
        "or --delete ID");
  nlohmann::json body = readBody(o.json);
  if (o.item > 0) {
    if (!body.is_object() || !body.contains("measurements"))
      body = nlohmann::json{{"measurements", body}};
    body["item"] = o.item;
  }
  try {
    const daemon::TapeRequest request = daemon::parseTapeRequest(body);
    catalog.setTape(request.itemId, daemon::tapeEntriesFor(catalog, request));
    std::cout << nlohmann::json{{"item", request.itemId},
                                {"tape", daemon::tapeRowsJson(catalog.tapes(request.itemId))},
                                {"corrections",
                                 pipeline::correctionTableJson(daemon::tapeCorrections(catalog))}}
                     .dump(2)
              << "\n";
  } catch (const daemon::BadRequest& e) {
    throw std::runtime_error((o.json == "-" ? std::string("stdin") : o.json) + ": " + e.what());
  }
}

}  // namespace

void addTapeCommands(CLI::App& app) {
  auto o = std::make_shared<TapeOptions>();
  auto* tape = app.add_subcommand(
      "tape", "Record tape measurements of an item and list the corrections they make");
  tape->add_option("--data", o->data, "The station's data directory (holds catalog.sqlite)")
      ->required();
  tape->add_option("--item", o->item, "Item id (else the JSON's \"item\")");
  tape->add_option("--json", o->json,
                   "{\"item\": id, \"measurements\": {name: cm}} (or the map alone with --item); "
                   "- for stdin");
  tape->add_flag("--list", o->list, "List the corrections per type and measurement");
  tape->add_option("--delete", o->remove, "Remove an item's tape measurements");
  tape->callback([o] { runTape(*o); });
}

}  // namespace garmcap::cli
