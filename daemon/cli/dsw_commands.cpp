#include "commands.h"

namespace garmcap::cli {

void addDswCommands(CLI::App& /*app*/) {}

}  // namespace garmcap::cli
