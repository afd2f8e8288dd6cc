// GPIO: the debouncer as a pure function of timestamped edges, line lookup by chip label and
// line name, and the Gpio facade over the simulated device (the same code path libgpiod uses).

#include "garmcap/capture/gpio.h"

#include <gtest/gtest.h>
#include <poll.h>

#include <filesystem>

#include "garmcap/capture/gpio_device.h"

namespace garmcap::capture {
namespace {

using std::chrono::milliseconds;
using Kind = ButtonEvent::Kind;

GpioClock::time_point at(int ms) {
  return GpioClock::time_point(milliseconds(1000000 + ms));
}

std::vector<Kind> kinds(const std::vector<ButtonEvent>& events) {
  std::vector<Kind> out;
  for (const auto& e : events) {
    out.push_back(e.kind);
  }
  return out;
}

/// Feeds edges (ms, level) and then ticks to `endMs`, collecting every event.
std::vector<ButtonEvent> run(Debouncer& d, const std::vector<std::pair<int, bool>>& edges,
                             int endMs) {
  std::vector<ButtonEvent> out;
  for (const auto& [ms, level] : edges) {
    auto e = d.feed({at(ms), level});
    out.insert(out.end(), e.begin(), e.end());
  }
  auto e = d.tick(at(endMs));
  out.insert(out.end(), e.begin(), e.end());
  return out;
}

TEST(Debouncer, CleanPressIsPressedReleasedShortPress) {
  Debouncer d;
  const auto ev = run(d, {{0, true}, {200, false}}, 400);
  ASSERT_EQ(kinds(ev), (std::vector<Kind>{Kind::kPressed, Kind::kReleased, Kind::kShortPress}));
  EXPECT_EQ(ev[0].time, at(0));
  EXPECT_EQ(ev[1].time, at(200));
  EXPECT_EQ(ev[2].held, milliseconds(200));
  EXPECT_FALSE(d.pressed());
}

TEST(Debouncer, ContactBounceMakesOnePress) {
  Debouncer d;  // 30 ms
  // Bounces on press (0-12 ms) and on release (300-309 ms).
  const auto ev = run(d,
                      {{0, true},
                       {3, false},
                       {5, true},
                       {9, false},
                       {12, true},
                       {300, false},
                       {302, true},
                       {309, false}},
                      500);
  ASSERT_EQ(kinds(ev), (std::vector<Kind>{Kind::kPressed, Kind::kReleased, Kind::kShortPress}));
  EXPECT_EQ(ev[0].time, at(12));  // the edge that started the stable level
  EXPECT_EQ(ev[1].time, at(309));
  EXPECT_EQ(ev[1].held, milliseconds(297));
}

TEST(Debouncer, GlitchShorterThanTheWindowIsIgnored) {
  Debouncer d;
  EXPECT_TRUE(run(d, {{0, true}, {20, false}}, 500).empty());
  EXPECT_FALSE(d.pressed());
  EXPECT_FALSE(d.nextDeadline());
}

TEST(Debouncer, PressNeedsTheStableTimeBeforeItCounts) {
  Debouncer d;
  EXPECT_TRUE(d.feed({at(0), true}).empty());
  EXPECT_TRUE(d.tick(at(29)).empty());
  ASSERT_EQ(d.nextDeadline(), at(30));
  EXPECT_EQ(kinds(d.tick(at(30))), (std::vector<Kind>{Kind::kPressed}));
  EXPECT_TRUE(d.pressed());
}

TEST(Debouncer, LongPressFiresWhileHeldAndReleaseIsNotAShortPress) {
  Debouncer d({milliseconds(30), milliseconds(2000)});
  d.feed({at(0), true});
  EXPECT_EQ(kinds(d.tick(at(100))), (std::vector<Kind>{Kind::kPressed}));
  ASSERT_EQ(d.nextDeadline(), at(2000));
  EXPECT_TRUE(d.tick(at(1999)).empty());
  const auto longPress = d.tick(at(2000));
  ASSERT_EQ(kinds(longPress), (std::vector<Kind>{Kind::kLongPress}));
  EXPECT_EQ(longPress[0].time, at(2000));
  EXPECT_FALSE(d.nextDeadline());
  const auto release = run(d, {{3000, false}}, 3100);
  EXPECT_EQ(kinds(release), (std::vector<Kind>{Kind::kReleased}));
  EXPECT_EQ(release[0].held, milliseconds(3000));
}

TEST(Debouncer, LongPressWithoutTicksIsStillReportedAtRelease) {
  Debouncer d({milliseconds(30), milliseconds(1000)});
  const auto ev = run(d, {{0, true}, {2500, false}}, 2600);
  EXPECT_EQ(kinds(ev), (std::vector<Kind>{Kind::kPressed, Kind::kLongPress, Kind::kReleased}));
}

TEST(Debouncer, ReleaseSettlingJustBeforeTheLongPressTimeIsShort) {
  Debouncer d({milliseconds(30), milliseconds(1000)});
  d.feed({at(0), true});
  d.tick(at(50));
  d.feed({at(990), false});  // released at 990 ms; not yet stable at 1000 ms
  EXPECT_TRUE(d.tick(at(1005)).empty());
  EXPECT_EQ(kinds(d.tick(at(1020))), (std::vector<Kind>{Kind::kReleased, Kind::kShortPress}));
}

TEST(Debouncer, ButtonHeldAtStartUpIsNotAPress) {
  Debouncer d({}, /*initiallyPressed=*/true);
  EXPECT_TRUE(d.pressed());
  EXPECT_TRUE(d.tick(at(10000)).empty());  // no long press either
  EXPECT_EQ(kinds(run(d, {{20000, false}}, 20100)), (std::vector<Kind>{Kind::kReleased}));
  EXPECT_EQ(kinds(run(d, {{21000, true}, {21100, false}}, 21200)),
            (std::vector<Kind>{Kind::kPressed, Kind::kReleased, Kind::kShortPress}));
}

TEST(Debouncer, OutOfOrderTimestampsAreClamped) {
  Debouncer d;
  d.feed({at(100), true});
  d.feed({at(50), false});  // older than the last edge: treated as at 100 ms
  EXPECT_TRUE(d.tick(at(500)).empty());
}

// --- lookup ----------------------------------------------------------------------------------

std::vector<GpioChipInfo> piChips() {
  return {{"gpiochip0", "pinctrl-rp1", {"ID_SDA", "ID_SCL", "GPIO2", "GPIO17", "GPIO27"}},
          {"gpiochip10", "gpio-brcmstb@107d508500", {"RP1_SDA", "", "PWR_GPIO"}},
          {"gpiochip11", "gpio-extra", {"GPIO27"}}};
}

TEST(GpioLookup, FindsALineByNameOnAnyChip) {
  const auto loc = findGpioLine(piChips(), {"", "GPIO17", true});
  EXPECT_EQ(loc.chipName, "gpiochip0");
  EXPECT_EQ(loc.chipLabel, "pinctrl-rp1");
  EXPECT_EQ(loc.offset, 3u);
}

TEST(GpioLookup, ChipByLabelOrByName) {
  EXPECT_EQ(findGpioLine(piChips(), {"pinctrl-rp1", "GPIO27", false}).offset, 4u);
  EXPECT_EQ(findGpioLine(piChips(), {"gpiochip11", "GPIO27", false}).chipLabel, "gpio-extra");
}

TEST(GpioLookup, AmbiguousNameAsksForTheChip) {
  try {
    findGpioLine(piChips(), {"", "GPIO27", false});
    FAIL();
  } catch (const GpioError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("several chips"), std::string::npos) << m;
    EXPECT_NE(m.find("pinctrl-rp1"), std::string::npos) << m;
    EXPECT_NE(m.find("gpio-extra"), std::string::npos) << m;
  }
}

TEST(GpioLookup, MissingLineOrChipListsTheChipsSeen) {
  try {
    findGpioLine(piChips(), {"pinctrl-rp1", "GPIO99", false});
    FAIL();
  } catch (const GpioError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("GPIO99"), std::string::npos) << m;
    EXPECT_NE(m.find("gpiochip0 [pinctrl-rp1]"), std::string::npos) << m;
  }
  try {
    findGpioLine(piChips(), {"pinctrl-bcm2835", "GPIO17", false});
    FAIL();
  } catch (const GpioError& e) {
    EXPECT_NE(std::string(e.what()).find("chip 'pinctrl-bcm2835' not found"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(findGpioLine({}, {"", "GPIO17", false}), GpioError);
  EXPECT_THROW(findGpioLine(piChips(), {"", "", false}), GpioError);
}

// --- the facade over the simulated device ------------------------------------------------------

GpioConfig stationConfig() {
  GpioConfig c;
  c.backend = "simulated";
  c.button = {"pinctrl-rp1", "GPIO17", true};
  c.statusLed = GpioLineSpec{"pinctrl-rp1", "GPIO27", false};
  c.relay = GpioLineSpec{"pinctrl-rp1", "GPIO2", true};
  return c;
}

bool readable(int fd) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, 0) == 1 && (p.revents & POLLIN) != 0;
}

TEST(SimulatedGpio, RequestsLinesWithTheRightFlags) {
  auto device = std::make_unique<SimulatedGpioDevice>(piChips(), "GPIO2", "");
  SimulatedGpioDevice* sim = device.get();
  GpioConfig c = stationConfig();
  c.statusLed = GpioLineSpec{"pinctrl-rp1", "GPIO2", false};
  c.relay.reset();
  auto gpio = makeDeviceGpio(std::move(device), c);
  const auto log = sim->requestLog();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0], "gpiochip0/3 in active-low pull-up garmcapd");
  EXPECT_EQ(log[1], "gpiochip0/2 out garmcapd");
  EXPECT_EQ(gpio->relay(), nullptr);
  ASSERT_NE(gpio->statusLed(), nullptr);
  gpio->statusLed()->set(true);
  EXPECT_TRUE(sim->ledOn());
  EXPECT_EQ(gpio->statusLed()->name(), "gpiochip0/GPIO2");
}

TEST(SimulatedGpio, EventFdDrivesTheButtonLikeAKernelLine) {
  auto gpio = makeGpio(stationConfig());
  ASSERT_NE(gpio->simulation(), nullptr);
  EXPECT_EQ(gpio->backend(), "simulated");
  Button& button = gpio->button();
  const int fd = button.eventFd();
  ASSERT_GE(fd, 0);
  EXPECT_FALSE(readable(fd));
  const auto t0 = GpioClock::now() - milliseconds(500);
  gpio->simulation()->injectEdge({t0, true});
  gpio->simulation()->injectEdge({t0 + milliseconds(2), false});  // bounce
  gpio->simulation()->injectEdge({t0 + milliseconds(4), true});
  gpio->simulation()->injectEdge({t0 + milliseconds(150), false});
  EXPECT_TRUE(readable(fd));
  const auto events = button.readEvents();  // ticks to now: everything has settled
  EXPECT_FALSE(readable(fd));
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kPressed, Kind::kReleased, Kind::kShortPress}));
  EXPECT_FALSE(button.nextDeadline());
}

TEST(SimulatedGpio, ClickNeedsTheTimerForTheRelease) {
  auto gpio = makeGpio(stationConfig());
  gpio->simulation()->click(milliseconds(100));
  Button& button = gpio->button();
  auto events = button.readEvents();
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kPressed}));
  const auto deadline = button.nextDeadline();
  ASSERT_TRUE(deadline);
  events = button.tick(*deadline);
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kReleased, Kind::kShortPress}));
}

TEST(SimulatedGpio, OutputsStartOffAndFollowSet) {
  auto gpio = makeGpio(stationConfig());
  auto* sim = gpio->simulation();
  EXPECT_FALSE(sim->ledOn());
  EXPECT_FALSE(sim->relayOn());
  gpio->relay()->set(true);
  EXPECT_TRUE(sim->relayOn());
  EXPECT_TRUE(gpio->relay()->value());
  gpio->relay()->set(false);
  EXPECT_FALSE(sim->relayOn());
}

TEST(SimulatedGpio, BusyLineIsAClearError) {
  auto device = std::make_unique<SimulatedGpioDevice>(simulatedChipsFor(stationConfig()));
  device->failRequests("GPIO17", EBUSY);
  try {
    makeDeviceGpio(std::move(device), stationConfig());
    FAIL();
  } catch (const GpioError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("GPIO17"), std::string::npos) << m;
    EXPECT_NE(m.find("busy"), std::string::npos) << m;
  }
}

TEST(GpioFactory, UnknownBackendIsRefused) {
  GpioConfig c;
  c.backend = "wiringpi";
  EXPECT_THROW(makeGpio(c), std::invalid_argument);
}

TEST(GpioFactory, LibgpiodWithoutChipsSaysSo) {
  bool anyChip = false;
  for (const auto& entry : std::filesystem::directory_iterator("/dev")) {
    anyChip |= entry.path().filename().string().rfind("gpiochip", 0) == 0;
  }
  if (anyChip) {
    GTEST_SKIP() << "this machine has GPIO chips; the no-chip message is not observable";
  }
  GpioConfig c;
  c.backend = "gpiod";
  try {
    makeGpio(c);
    FAIL();
  } catch (const GpioError& e) {
    EXPECT_NE(std::string(e.what()).find("no GPIO chips found"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace garmcap::capture
