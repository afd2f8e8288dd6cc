#include "commands.h"

namespace garmcap::cli {

void addDraftCommands(CLI::App& /*app*/) {}

}  // namespace garmcap::cli
