#pragma once
// Everything that differs between libcamera versions, in one place. Debian 12 ships 0.0.3;
// Raspberry Pi OS ships newer ones (research/anchors_capture.md §1.1):
//  - 0.1: generateConfiguration takes Span<const StreamRole> (a std::vector still converts);
//  - 0.2: CameraConfiguration::transform became `orientation` (Orientation::Rotate0);
//  - 0.5: ExposureTimeMode/AnalogueGainMode must be Manual for ExposureTime/AnalogueGain to
//    stick (AeEnable alone is kept but means "both modes").
// Building against a newer libcamera means checking this file, nothing else.

#include <libcamera/camera.h>
#include <libcamera/control_ids.h>
#include <libcamera/controls.h>
#include <libcamera/version.h>

#include <memory>
#include <vector>

#define GARMCAP_LIBCAMERA_AT_LEAST(major, minor) \
  (LIBCAMERA_VERSION_MAJOR > (major) ||          \
   (LIBCAMERA_VERSION_MAJOR == (major) && LIBCAMERA_VERSION_MINOR >= (minor)))

namespace garmcap::capture::compat {

inline std::unique_ptr<libcamera::CameraConfiguration> generateConfiguration(
    libcamera::Camera& camera, libcamera::StreamRole role) {
  const std::vector<libcamera::StreamRole> roles{role};
  return camera.generateConfiguration(roles);
}

/// No rotation or flip: the station's geometry assumes the sensor's native orientation.
inline void setIdentityOrientation(libcamera::CameraConfiguration& config) {
#if GARMCAP_LIBCAMERA_AT_LEAST(0, 2)
  config.orientation = libcamera::Orientation::Rotate0;
#else
  config.transform = libcamera::Transform::Identity;
#endif
}

/// Adds what a newer libcamera needs besides AeEnable=false for a manual exposure.
inline void addManualExposureModes([[maybe_unused]] libcamera::ControlList& controls) {
#if GARMCAP_LIBCAMERA_AT_LEAST(0, 5)
  controls.set(libcamera::controls::ExposureTimeMode, libcamera::controls::ExposureTimeModeManual);
  controls.set(libcamera::controls::AnalogueGainMode, libcamera::controls::AnalogueGainModeManual);
#endif
}

}  // namespace garmcap::capture::compat
