#include "commands.h"

namespace garmcap::cli {

void addPipelineCommands(CLI::App& /*app*/) {}

}  // namespace garmcap::cli
