#include "commands.h"

namespace garmcap::cli {

void addCalibCommands(CLI::App& /*app*/) {}

}  // namespace garmcap::cli
