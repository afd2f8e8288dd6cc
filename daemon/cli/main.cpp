// garmcap: the command-line tool for drafts, grading, calibration, rendering and the pipeline.
#include <cstdio>
#include <exception>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"garmcap: drafts, grading, calibration and capture for GarmCap Station"};
  app.require_subcommand(1);
  garmcap::cli::addDraftCommands(app);
  garmcap::cli::addDswCommands(app);
  garmcap::cli::addCalibCommands(app);
  garmcap::cli::addCaptureCommands(app);
  garmcap::cli::addPipelineCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "garmcap: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
