// Boost.Asio's SSL implementation on OpenSSL, compiled once for the tree
// (daemon/asio/CMakeLists.txt).
#include <boost/asio/ssl/impl/src.hpp>
