// Placeholder translation unit until the first capture sources land.
namespace garmcap::capture {}
