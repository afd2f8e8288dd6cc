#pragma once
// Each module's subcommands of the `garmcap` CLI are registered by one function, defined in the
// file named beside it, so that the main stays a thin wiring of options (rpicam-apps' apps/).
// A subcommand's callback throws std::exception with a precise message on failure; main prints
// it as "garmcap: error: ..." and exits 1.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace garmcap::cli {

void addDraftCommands(CLI::App& app);  // draft_commands.cpp: draft, measure
void addDswCommands(CLI::App& app);    // dsw_commands.cpp: coords, grade, sizerun
void addCalibCommands(CLI::App& app);  // calib_commands.cpp: form, calibrate, calibrate-camera
// `rig` is the group main makes for the rig subcommands of both.
void addCaptureCommands(CLI::App& app, CLI::App& rig);  // capture_commands.cpp: render, rig make
void addPipelineCommands(CLI::App& app,
                         CLI::App& rig);  // pipeline_commands.cpp: capture, rig eval/crop
void addTapeCommands(CLI::App& app);      // tape_commands.cpp: tape (the station's catalog)
void addMarkerCommands(CLI::App& app);    // marker_commands.cpp: marker

// A camera frame file as the station's rigs read it (capture::loadRigImage): a cut JPEG is an
// error, not a partly grey frame that the pipeline would refuse for another reason ("not a green
// screen"). Throws drafts::FileError "<what>: <file>: <reason>". Defined in pipeline_commands.cpp.
cv::Mat readFrameFile(const std::filesystem::path& path, const std::string& what);

}  // namespace garmcap::cli
