// libgpiod 1.6 (the v1 C++ API: gpiod::chip / gpiod::line) behind GpioDevice. libgpiod throws
// std::system_error; it is caught here and turned into GpioError naming the chip and line.

#include <chrono>
#include <gpiod.hpp>
#include <system_error>

#include "garmcap/capture/gpio_device.h"

namespace garmcap::capture {
namespace {

std::string where(const GpioLineLocation& line) {
  return "GPIO line '" + line.lineName + "' (" + line.chipName + " [" + line.chipLabel +
         "] offset " + std::to_string(line.offset) + ")";
}

[[noreturn]] void rethrow(const GpioLineLocation& line, const char* what,
                          const std::system_error& e) {
  const int err = e.code().value();
  std::string reason = e.what();
  if (err == EBUSY) {
    reason = "busy: another program has requested it";
  } else if (err == EACCES || err == EPERM) {
    reason = "permission denied (is the user in group 'gpio'?)";
  }
  throw GpioError(where(line) + ": " + what + ": " + reason);
}

class LibgpiodInput final : public GpioInputLine {
 public:
  LibgpiodInput(gpiod::chip chip, gpiod::line line, GpioLineLocation location)
      : chip_(std::move(chip)), line_(std::move(line)), location_(std::move(location)) {}
  ~LibgpiodInput() override {
    try {
      line_.release();
    } catch (const std::system_error&) {
      // Releasing closes the fd; nothing useful to do if the kernel refuses on the way out.
    }
  }

  int fd() const override { return line_.event_get_fd(); }

  std::vector<ButtonEdge> readEdges() override {
    std::vector<ButtonEdge> out;
    try {
      // The kernel queues events in order; drain without blocking.
      while (line_.event_wait(std::chrono::nanoseconds(0))) {
        const gpiod::line_event ev = line_.event_read();
        // Event timestamps are CLOCK_MONOTONIC since Linux 5.7, the clock of steady_clock.
        const GpioClock::time_point t(
            std::chrono::duration_cast<GpioClock::duration>(ev.timestamp));
        out.push_back({t, ev.event_type == gpiod::line_event::RISING_EDGE});
      }
    } catch (const std::system_error& e) {
      rethrow(location_, "reading events", e);
    }
    return out;
  }

  bool value() override {
    try {
      return line_.get_value() != 0;
    } catch (const std::system_error& e) {
      rethrow(location_, "reading the value", e);
    }
  }

 private:
  gpiod::chip chip_;
  gpiod::line line_;
  GpioLineLocation location_;
};

class LibgpiodOutput final : public GpioOutputHandle {
 public:
  LibgpiodOutput(gpiod::chip chip, gpiod::line line, GpioLineLocation location)
      : chip_(std::move(chip)), line_(std::move(line)), location_(std::move(location)) {}
  ~LibgpiodOutput() override {
    try {
      line_.set_value(0);  // lights off when the station stops
      line_.release();
    } catch (const std::system_error&) {
      // See LibgpiodInput's destructor.
    }
  }
  void set(bool on) override {
    try {
      line_.set_value(on ? 1 : 0);
    } catch (const std::system_error& e) {
      rethrow(location_, "setting the value", e);
    }
  }

 private:
  gpiod::chip chip_;
  gpiod::line line_;
  GpioLineLocation location_;
};

class LibgpiodDevice final : public GpioDevice {
 public:
  std::string name() const override { return "gpiod"; }

  std::vector<GpioChipInfo> chips() override {
    std::vector<GpioChipInfo> out;
    try {
      for (const auto& chip : gpiod::make_chip_iter()) {
        GpioChipInfo info{chip.name(), chip.label(), {}};
        const unsigned n = chip.num_lines();
        info.lineNames.reserve(n);
        for (unsigned i = 0; i < n; ++i) {
          info.lineNames.push_back(chip.get_line(i).name());
        }
        out.push_back(std::move(info));
      }
    } catch (const std::system_error& e) {
      throw GpioError(std::string("cannot list GPIO chips: ") + e.what() +
                      " (is the user in group 'gpio'?)");
    }
    return out;
  }

  std::unique_ptr<GpioInputLine> requestInput(const GpioLineLocation& location,
                                              const GpioInputRequest& request) override {
    try {
      gpiod::chip chip(location.chipName, gpiod::chip::OPEN_BY_NAME);
      gpiod::line line = chip.get_line(location.offset);
      gpiod::line_request config;
      config.consumer = request.consumer;
      config.request_type = gpiod::line_request::EVENT_BOTH_EDGES;
      if (request.activeLow) {
        config.flags |= gpiod::line_request::FLAG_ACTIVE_LOW;
      }
      if (request.pullUp) {
        config.flags |= gpiod::line_request::FLAG_BIAS_PULL_UP;
      }
      line.request(config);
      return std::make_unique<LibgpiodInput>(std::move(chip), std::move(line), location);
    } catch (const std::system_error& e) {
      rethrow(location, "requesting it for edge events", e);
    }
  }

  std::unique_ptr<GpioOutputHandle> requestOutput(const GpioLineLocation& location,
                                                  const GpioOutputRequest& request) override {
    try {
      gpiod::chip chip(location.chipName, gpiod::chip::OPEN_BY_NAME);
      gpiod::line line = chip.get_line(location.offset);
      gpiod::line_request config;
      config.consumer = request.consumer;
      config.request_type = gpiod::line_request::DIRECTION_OUTPUT;
      if (request.activeLow) {
        config.flags |= gpiod::line_request::FLAG_ACTIVE_LOW;
      }
      line.request(config, request.initial ? 1 : 0);
      return std::make_unique<LibgpiodOutput>(std::move(chip), std::move(line), location);
    } catch (const std::system_error& e) {
      rethrow(location, "requesting it as output", e);
    }
  }
};

}  // namespace

std::unique_ptr<GpioDevice> makeLibgpiodDevice() {
  return std::make_unique<LibgpiodDevice>();
}

}  // namespace garmcap::capture
