// The hub over TLS: the hub serving HTTPS on loopback (a real PostgreSQL) to a client that
// verifies it, while a plain-HTTP client (answered 400 in plain text), a TLS 1.1 client and a
// client that never starts its handshake are turned away without stopping it. Certificates are
// made at test time (common/test_certs.h). The [tls] configuration and the certificate and key
// checks at start are in hub_config_test.cpp (no database).
#include <gtest/gtest.h>

#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "../common/temp_folder.h"
#include "../common/test_certs.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_service.h"
#include "temp_postgres.h"

namespace garmcap::hub {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace ssl = asio::ssl;
namespace fs = std::filesystem;
using tcp = asio::ip::tcp;

// --- the hub serving HTTPS -------------------------------------------------------------------

struct Answer {
  int status = 0;
  std::string body;
};

// GET over TLS with the given client context; throws beast::system_error on a failed handshake.
Answer httpsGet(std::uint16_t port, ssl::context& ctx, const std::string& target) {
  asio::io_context io;
  beast::ssl_stream<beast::tcp_stream> stream(io, ctx);
  stream.set_verify_callback(ssl::host_name_verification("127.0.0.1"));
  beast::get_lowest_layer(stream).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  stream.handshake(ssl::stream_base::client);
  http::request<http::empty_body> req{http::verb::get, target, 11};
  req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  beast::error_code ec;
  stream.shutdown(ec);
  return {static_cast<int>(res.result_int()), res.body()};
}

// The browser log-in over TLS: POST /api/session's Set-Cookie.
std::string httpsLogInCookie(std::uint16_t port, ssl::context& ctx, const std::string& token) {
  asio::io_context io;
  beast::ssl_stream<beast::tcp_stream> stream(io, ctx);
  stream.set_verify_callback(ssl::host_name_verification("127.0.0.1"));
  beast::get_lowest_layer(stream).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  stream.handshake(ssl::stream_base::client);
  http::request<http::string_body> req{http::verb::post, "/api/session", 11};
  req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  req.set(http::field::content_type, "application/json");
  req.body() = nlohmann::json{{"token", token}}.dump();
  req.prepare_payload();
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  EXPECT_EQ(res.result_int(), 200u) << res.body();
  beast::error_code ec;
  stream.shutdown(ec);
  return std::string(res[http::field::set_cookie]);
}

// What a plain-HTTP client to the TLS port gets: the bytes the hub sends back before it closes;
// fails the test if the connection stays open 5 s.
std::string plainRequest(std::uint16_t port, const std::string& request) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  asio::write(stream.socket(), asio::buffer(request));
  std::string received;
  std::array<char, 512> chunk{};
  bool closed = false;
  stream.expires_after(std::chrono::seconds(5));
  std::function<void()> readMore = [&] {
    stream.async_read_some(asio::buffer(chunk), [&](beast::error_code ec, std::size_t n) {
      received.append(chunk.data(), n);
      if (!ec)
        return readMore();
      closed = ec != beast::error::timeout;
    });
  };
  readMore();
  io.run();
  EXPECT_TRUE(closed) << "the hub kept a plain-HTTP connection to its TLS port open";
  return received;
}

TEST(HubTls, ServesHttpsAndTurnsAwayPlainHttpOldTlsAndSilentClients) {
  if (!test::postgresBinDir())
    GTEST_SKIP() << "PostgreSQL server binaries not found under /usr/lib/postgresql";
  garmcap::testing::TempFolder dir{"garmcap-hubtls"};
  const garmcap::test::TestCerts certs(dir.path());
  test::TempPostgres pg;
  pg.createDatabase("hub_tls");
  HubConfig c;
  c.databaseUrl = pg.url("hub_tls");
  c.listenPort = 0;
  c.threads = 1;  // one thread: a client that hangs in its handshake would block everything
  c.tlsCertFile = certs.serverCert.string();
  c.tlsKeyFile = certs.serverKey.string();
  c.adminTokenSha256 = tokenHash("tls-admin");
  c.validate();
  HubService service(c);
  service.start();
  const auto port = service.port();

  // A client that connects and sends nothing holds no thread.
  asio::io_context io;
  tcp::socket silent(io);
  silent.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));

  ssl::context trusting(ssl::context::tls_client);
  trusting.set_verify_mode(ssl::verify_peer);
  trusting.load_verify_file(certs.caCert.string());
  const Answer health = httpsGet(port, trusting, "/api/hub/health");
  EXPECT_EQ(health.status, 200);
  EXPECT_EQ(nlohmann::json::parse(health.body).value("ok", false), true) << health.body;

  // Over HTTPS the browser's session cookie is Secure: it never goes out in clear.
  const std::string cookie = httpsLogInCookie(port, trusting, "tls-admin");
  EXPECT_NE(cookie.find("; Secure"), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos) << cookie;

  // Plain HTTP is answered in plain text, once, and the connection closed (nginx's 497 idea).
  for (const std::string& request :
       {std::string("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"),
        std::string("GET /api/hub/health HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: "
                    "keep-alive\r\n\r\nGET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")}) {
    const std::string plain = plainRequest(port, request);
    EXPECT_EQ(plain.rfind("HTTP/1.1 400 Bad Request\r\n", 0), 0u) << plain;
    EXPECT_NE(plain.find("Content-Type: text/plain"), std::string::npos) << plain;
    EXPECT_NE(plain.find("Connection: close"), std::string::npos) << plain;
    EXPECT_NE(plain.find("speaks HTTPS only"), std::string::npos) << plain;
    EXPECT_EQ(plain.find("HTTP/1.1", 1), std::string::npos) << "one answer only: " << plain;
    const auto head = plain.find("\r\n\r\n");
    ASSERT_NE(head, std::string::npos) << plain;
    const auto length = plain.find("Content-Length: ");
    ASSERT_NE(length, std::string::npos) << plain;
    EXPECT_EQ(std::stoul(plain.substr(length + 16)), plain.size() - head - 4) << plain;
  }

  ssl::context old(ssl::context::tls_client);
  old.set_verify_mode(ssl::verify_peer);
  old.load_verify_file(certs.caCert.string());
  // Security level 0 lets this client offer TLS 1.1 at all under OpenSSL 3; the hub must say no.
  SSL_CTX_set_security_level(old.native_handle(), 0);
  SSL_CTX_set_min_proto_version(old.native_handle(), TLS1_VERSION);
  SSL_CTX_set_max_proto_version(old.native_handle(), TLS1_1_VERSION);
  EXPECT_THROW(httpsGet(port, old, "/api/hub/health"), boost::system::system_error);

  ssl::context otherCa(ssl::context::tls_client);
  otherCa.set_verify_mode(ssl::verify_peer);
  otherCa.load_verify_file(certs.otherCaCert.string());
  EXPECT_THROW(httpsGet(port, otherCa, "/api/hub/health"), boost::system::system_error);

  // Still serving, on its one thread.
  EXPECT_EQ(httpsGet(port, trusting, "/api/hub/health").status, 200);
  service.stop();
}

}  // namespace
}  // namespace garmcap::hub
