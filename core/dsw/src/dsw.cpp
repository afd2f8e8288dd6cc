// Placeholder translation unit until the first dsw sources land.
namespace garmcap::dsw {}
