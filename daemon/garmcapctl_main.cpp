// garmcapctl: drive a running garmcapd over its HTTP API (docs/api.md).
//   garmcapctl status | press | capture-empty [--wait] | capture [--sku S] [--wait]
//   garmcapctl list [--q TEXT] [--type T] [--limit N] | show ID
//   garmcapctl export ID --what pattern.json|pattern.svg|pattern.dxf|pattern.pdf|sizeguide.csv|
//                     sizeguide.json|nested_grading.svg|.pdf|.dxf|marker.svg|.pdf|.dxf|.json|image
//                     [--size S] [--paper a4|letter|a0] [--width CM] [--sizes S,S]
//                     [--kind product] --out FILE
//   garmcapctl tape --json FILE|- [--item ID] | tape --list | tape --delete ID
// Options: --url http://127.0.0.1:8080 (env GARMCAPD_URL), --token T (env GARMCAPD_TOKEN).
// Exit status: 0 ok, 1 the API answered an error (printed), 2 cannot reach the daemon.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;

namespace {

struct Target {
  std::string host = "127.0.0.1";
  std::string port = "8080";
  std::string token;
};

struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Target parseUrl(const std::string& url) {
  const std::string prefix = "http://";
  if (url.rfind(prefix, 0) != 0)
    throw Failure("--url must start with http://, got " + url);
  std::string rest = url.substr(prefix.size());
  rest = rest.substr(0, rest.find('/'));
  Target t;
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos) {
    t.host = rest;
    t.port = "80";
  } else {
    t.host = rest.substr(0, colon);
    t.port = rest.substr(colon + 1);
  }
  if (t.host.size() > 2 && t.host.front() == '[')
    t.host = t.host.substr(1, t.host.size() - 2);
  return t;
}

http::response<http::string_body> request(const Target& t, http::verb verb, const std::string& path,
                                          const std::string& body = "") {
  asio::io_context io;
  asio::ip::tcp::resolver resolver(io);
  beast::tcp_stream stream(io);
  stream.expires_after(std::chrono::seconds(30));
  beast::error_code ec;
  auto results = resolver.resolve(t.host, t.port, ec);
  if (!ec)
    stream.connect(results, ec);
  if (ec)
    throw std::system_error(ec, "cannot reach garmcapd at " + t.host + ":" + t.port);
  http::request<http::string_body> req{verb, path, 11};
  req.set(http::field::host, t.host);
  req.set(http::field::user_agent, "garmcapctl");
  if (!t.token.empty())
    req.set(http::field::authorization, "Bearer " + t.token);
  if (!body.empty()) {
    req.set(http::field::content_type, "application/json");
    req.body() = body;
  }
  req.prepare_payload();
  http::write(stream, req, ec);
  if (ec)
    throw std::system_error(ec, "cannot send to garmcapd");
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(512u << 20);
  http::read(stream, buffer, parser, ec);
  if (ec)
    throw std::system_error(ec, "no answer from garmcapd");
  stream.socket().shutdown(asio::ip::tcp::socket::shutdown_both, ec);
  return parser.release();
}

nlohmann::json jsonOrThrow(const http::response<http::string_body>& res) {
  auto j = nlohmann::json::parse(res.body(), nullptr, false);
  if (res.result_int() >= 400) {
    std::string msg =
        j.is_object() && j.contains("error") ? j["error"].get<std::string>() : res.body();
    throw Failure("HTTP " + std::to_string(res.result_int()) + ": " + msg);
  }
  if (j.is_discarded())
    throw Failure("garmcapd answered something that is not JSON");
  return j;
}

// A GET that waits out a busy station: a 503 with Retry-After (one marker is laid at a time)
// is tried again after the seconds it names (at most 30), up to kBusyAttempts times, saying so on
// stderr; any other answer, or the last 503, is returned as it is.
constexpr int kBusyAttempts = 12;

http::response<http::string_body> getWaitingOutBusy(const Target& t, const std::string& path) {
  for (int attempt = 1;; ++attempt) {
    auto res = request(t, http::verb::get, path);
    const auto retryAfter = res.find(http::field::retry_after);
    if (res.result() != http::status::service_unavailable || retryAfter == res.end() ||
        attempt == kBusyAttempts)
      return res;
    int seconds = 0;
    try {
      seconds = std::clamp(std::stoi(std::string(retryAfter->value())), 0, 30);
    } catch (const std::exception&) {
      return res;  // not delta-seconds (an HTTP date): leave the answer to the caller
    }
    const auto j = nlohmann::json::parse(res.body(), nullptr, false);
    const std::string why = j.is_object() && j.contains("error") && j["error"].is_string()
                                ? j["error"].get<std::string>()
                                : std::string("busy");
    std::cerr << "garmcapctl: the station is busy (" << why << "); trying again in " << seconds
              << " s (" << attempt << " of " << kBusyAttempts - 1 << ")\n";
    std::this_thread::sleep_for(std::chrono::seconds(seconds));
  }
}

nlohmann::json waitForJob(const Target& t, std::int64_t id, int timeoutS) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeoutS);
  while (true) {
    auto j = jsonOrThrow(request(t, http::verb::get, "/api/jobs/" + std::to_string(id)));
    const std::string state = j.value("state", "");
    if (state == "done" || state == "failed")
      return j;
    if (std::chrono::steady_clock::now() > deadline)
      throw Failure("job " + std::to_string(id) + " still " + state + " after " +
                    std::to_string(timeoutS) + " s");
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

std::string urlEncode(const std::string& s) {
  std::string out;
  char buf[4];
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out.push_back(static_cast<char>(c));
    } else {
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      out += buf;
    }
  }
  return out;
}

// The item files `export --what` fetches: /api/items/ID/<name> (docs/api.md).
const std::vector<std::string> kExportFiles = {
    "pattern.json",       "pattern.svg",   "pattern.dxf",        "pattern.pdf",
    "sizeguide.json",     "sizeguide.csv", "nested_grading.svg", "nested_grading.pdf",
    "nested_grading.dxf", "marker.svg",    "marker.pdf",         "marker.dxf",
    "marker.json"};

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names)
    out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"garmcapctl: control a running garmcapd over its HTTP API"};
  app.require_subcommand(1);
  std::string url =
      std::getenv("GARMCAPD_URL") ? std::getenv("GARMCAPD_URL") : "http://127.0.0.1:8080";
  std::string token = std::getenv("GARMCAPD_TOKEN") ? std::getenv("GARMCAPD_TOKEN") : "";
  app.add_option("--url", url, "daemon URL");
  app.add_option("--token", token, "bearer token");

  bool wait = false;
  int timeoutS = 300;
  std::string sku, q, type, what = "pattern.json", size, kind = "product", out, paper, width, sizes;
  int limit = 20;
  std::int64_t id = 0;
  auto* status = app.add_subcommand("status", "station state, queue, camera");
  auto* press = app.add_subcommand("press", "simulated button press");
  auto* empty = app.add_subcommand("capture-empty", "capture the bare form (calibration)");
  auto* capture = app.add_subcommand("capture", "capture a garment");
  capture->add_option("--sku", sku, "SKU typed or scanned");
  for (auto* c : {press, empty, capture}) {
    c->add_flag("--wait", wait, "wait until the job is done or failed");
    c->add_option("--timeout", timeoutS, "seconds to wait");
  }
  auto* list = app.add_subcommand("list", "list catalog items");
  list->add_option("--q", q, "search text");
  list->add_option("--type", type, "top, dress, skirt, pants");
  list->add_option("--limit", limit, "page size");
  auto* show = app.add_subcommand("show", "one item as JSON");
  show->add_option("id", id)->required();
  auto* exp = app.add_subcommand("export", "download an item's pattern, size guide or image");
  exp->add_option("id", id)->required();
  exp->add_option("--what", what,
                  "pattern.json|svg|dxf|pdf, sizeguide.json|csv, nested_grading.svg|pdf|dxf, "
                  "marker.svg|pdf|dxf|json, image");
  exp->add_option("--size", size, "pattern size (default: as measured)");
  exp->add_option("--paper", paper, "pattern.pdf tiled for a4, letter or a0 (default a4)");
  exp->add_option("--width", width, "marker: fabric width in cm (default 150)");
  exp->add_option("--sizes", sizes, "marker: sizes to lay, comma separated (default: as measured)");
  exp->add_option("--kind", kind, "image kind (product, cutout, dressed, ...)");
  exp->add_option("--out", out, "output file (default: stdout)");
  // The shop's tape measure (issue 15 part 7): the body is {"item": id, "measurements": {name:
  // cm}}; with --item the file may hold the measurements alone. Through the daemon, which owns
  // the catalog's one writer connection and checks every value (docs/api.md).
  std::string tapeJson;
  bool tapeList = false;
  std::int64_t tapeItem = 0, tapeDelete = 0;
  auto* tape = app.add_subcommand("tape", "record tape measurements, list the corrections");
  tape->add_option("--json", tapeJson, "file with the taped measurements, - for stdin");
  tape->add_option("--item", tapeItem, "item id (else the JSON's \"item\")");
  tape->add_flag("--list", tapeList, "list taped measurements and the corrections per type");
  tape->add_option("--delete", tapeDelete, "remove an item's taped measurements");
  CLI11_PARSE(app, argc, argv);

  try {
    Target t = parseUrl(url);
    t.token = token;
    nlohmann::json result;
    auto submit = [&](const std::string& path, const std::string& body) {
      auto j = jsonOrThrow(request(t, http::verb::post, path, body));
      if (wait && j.contains("job")) {
        j = waitForJob(t, j["job"].get<std::int64_t>(), timeoutS);
        std::cout << j.dump(2) << "\n";
        return j.value("state", "") == "done" ? 0 : 1;
      }
      std::cout << j.dump(2) << "\n";
      return 0;
    };
    if (*status) {
      std::cout << jsonOrThrow(request(t, http::verb::get, "/api/status")).dump(2) << "\n";
    } else if (*press) {
      return submit("/api/button", "");
    } else if (*empty) {
      return submit("/api/capture/empty", "");
    } else if (*capture) {
      return submit("/api/capture", sku.empty() ? "" : nlohmann::json{{"sku", sku}}.dump());
    } else if (*list) {
      std::string path = "/api/items?limit=" + std::to_string(limit);
      if (!q.empty())
        path += "&q=" + urlEncode(q);
      if (!type.empty())
        path += "&type=" + urlEncode(type);
      auto j = jsonOrThrow(request(t, http::verb::get, path));
      for (const auto& it : j["items"])
        std::cout << it["id"] << "\t" << it["sku"].get<std::string>() << "\t"
                  << it["type"].get<std::string>() << "\t" << it["status"].get<std::string>()
                  << "\t" << it["title"].get<std::string>() << "\n";
      std::cout << j["total"] << " item(s)\n";
    } else if (*show) {
      std::cout
          << jsonOrThrow(request(t, http::verb::get, "/api/items/" + std::to_string(id))).dump(2)
          << "\n";
    } else if (*tape) {
      if (tapeList) {
        auto j = jsonOrThrow(request(t, http::verb::get, "/api/tape"));
        std::printf("%-6s %-18s %3s %-12s %8s %6s %9s\n", "type", "measurement", "n", "kind",
                    "offset", "scale", "LOO (cm)");
        for (const auto& c : j["corrections"]) {
          if (c["kind"] == "none") {
            std::printf("%-6s %-18s %3d %-12s (tape %d more)\n",
                        c["type"].get<std::string>().c_str(),
                        c["measurement"].get<std::string>().c_str(), c["n"].get<int>(), "none",
                        c["needs"].get<int>());
            continue;
          }
          std::printf("%-6s %-18s %3d %-12s %+8.2f %6.3f %9.2f\n",
                      c["type"].get<std::string>().c_str(),
                      c["measurement"].get<std::string>().c_str(), c["n"].get<int>(),
                      c["kind"].get<std::string>().c_str(), c["offset_cm"].get<double>(),
                      c["scale"].get<double>(), c["residual_cm"].get<double>());
        }
        std::printf("%zu taped measurement(s)\n", j["tape"].size());
      } else if (tapeDelete > 0) {
        std::cout << jsonOrThrow(
                         request(t, http::verb::delete_, "/api/tape/" + std::to_string(tapeDelete)))
                         .dump(2)
                  << "\n";
      } else {
        if (tapeJson.empty())
          throw Failure("tape: give --json FILE|-, --list or --delete ID");
        std::stringstream text;
        if (tapeJson == "-") {
          text << std::cin.rdbuf();
        } else {
          std::ifstream f(tapeJson);
          if (!f)
            throw Failure("tape: cannot read " + tapeJson);
          text << f.rdbuf();
        }
        auto body = nlohmann::json::parse(text.str(), nullptr, false);
        if (body.is_discarded() || !body.is_object())
          throw Failure("tape: " + tapeJson + " is not a JSON object");
        if (tapeItem > 0) {
          if (!body.contains("measurements"))
            body = nlohmann::json{{"measurements", body}};
          body["item"] = tapeItem;
        }
        std::cout << jsonOrThrow(request(t, http::verb::post, "/api/tape", body.dump())).dump(2)
                  << "\n";
      }
    } else if (*exp) {
      std::string path = "/api/items/" + std::to_string(id) + "/";
      if (what == "image")
        path += "images/" + urlEncode(kind);
      else if (std::find(kExportFiles.begin(), kExportFiles.end(), what) != kExportFiles.end())
        path += what;
      else
        throw Failure("--what must be one of " + joined(kExportFiles) + " or image");
      // The daemon checks every value and names what is wrong (docs/exports.md).
      std::vector<std::string> query;
      const bool pdf = what == "pattern.pdf", marker = what.rfind("marker.", 0) == 0;
      if (!size.empty())
        query.push_back("size=" + urlEncode(size));
      if (!paper.empty() && !pdf)
        throw Failure("--paper goes with --what pattern.pdf");
      if (!paper.empty())
        query.push_back("paper=" + urlEncode(paper));
      if ((!width.empty() || !sizes.empty()) && !marker)
        throw Failure("--width and --sizes go with --what marker.*");
      if (!width.empty())
        query.push_back("width=" + urlEncode(width));
      if (!sizes.empty())
        query.push_back("sizes=" + urlEncode(sizes));
      for (std::size_t i = 0; i < query.size(); ++i)
        path += (i == 0 ? "?" : "&") + query[i];
      auto res = getWaitingOutBusy(t, path);
      if (res.result_int() >= 400)
        jsonOrThrow(res);
      if (out.empty()) {
        std::cout << res.body();
      } else {
        std::ofstream f(out, std::ios::binary);
        f << res.body();
        if (!f)
          throw Failure("cannot write " + out);
        std::cerr << "wrote " << out << " (" << res.body().size() << " bytes)\n";
      }
    }
    return 0;
  } catch (const Failure& e) {
    std::cerr << "garmcapctl: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "garmcapctl: " << e.what() << "\n";
    return 2;
  }
}
