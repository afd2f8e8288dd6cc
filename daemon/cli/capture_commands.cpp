#include "commands.h"

namespace garmcap::cli {

void addCaptureCommands(CLI::App& /*app*/) {}

}  // namespace garmcap::cli
