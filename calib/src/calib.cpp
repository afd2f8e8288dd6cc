// Placeholder translation unit until the first calib sources land.
namespace garmcap::calib {}
