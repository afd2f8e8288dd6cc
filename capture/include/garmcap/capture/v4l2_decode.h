#pragma once
// Turning V4L2 buffers into BGR images: MJPEG validity checks (cheap UVC cameras deliver
// truncated or garbage JPEGs, which must be dropped, not decoded: ustreamer's rules), MJPEG and
// YUYV (YUV 4:2:2 packed) decoding. Pure functions, no device.

#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <string>
#include <vector>

namespace garmcap::capture {

/// "MJPG", "YUYV", ... from a V4L2 fourcc.
std::string fourccToString(std::uint32_t fourcc);

enum class MjpegCheck {
  kOk,
  kTooSmall,       ///< fewer than kMinMjpegBytes: a stub the camera sent instead of a frame
  kNoStartMarker,  ///< does not begin with FF D8 (SOI)
  kBadEndMarker,   ///< does not end with FF D9 (EOI), after trailing zero padding
};

const char* toString(MjpegCheck check);

/// Smallest plausible JPEG frame (ustreamer drops frames under 125 bytes).
inline constexpr std::size_t kMinMjpegBytes = 125;

/// Checks the framing of one MJPEG frame (`bytes` = bytesused of the buffer). Zero bytes after
/// the EOI marker are accepted: UVC drivers pad buffers.
MjpegCheck checkMjpegFrame(std::span<const std::uint8_t> bytes);

/// Decodes a JPEG to BGR; returns an empty Mat when the data cannot be decoded. Call
/// checkMjpegFrame first; this does not repeat its checks.
cv::Mat decodeMjpeg(std::span<const std::uint8_t> bytes);

/// Decodes packed YUYV (Y0 U Y1 V per two pixels, `bytesPerLine` >= 2 * width) to BGR.
/// Returns an empty Mat when `bytes` is shorter than height * bytesPerLine or the size is odd.
cv::Mat decodeYuyv(std::span<const std::uint8_t> bytes, int width, int height, int bytesPerLine);

/// Encodes BGR to packed YUYV with `bytesPerLine` = 2 * width (BT.601 limited range, the
/// inverse of decodeYuyv). Used by the fake device and tests; width must be even.
std::vector<std::uint8_t> encodeYuyv(const cv::Mat& bgr);

}  // namespace garmcap::capture
