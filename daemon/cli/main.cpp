// garmcap: the command-line tool for drafts, grading, calibration, rendering and the pipeline.
#include <cstdio>
#include <exception>

#include "commands.h"
#include "garmcap/pipeline/capture_pipeline.h"

int main(int argc, char** argv) {
  garmcap::pipeline::keepFrameMemoryMapped();
  CLI::App app{"garmcap: drafts, grading, calibration and capture for GarmCap Station"};
  app.require_subcommand(1);
  garmcap::cli::addDraftCommands(app);
  garmcap::cli::addDswCommands(app);
  garmcap::cli::addCalibCommands(app);
  garmcap::cli::addCaptureCommands(app);
  garmcap::cli::addPipelineCommands(app);
  garmcap::cli::addTapeCommands(app);
  garmcap::cli::addMarkerCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0: CLI11 prints them. Usage errors
    // (missing or unknown options, bad values) follow the same contract as every other error:
    // one "garmcap: error: ..." line on stderr and exit status 1.
    if (e.get_exit_code() == 0)
      return app.exit(e);
    std::fprintf(stderr, "garmcap: error: %s (see --help)\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "garmcap: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
