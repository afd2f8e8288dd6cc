#pragma once
// The one exception type of calib's input boundaries. `kind` lets the CLI, the daemon and the
// tests tell the bad-input cases apart; `what()` is the precise message for people.

#include <stdexcept>
#include <string>

namespace garmcap::calib {

enum class CalibErrorKind {
  kMeshNotClosed,      // the form mesh has open or non-manifold edges
  kMeshUnits,          // mesh size implausible for its declared units (e.g. metres read as cm)
  kSidecar,            // sidecar malformed or disagreeing with the mesh by more than 2%
  kFormNotRecognised,  // no torso/landmarks could be found on the mesh
  kNotGreenScreen,     // the frame border is not a green screen
  kNoFormInFrame,      // nothing (or too little) in front of the screen
  kFormCutOff,         // the silhouette touches the frame edge
  kFitFailed,          // the model silhouette does not match the observed one
  kCameraCalibration,  // chessboard calibration failed (too few boards, ...)
};

class CalibError : public std::runtime_error {
 public:
  CalibError(CalibErrorKind kind, const std::string& message)
      : std::runtime_error(message), kind_(kind) {}
  CalibErrorKind kind() const { return kind_; }

 private:
  CalibErrorKind kind_;
};

}  // namespace garmcap::calib
