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
  // One group, two owners: the simulator makes rigs, the pipeline evaluates and crops them.
  CLI::App* rig = app.add_subcommand(
      "rig", "Rigs of replayed images: make (simulator), eval and crop (pipeline)");
  rig->require_subcommand(1);
  garmcap::cli::addCaptureCommands(app, *rig);
  garmcap::cli::addPipelineCommands(app, *rig);
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
