#pragma once
// The seam under the GPIO back ends: chip enumeration and line requests behind an interface,
// so that line lookup by chip label and line name, request flags, event draining and
// debouncing are tested without a kernel GPIO chip (Debian's kernel has neither gpio-mockup nor
// gpio-sim). Implementations: libgpiod 1.6 (gpiod::chip / gpiod::line) and SimulatedGpioDevice,
// which is also the station's simulated GPIO.

#include <memory>
#include <string>
#include <vector>

#include "garmcap/capture/gpio.h"

namespace garmcap::capture {

/// A GPIO chip as the kernel lists it: name "gpiochipN", label (driver's, e.g. "pinctrl-rp1"),
/// line names by offset (empty string for unnamed lines).
struct GpioChipInfo {
  std::string name;
  std::string label;
  std::vector<std::string> lineNames;
};

struct GpioLineLocation {
  std::string chipName;
  std::string chipLabel;
  unsigned offset = 0;
  std::string lineName;
};

/// Finds spec.line on the chip whose label or name is spec.chip (any chip when empty). Throws
/// GpioError naming the line and listing the chips seen when it is absent, or the chips when
/// the name is ambiguous across chips.
GpioLineLocation findGpioLine(const std::vector<GpioChipInfo>& chips, const GpioLineSpec& spec);

/// A requested input line with both-edge events.
class GpioInputLine {
 public:
  virtual ~GpioInputLine() = default;
  /// Readable when edges are pending; owned by this object.
  virtual int fd() const = 0;
  /// Drains pending edges without blocking, in logical polarity (active = pressed).
  virtual std::vector<ButtonEdge> readEdges() = 0;
  /// Current logical level.
  virtual bool value() = 0;
};

class GpioOutputHandle {
 public:
  virtual ~GpioOutputHandle() = default;
  virtual void set(bool on) = 0;
};

struct GpioInputRequest {
  bool activeLow = false;
  bool pullUp = false;
  std::string consumer;
};

struct GpioOutputRequest {
  bool activeLow = false;
  bool initial = false;
  std::string consumer;
};

class GpioDevice {
 public:
  virtual ~GpioDevice() = default;
  /// "gpiod" or "simulated".
  virtual std::string name() const = 0;
  /// Throws GpioError when the chips cannot be listed.
  virtual std::vector<GpioChipInfo> chips() = 0;
  /// Throws GpioError naming the line (busy, permission, missing chip).
  virtual std::unique_ptr<GpioInputLine> requestInput(const GpioLineLocation& line,
                                                      const GpioInputRequest& request) = 0;
  virtual std::unique_ptr<GpioOutputHandle> requestOutput(const GpioLineLocation& line,
                                                          const GpioOutputRequest& request) = 0;
  /// Non-null for the simulated device.
  virtual GpioSimulation* simulation() { return nullptr; }
};

/// libgpiod 1.6. Listing chips needs /dev/gpiochip*; without any, chips() returns none and
/// line lookup fails with "no GPIO chips found".
std::unique_ptr<GpioDevice> makeLibgpiodDevice();

/// A simulated set of chips. Edges injected through GpioSimulation reach the (single)
/// requested input line through an eventfd, exactly like kernel events reach the libgpiod fd.
class SimulatedGpioDevice final : public GpioDevice, public GpioSimulation {
 public:
  /// `ledLine`/`relayLine`: names of the lines GpioSimulation::ledOn/relayOn report.
  SimulatedGpioDevice(std::vector<GpioChipInfo> chips, std::string ledLine = {},
                      std::string relayLine = {});
  ~SimulatedGpioDevice() override;

  std::string name() const override { return "simulated"; }
  std::vector<GpioChipInfo> chips() override { return chips_; }
  std::unique_ptr<GpioInputLine> requestInput(const GpioLineLocation& line,
                                              const GpioInputRequest& request) override;
  std::unique_ptr<GpioOutputHandle> requestOutput(const GpioLineLocation& line,
                                                  const GpioOutputRequest& request) override;
  GpioSimulation* simulation() override { return this; }

  // GpioSimulation
  void injectEdge(const ButtonEdge& edge) override;
  void click(std::chrono::milliseconds held) override;
  bool ledOn() const override;
  bool relayOn() const override;

  // Test hooks.
  /// Requests of this line fail with `err` (EBUSY: "in use by another consumer").
  void failRequests(const std::string& lineName, int err);
  /// Output value by line name (logical).
  bool output(const std::string& lineName) const;
  /// Requests made, for checking flags: "chip/offset in|out activeLow pullUp consumer".
  std::vector<std::string> requestLog() const;

  struct State;  // shared with the line handles

 private:
  std::vector<GpioChipInfo> chips_;
  std::string ledLine_;
  std::string relayLine_;
  std::shared_ptr<State> state_;
};

/// The Gpio facade over any GpioDevice: looks up the lines of `config`, requests them, and
/// debounces the button. makeGpio() uses it with libgpiod or the simulated device.
std::unique_ptr<Gpio> makeDeviceGpio(std::unique_ptr<GpioDevice> device, const GpioConfig& config);

/// The simulated chips makeGpio("simulated") builds for `config`: one chip per distinct chip
/// name in the config (label "gpio-sim" when none), holding the configured line names.
std::vector<GpioChipInfo> simulatedChipsFor(const GpioConfig& config);

}  // namespace garmcap::capture
