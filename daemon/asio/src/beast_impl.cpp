// Boost.Beast's non-template implementation, compiled once for the tree
// (daemon/asio/CMakeLists.txt).
#include <boost/beast/src.hpp>
