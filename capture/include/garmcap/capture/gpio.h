#pragma once
// The station's push button, status LED and light relay: libgpiod 1.6 on hardware, or a
// simulated GPIO driven by tests and the HTTP API.
//
// Event-loop use (Boost.Asio in the daemon):
//   auto gpio = makeGpio(cfg);
//   posix::stream_descriptor sd(io, gpio->button().eventFd());   // the Button owns the fd:
//   sd.async_wait(wait_read, ...) -> for (auto& e : gpio->button().readEvents()) handle(e);
//   steady_timer at *gpio->button().nextDeadline() -> gpio->button().tick(steady_clock::now())
//   ... sd.release() before the Gpio is destroyed.
// Debouncing is done here in user space from the kernel's edge timestamps (libgpiod 1.6 has
// none): a level counts only once it has been stable for DebounceConfig::stable (30 ms).
//
// Threads: one thread at a time (the event loop); GpioSimulation's methods may be called from
// any thread. Errors: GpioError with a message naming the chip/line.

#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace garmcap::capture {

using GpioClock = std::chrono::steady_clock;  // CLOCK_MONOTONIC, like gpio event timestamps

class GpioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One raw edge of the button line, already converted to "pressed" polarity (active-low
/// buttons report active = true when pulled to ground).
struct ButtonEdge {
  GpioClock::time_point time;
  bool active = false;
};

/// A debounced event.
struct ButtonEvent {
  enum class Kind {
    kPressed,     ///< level became pressed (stable for the debounce time)
    kReleased,    ///< level became released
    kShortPress,  ///< released before the long-press time: "a press" for the station
    kLongPress,   ///< held for the long-press time (emitted while still held)
  };
  Kind kind;
  /// When it happened: the first edge of the stable level (kPressed/kReleased/kShortPress), or
  /// press time + longPress (kLongPress).
  GpioClock::time_point time;
  /// kReleased/kShortPress: how long the button was held.
  std::chrono::milliseconds held{0};
};

const char* toString(ButtonEvent::Kind kind);

struct DebounceConfig {
  std::chrono::milliseconds stable{30};  ///< a level must last this long to count
  std::chrono::milliseconds longPress{2000};
};

/// Pure debouncer over timestamped edges (no clock of its own, no I/O): unit-testable and
/// shared by the libgpiod and simulated back ends. Edges must come in time order; an edge older
/// than the last one is clamped to it.
class Debouncer {
 public:
  /// `initiallyPressed`: the line's level at start-up (a button held while the station starts
  /// is not a press, and never becomes a long press).
  explicit Debouncer(DebounceConfig config = {}, bool initiallyPressed = false);

  /// Feeds one raw edge; returns the events it settles (the previous level may become stable).
  std::vector<ButtonEvent> feed(const ButtonEdge& edge);
  /// Advances time without an edge: commits a level stable since `now - stable`, emits a
  /// long press that is due.
  std::vector<ButtonEvent> tick(GpioClock::time_point now);
  /// When tick() should next be called (pending level to confirm, long press to emit), or
  /// nullopt when nothing is pending.
  std::optional<GpioClock::time_point> nextDeadline() const;
  /// The debounced level.
  bool pressed() const { return stablePressed_; }
  const DebounceConfig& config() const { return config_; }

 private:
  void commit(bool active, GpioClock::time_point since, std::vector<ButtonEvent>& out);
  void emitLongIfDue(GpioClock::time_point now, std::vector<ButtonEvent>& out);

  DebounceConfig config_;
  bool stablePressed_ = false;
  bool rawActive_ = false;
  GpioClock::time_point rawSince_{};      // time of the last raw edge
  bool pending_ = false;                  // raw level differs from the stable one
  GpioClock::time_point pressedSince_{};  // start of the stable press
  bool longEmitted_ = false;
  GpioClock::time_point lastEdge_{};
};

/// The push button. Owns its event fd.
class Button {
 public:
  virtual ~Button() = default;
  /// Readable when raw edges are pending. Owned by the Button; wrap it in
  /// posix::stream_descriptor and release() it before the Button goes.
  virtual int eventFd() const = 0;
  /// Reads all pending edges without blocking, debounces them (then ticks to now) and returns
  /// the resulting events. Throws GpioError when the line cannot be read.
  virtual std::vector<ButtonEvent> readEvents() = 0;
  /// Timer callback: see Debouncer::tick.
  virtual std::vector<ButtonEvent> tick(GpioClock::time_point now) = 0;
  virtual std::optional<GpioClock::time_point> nextDeadline() const = 0;
  virtual bool pressed() const = 0;
};

/// A digital output: status LED or light relay.
class OutputLine {
 public:
  virtual ~OutputLine() = default;
  /// Logical on/off (polarity handled by the line's activeLow). Throws GpioError.
  virtual void set(bool on) = 0;
  virtual bool value() const = 0;
  /// "chip/line" for messages.
  virtual std::string name() const = 0;
};
using StatusLed = OutputLine;
using Relay = OutputLine;

/// Test/API hooks of the simulated GPIO. Thread-safe.
class GpioSimulation {
 public:
  virtual ~GpioSimulation() = default;
  /// Queues a raw edge (makes the button's fd readable).
  virtual void injectEdge(const ButtonEdge& edge) = 0;
  /// A clean press of `held` ending now: injects press at now-held and release at now.
  virtual void click(std::chrono::milliseconds held = std::chrono::milliseconds(100)) = 0;
  /// Output states as last set by the station.
  virtual bool ledOn() const = 0;
  virtual bool relayOn() const = 0;
};

/// A line found by name, optionally on one chip. `chip` is the chip's label (e.g.
/// "pinctrl-rp1") or name ("gpiochip0"), empty to search all chips; `line` is the line name
/// (e.g. "GPIO17"). Numbers are never used: they change between kernels.
struct GpioLineSpec {
  std::string chip;
  std::string line;
  bool activeLow = false;
};

struct GpioConfig {
  std::string backend = "simulated";  ///< "gpiod" or "simulated"
  GpioLineSpec button{"", "GPIO17", true};
  bool buttonPullUp = true;               ///< bias pull-up (button to ground)
  std::optional<GpioLineSpec> statusLed;  ///< absent: no LED fitted
  std::optional<GpioLineSpec> relay;      ///< absent: no relay fitted
  DebounceConfig debounce;
  std::string consumer = "garmcapd";
};

class Gpio {
 public:
  virtual ~Gpio() = default;
  virtual std::string backend() const = 0;
  virtual Button& button() = 0;
  /// nullptr when not configured.
  virtual OutputLine* statusLed() = 0;
  virtual OutputLine* relay() = 0;
  /// Non-null only for the simulated back end.
  virtual GpioSimulation* simulation() { return nullptr; }
};

/// Creates the GPIO back end. Throws GpioError naming the chip/line when a line is not found
/// (listing the chips seen) or cannot be requested; std::invalid_argument for an unknown
/// back-end name.
std::unique_ptr<Gpio> makeGpio(const GpioConfig& config);

}  // namespace garmcap::capture
