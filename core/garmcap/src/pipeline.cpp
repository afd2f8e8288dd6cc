// Placeholder translation unit until the first pipeline sources land.
namespace garmcap::pipeline {}
