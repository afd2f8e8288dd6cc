#include "garmcap/capture/v4l2_decode.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace garmcap::capture {

std::string fourccToString(std::uint32_t fourcc) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xFFu);
    s[static_cast<std::size_t>(i)] = (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

const char* toString(MjpegCheck check) {
  switch (check) {
    case MjpegCheck::kOk:
      return "ok";
    case MjpegCheck::kTooSmall:
      return "too small";
    case MjpegCheck::kNoStartMarker:
      return "no JPEG start marker (FFD8)";
    case MjpegCheck::kBadEndMarker:
      return "no JPEG end marker (FFD9): truncated frame";
  }
  return "?";
}

MjpegCheck checkMjpegFrame(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kMinMjpegBytes) {
    return MjpegCheck::kTooSmall;
  }
  if (bytes[0] != 0xFF || bytes[1] != 0xD8) {
    return MjpegCheck::kNoStartMarker;
  }
  // UVC payloads are often padded with zeros after EOI; look past them.
  std::size_t end = bytes.size();
  while (end > 2 && bytes[end - 1] == 0x00) {
    --end;
  }
  if (end < 4 || bytes[end - 2] != 0xFF || bytes[end - 1] != 0xD9) {
    return MjpegCheck::kBadEndMarker;
  }
  return MjpegCheck::kOk;
}

cv::Mat decodeMjpeg(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) {
    return {};
  }
  // imdecode takes a Mat header over the bytes; no copy.
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1,
                    const_cast<std::uint8_t*>(bytes.data()));
  try {
    return cv::imdecode(raw, cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    // libjpeg errors surface as cv::Exception on some builds; a bad frame is a value here.
    return {};
  }
}

cv::Mat decodeYuyv(std::span<const std::uint8_t> bytes, int width, int height, int bytesPerLine) {
  if (width <= 0 || height <= 0 || width % 2 != 0 || bytesPerLine < 2 * width) {
    return {};
  }
  const auto needed = static_cast<std::size_t>(height) * static_cast<std::size_t>(bytesPerLine);
  if (bytes.size() < needed) {
    return {};
  }
  const cv::Mat packed(height, width, CV_8UC2, const_cast<std::uint8_t*>(bytes.data()),
                       static_cast<std::size_t>(bytesPerLine));
  cv::Mat bgr;
  cv::cvtColor(packed, bgr, cv::COLOR_YUV2BGR_YUYV);
  return bgr;
}

std::vector<std::uint8_t> encodeYuyv(const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3 && bgr.cols % 2 == 0);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(bgr.rows) *
                                static_cast<std::size_t>(bgr.cols) * 2);
  auto clamp8 = [](double v) {
    return static_cast<std::uint8_t>(std::clamp(static_cast<int>(v + 0.5), 0, 255));
  };
  std::size_t k = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    const auto* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; x += 2) {
      double ys[2];
      double u = 0.0;
      double v = 0.0;
      for (int i = 0; i < 2; ++i) {
        const double b = row[x + i][0];
        const double g = row[x + i][1];
        const double r = row[x + i][2];
        ys[i] = 16.0 + 0.257 * r + 0.504 * g + 0.098 * b;
        u += 128.0 - 0.148 * r - 0.291 * g + 0.439 * b;
        v += 128.0 + 0.439 * r - 0.368 * g - 0.071 * b;
      }
      out[k++] = clamp8(ys[0]);
      out[k++] = clamp8(u / 2.0);
      out[k++] = clamp8(ys[1]);
      out[k++] = clamp8(v / 2.0);
    }
  }
  return out;
}

}  // namespace garmcap::capture
