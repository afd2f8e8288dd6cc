// Boost.Asio's non-template implementation, compiled once for the tree (daemon/asio/CMakeLists.txt
// says why and what every user of Asio must link).
#include <boost/asio/impl/src.hpp>
