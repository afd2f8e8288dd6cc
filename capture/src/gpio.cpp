#include "garmcap/capture/gpio.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <set>

#include "garmcap/capture/gpio_device.h"

namespace garmcap::capture {

const char* toString(ButtonEvent::Kind kind) {
  switch (kind) {
    case ButtonEvent::Kind::kPressed:
      return "pressed";
    case ButtonEvent::Kind::kReleased:
      return "released";
    case ButtonEvent::Kind::kShortPress:
      return "short press";
    case ButtonEvent::Kind::kLongPress:
      return "long press";
  }
  return "?";
}

// --- Debouncer -----------------------------------------------------------------------------

Debouncer::Debouncer(DebounceConfig config, bool initiallyPressed)
    : config_(config),
      stablePressed_(initiallyPressed),
      rawActive_(initiallyPressed),
      longEmitted_(initiallyPressed) {}

void Debouncer::commit(bool active, GpioClock::time_point since, std::vector<ButtonEvent>& out) {
  using std::chrono::duration_cast;
  using std::chrono::milliseconds;
  pending_ = false;
  if (active == stablePressed_) {
    return;
  }
  stablePressed_ = active;
  if (active) {
    pressedSince_ = since;
    longEmitted_ = false;
    out.push_back({ButtonEvent::Kind::kPressed, since, milliseconds(0)});
    return;
  }
  const auto held = duration_cast<milliseconds>(since - pressedSince_);
  // A press that reached the long-press time before its release is a long press, even when
  // nobody ticked in between.
  if (!longEmitted_ && held >= config_.longPress) {
    longEmitted_ = true;
    out.push_back({ButtonEvent::Kind::kLongPress, pressedSince_ + config_.longPress, held});
  }
  out.push_back({ButtonEvent::Kind::kReleased, since, held});
  if (!longEmitted_) {
    out.push_back({ButtonEvent::Kind::kShortPress, since, held});
  }
  longEmitted_ = true;  // nothing more for this press
}

void Debouncer::emitLongIfDue(GpioClock::time_point now, std::vector<ButtonEvent>& out) {
  if (!stablePressed_ || longEmitted_) {
    return;
  }
  // A release that is still settling ends the press tentatively at its first edge.
  const auto end = (pending_ && !rawActive_) ? rawSince_ : now;
  if (end - pressedSince_ >= config_.longPress) {
    longEmitted_ = true;
    out.push_back({ButtonEvent::Kind::kLongPress, pressedSince_ + config_.longPress,
                   std::chrono::duration_cast<std::chrono::milliseconds>(config_.longPress)});
  }
}

std::vector<ButtonEvent> Debouncer::tick(GpioClock::time_point now) {
  std::vector<ButtonEvent> out;
  if (pending_ && now - rawSince_ >= config_.stable) {
    commit(rawActive_, rawSince_, out);
  }
  emitLongIfDue(now, out);
  return out;
}

std::vector<ButtonEvent> Debouncer::feed(const ButtonEdge& edge) {
  const auto t = std::max(edge.time, lastEdge_);
  lastEdge_ = t;
  std::vector<ButtonEvent> out = tick(t);
  // A repeated level means an opposite edge was lost in a bounce: restart the stability window.
  rawActive_ = edge.active;
  rawSince_ = t;
  pending_ = rawActive_ != stablePressed_;
  return out;
}

std::optional<GpioClock::time_point> Debouncer::nextDeadline() const {
  std::optional<GpioClock::time_point> next;
  if (pending_) {
    next = rawSince_ + config_.stable;
  }
  if (stablePressed_ && !longEmitted_ && !(pending_ && !rawActive_)) {
    const auto due = pressedSince_ + config_.longPress;
    next = next ? std::min(*next, due) : due;
  }
  return next;
}

// --- line lookup -----------------------------------------------------------------------------

GpioLineLocation findGpioLine(const std::vector<GpioChipInfo>& chips, const GpioLineSpec& spec) {
  if (spec.line.empty()) {
    throw GpioError("GPIO line name is empty (lines are found by name, e.g. \"GPIO17\")");
  }
  if (chips.empty()) {
    throw GpioError("GPIO line '" + spec.line +
                    "': no GPIO chips found (no /dev/gpiochip*; use the simulated GPIO "
                    "without hardware)");
  }
  std::string seen;
  bool chipMatched = spec.chip.empty();
  std::vector<GpioLineLocation> found;
  for (const auto& chip : chips) {
    seen += (seen.empty() ? "" : ", ") + chip.name + " [" + chip.label + "]";
    if (!spec.chip.empty() && spec.chip != chip.label && spec.chip != chip.name) {
      continue;
    }
    chipMatched = true;
    for (std::size_t i = 0; i < chip.lineNames.size(); ++i) {
      if (chip.lineNames[i] == spec.line) {
        found.push_back({chip.name, chip.label, static_cast<unsigned>(i), spec.line});
      }
    }
  }
  if (!chipMatched) {
    throw GpioError("GPIO chip '" + spec.chip + "' not found (chips: " + seen + ")");
  }
  if (found.empty()) {
    throw GpioError("GPIO line '" + spec.line + "' not found" +
                    (spec.chip.empty() ? std::string() : " on chip '" + spec.chip + "'") +
                    " (chips: " + seen + ")");
  }
  if (found.size() > 1) {
    std::string where;
    for (const auto& f : found) {
      where += (where.empty() ? "" : ", ") + f.chipName + " [" + f.chipLabel + "]";
    }
    throw GpioError("GPIO line '" + spec.line + "' exists on several chips (" + where +
                    "); name the chip by its label");
  }
  return found.front();
}

// --- simulated device --------------------------------------------------------------------------

struct SimulatedGpioDevice::State {
  mutable std::mutex mutex;
  int eventFd = -1;  // the input line's fd; -1 until requested
  std::deque<ButtonEdge> edges;
  bool level = false;
  std::map<std::string, bool> outputs;
  std::map<std::string, int> failures;
  std::vector<std::string> log;
};

namespace {

std::string requestError(const GpioLineLocation& line, int err) {
  const std::string where = "GPIO line '" + line.lineName + "' (" + line.chipName + " [" +
                            line.chipLabel + "] offset " + std::to_string(line.offset) + ")";
  if (err == EBUSY) {
    return where + " is busy: another program has requested it";
  }
  if (err == EACCES || err == EPERM) {
    return where + ": permission denied (is the user in group 'gpio'?)";
  }
  return where + ": " + std::strerror(err);
}

class SimulatedInputLine final : public GpioInputLine {
 public:
  explicit SimulatedInputLine(std::shared_ptr<SimulatedGpioDevice::State> state)
      : state_(std::move(state)) {}
  ~SimulatedInputLine() override {
    std::lock_guard lock(state_->mutex);
    ::close(state_->eventFd);
    state_->eventFd = -1;
    state_->edges.clear();
  }
  int fd() const override { return state_->eventFd; }
  std::vector<ButtonEdge> readEdges() override {
    std::lock_guard lock(state_->mutex);
    std::uint64_t counter = 0;
    // Non-blocking eventfd: EAGAIN when nothing is pending, which is fine.
    [[maybe_unused]] const auto n = ::read(state_->eventFd, &counter, sizeof(counter));
    std::vector<ButtonEdge> out(state_->edges.begin(), state_->edges.end());
    state_->edges.clear();
    return out;
  }
  bool value() override {
    std::lock_guard lock(state_->mutex);
    return state_->level;
  }

 private:
  std::shared_ptr<SimulatedGpioDevice::State> state_;
};

class SimulatedOutput final : public GpioOutputHandle {
 public:
  SimulatedOutput(std::shared_ptr<SimulatedGpioDevice::State> state, std::string line)
      : state_(std::move(state)), line_(std::move(line)) {}
  void set(bool on) override {
    std::lock_guard lock(state_->mutex);
    state_->outputs[line_] = on;
  }

 private:
  std::shared_ptr<SimulatedGpioDevice::State> state_;
  std::string line_;
};

}  // namespace

SimulatedGpioDevice::SimulatedGpioDevice(std::vector<GpioChipInfo> chips, std::string ledLine,
                                         std::string relayLine)
    : chips_(std::move(chips)),
      ledLine_(std::move(ledLine)),
      relayLine_(std::move(relayLine)),
      state_(std::make_shared<State>()) {}

SimulatedGpioDevice::~SimulatedGpioDevice() = default;

std::unique_ptr<GpioInputLine> SimulatedGpioDevice::requestInput(const GpioLineLocation& line,
                                                                 const GpioInputRequest& request) {
  std::lock_guard lock(state_->mutex);
  if (auto it = state_->failures.find(line.lineName); it != state_->failures.end()) {
    throw GpioError(requestError(line, it->second));
  }
  if (state_->eventFd >= 0) {
    throw GpioError(requestError(line, EBUSY));  // one button per simulated device
  }
  state_->eventFd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (state_->eventFd < 0) {
    throw GpioError(requestError(line, errno));
  }
  state_->log.push_back(line.chipName + "/" + std::to_string(line.offset) + " in" +
                        (request.activeLow ? " active-low" : "") +
                        (request.pullUp ? " pull-up" : "") + " " + request.consumer);
  return std::make_unique<SimulatedInputLine>(state_);
}

std::unique_ptr<GpioOutputHandle> SimulatedGpioDevice::requestOutput(
    const GpioLineLocation& line, const GpioOutputRequest& request) {
  std::lock_guard lock(state_->mutex);
  if (auto it = state_->failures.find(line.lineName); it != state_->failures.end()) {
    throw GpioError(requestError(line, it->second));
  }
  state_->outputs[line.lineName] = request.initial;
  state_->log.push_back(line.chipName + "/" + std::to_string(line.offset) + " out" +
                        (request.activeLow ? " active-low" : "") + " " + request.consumer);
  return std::make_unique<SimulatedOutput>(state_, line.lineName);
}

void SimulatedGpioDevice::injectEdge(const ButtonEdge& edge) {
  std::lock_guard lock(state_->mutex);
  state_->level = edge.active;
  if (state_->eventFd < 0) {
    return;  // no button requested: the edge goes nowhere, as on real hardware
  }
  state_->edges.push_back(edge);
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto n = ::write(state_->eventFd, &one, sizeof(one));
}

void SimulatedGpioDevice::click(std::chrono::milliseconds held) {
  const auto now = GpioClock::now();
  injectEdge({now - held, true});
  injectEdge({now, false});
}

bool SimulatedGpioDevice::ledOn() const {
  return !ledLine_.empty() && output(ledLine_);
}
bool SimulatedGpioDevice::relayOn() const {
  return !relayLine_.empty() && output(relayLine_);
}

void SimulatedGpioDevice::failRequests(const std::string& lineName, int err) {
  std::lock_guard lock(state_->mutex);
  state_->failures[lineName] = err;
}

bool SimulatedGpioDevice::output(const std::string& lineName) const {
  std::lock_guard lock(state_->mutex);
  auto it = state_->outputs.find(lineName);
  return it != state_->outputs.end() && it->second;
}

std::vector<std::string> SimulatedGpioDevice::requestLog() const {
  std::lock_guard lock(state_->mutex);
  return state_->log;
}

std::vector<GpioChipInfo> simulatedChipsFor(const GpioConfig& config) {
  std::map<std::string, std::vector<std::string>> byChip;
  std::vector<std::string> order;
  auto add = [&](const GpioLineSpec& spec) {
    const std::string chip = spec.chip.empty() ? "gpio-sim" : spec.chip;
    if (!byChip.count(chip)) {
      order.push_back(chip);
    }
    auto& lines = byChip[chip];
    if (std::find(lines.begin(), lines.end(), spec.line) == lines.end()) {
      lines.push_back(spec.line);
    }
  };
  add(config.button);
  if (config.statusLed) {
    add(*config.statusLed);
  }
  if (config.relay) {
    add(*config.relay);
  }
  std::vector<GpioChipInfo> chips;
  for (std::size_t i = 0; i < order.size(); ++i) {
    chips.push_back({"gpiochip" + std::to_string(i), order[i], byChip[order[i]]});
  }
  return chips;
}

// --- the Gpio facade -------------------------------------------------------------------------

namespace {

class DeviceButton final : public Button {
 public:
  DeviceButton(std::unique_ptr<GpioInputLine> line, DebounceConfig config)
      : line_(std::move(line)), debouncer_(config, line_->value()) {}

  int eventFd() const override { return line_->fd(); }

  std::vector<ButtonEvent> readEvents() override {
    std::vector<ButtonEvent> out;
    for (const auto& edge : line_->readEdges()) {
      auto events = debouncer_.feed(edge);
      out.insert(out.end(), events.begin(), events.end());
    }
    auto events = debouncer_.tick(GpioClock::now());
    out.insert(out.end(), events.begin(), events.end());
    return out;
  }

  std::vector<ButtonEvent> tick(GpioClock::time_point now) override { return debouncer_.tick(now); }
  std::optional<GpioClock::time_point> nextDeadline() const override {
    return debouncer_.nextDeadline();
  }
  bool pressed() const override { return debouncer_.pressed(); }

 private:
  std::unique_ptr<GpioInputLine> line_;
  Debouncer debouncer_;
};

class DeviceOutput final : public OutputLine {
 public:
  DeviceOutput(std::unique_ptr<GpioOutputHandle> handle, std::string name)
      : handle_(std::move(handle)), name_(std::move(name)) {}
  void set(bool on) override {
    handle_->set(on);
    value_ = on;
  }
  bool value() const override { return value_; }
  std::string name() const override { return name_; }

 private:
  std::unique_ptr<GpioOutputHandle> handle_;
  std::string name_;
  bool value_ = false;
};

class DeviceGpio final : public Gpio {
 public:
  DeviceGpio(std::unique_ptr<GpioDevice> device, const GpioConfig& config)
      : device_(std::move(device)) {
    const auto chips = device_->chips();
    const GpioLineLocation buttonLine = findGpioLine(chips, config.button);
    button_ = std::make_unique<DeviceButton>(
        device_->requestInput(buttonLine,
                              {config.button.activeLow, config.buttonPullUp, config.consumer}),
        config.debounce);
    auto output = [&](const GpioLineSpec& spec) {
      const GpioLineLocation loc = findGpioLine(chips, spec);
      return std::make_unique<DeviceOutput>(
          device_->requestOutput(loc, {spec.activeLow, false, config.consumer}),
          loc.chipName + "/" + loc.lineName);
    };
    if (config.statusLed) {
      led_ = output(*config.statusLed);
    }
    if (config.relay) {
      relay_ = output(*config.relay);
    }
  }

  std::string backend() const override { return device_->name(); }
  Button& button() override { return *button_; }
  OutputLine* statusLed() override { return led_.get(); }
  OutputLine* relay() override { return relay_.get(); }
  GpioSimulation* simulation() override { return device_->simulation(); }

 private:
  std::unique_ptr<GpioDevice> device_;  // outlives the lines requested from it
  std::unique_ptr<DeviceButton> button_;
  std::unique_ptr<DeviceOutput> led_;
  std::unique_ptr<DeviceOutput> relay_;
};

}  // namespace

std::unique_ptr<Gpio> makeDeviceGpio(std::unique_ptr<GpioDevice> device, const GpioConfig& config) {
  return std::make_unique<DeviceGpio>(std::move(device), config);
}

std::unique_ptr<Gpio> makeGpio(const GpioConfig& config) {
  if (config.backend == "simulated") {
    auto device = std::make_unique<SimulatedGpioDevice>(
        simulatedChipsFor(config), config.statusLed ? config.statusLed->line : std::string(),
        config.relay ? config.relay->line : std::string());
    return makeDeviceGpio(std::move(device), config);
  }
  if (config.backend == "gpiod") {
    return makeDeviceGpio(makeLibgpiodDevice(), config);
  }
  throw std::invalid_argument("unknown GPIO back end '" + config.backend +
                              "' (known: gpiod, simulated)");
}

}  // namespace garmcap::capture
