#pragma once
// Throwaway TLS certificates for tests, made at test time with the openssl command in a folder
// of the caller's: a CA, a server certificate it signs for IP 127.0.0.1 and the name hub.test
// (EC P-256: fast), and a second CA that signed nothing. Valid for two days.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace garmcap::test {

struct TestCerts {
  std::filesystem::path caCert, caKey, serverCert, serverKey, otherCaCert, otherCaKey;

  explicit TestCerts(const std::filesystem::path& dir)
      : caCert(dir / "ca.pem"),
        caKey(dir / "ca.key"),
        serverCert(dir / "server.pem"),
        serverKey(dir / "server.key"),
        otherCaCert(dir / "other-ca.pem"),
        otherCaKey(dir / "other-ca.key") {
    std::filesystem::create_directories(dir);
    const std::string d = quoted(dir);
    const std::string log = quoted(dir / "openssl.log");
    const std::string ec = " -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes";
    std::ofstream(dir / "server.ext") << "subjectAltName=IP:127.0.0.1,DNS:hub.test\n";
    run("openssl req -x509" + ec + " -keyout " + quoted(caKey) + " -out " + quoted(caCert) +
            " -days 2 -subj '/CN=GarmCap test CA' >>" + log + " 2>&1",
        log);
    run("openssl req -x509" + ec + " -keyout " + quoted(otherCaKey) + " -out " +
            quoted(otherCaCert) + " -days 2 -subj '/CN=Another test CA' >>" + log + " 2>&1",
        log);
    run("openssl req -new" + ec + " -keyout " + quoted(serverKey) + " -out " + d +
            "/server.csr -subj '/CN=hub.test' >>" + log + " 2>&1",
        log);
    run("openssl x509 -req -in " + d + "/server.csr -CA " + quoted(caCert) + " -CAkey " +
            quoted(caKey) + " -CAcreateserial -days 2 -extfile " + d + "/server.ext -out " +
            quoted(serverCert) + " >>" + log + " 2>&1",
        log);
  }

 private:
  static std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }
  static void run(const std::string& command, const std::string& log) {
    if (std::system(command.c_str()) != 0)
      throw std::runtime_error("test certificates: failed: " + command + " (see " + log + ")");
  }
};

}  // namespace garmcap::test
