// rigd's config: every error names the file, the line and the key.
#include <gtest/gtest.h>

#include <fstream>

#include "rig/config/config_error.hpp"
#include "rig/config/rigd_config.hpp"
#include "test_paths.hpp"

namespace rig::config {
namespace {

std::string message_for(const std::string& text, const std::vector<std::string>& overrides = {}) {
  testing::ScratchDir dir("config");
  const std::string path = dir.file("rigd.toml");
  std::ofstream(path) << text;
  try {
    load_rigd_config(path, overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Config, TheShippedSimulatorConfigIsValid) {
  const RigdConfig c = load_rigd_config(testing::source("config/rigd.sim.toml"));
  EXPECT_EQ(c.loop.rate_hz, 1000.0);
  EXPECT_EQ(c.daq.modbus.port, 1502);
  EXPECT_EQ(c.hash.size(), 16U);
}

TEST(Config, TheShippedRigConfigIsValid) {
  const RigdConfig c = load_rigd_config(testing::source("config/rigd.toml"));
  EXPECT_EQ(c.api.bind, "127.0.0.1");
}

TEST(Config, AnUnknownKeyIsAnErrorNamingFileLineAndKey) {
  const std::string m = message_for("[loop]\nrate_hz = 1000\nrte_hz = 2\n");
  EXPECT_NE(m.find("rigd.toml:3"), std::string::npos) << m;
  EXPECT_NE(m.find("unknown key 'loop.rte_hz'"), std::string::npos) << m;
}

TEST(Config, AnOutOfRangeValueNamesTheKeyAndTheRange) {
  const std::string m = message_for("[loop]\n\nrate_hz = 20000\n");
  EXPECT_NE(m.find("rigd.toml:3"), std::string::npos) << m;
  EXPECT_NE(m.find("'loop.rate_hz'"), std::string::npos) << m;
  EXPECT_NE(m.find("out of range [1000, 10000]"), std::string::npos) << m;
}

TEST(Config, AWrongTypeNamesTheExpectedType) {
  const std::string m = message_for("[daq]\nport = \"1502\"\n");
  EXPECT_NE(m.find("'daq.port': expected an integer"), std::string::npos) << m;
}

TEST(Config, AnUnknownChoiceListsTheAllowedOnes) {
  const std::string m = message_for("[daq]\ntransport = \"udp\"\n");
  EXPECT_NE(m.find("'udp' is not one of: tcp, rtu"), std::string::npos) << m;
}

TEST(Config, ATomlSyntaxErrorNamesTheLine) {
  const std::string m = message_for("[loop]\nrate_hz = = 3\n");
  EXPECT_NE(m.find("rigd.toml:2"), std::string::npos) << m;
}

TEST(Config, ANonLoopbackBindWithoutATokenFileIsRefused) {
  const std::string m = message_for("[api]\nbind = \"0.0.0.0\"\n");
  EXPECT_NE(m.find("'api.token_file' is required"), std::string::npos) << m;
}

TEST(Config, ABindNameInsteadOfAnAddressIsRefusedNamingTheKey) {
  const std::string m = message_for("[api]\nbind = \"localhost\"\n");
  EXPECT_NE(m.find("key 'api.bind' = \"localhost\" is not an IP address"), std::string::npos) << m;
}

TEST(Config, ADaqWatchdogOfZeroIsRefused) {
  const std::string m = message_for("[daq]\nwatchdog_ms = 0\n");
  EXPECT_NE(m.find("daq.watchdog_ms"), std::string::npos) << m;
  EXPECT_NE(m.find("rigd.toml:2"), std::string::npos) << m;
}

TEST(Config, TheLostDaqWritesLimitIsThreeOnTheRigTenOnTheSimulatedRigAndCanBeSet) {
  EXPECT_EQ(load_rigd_config(testing::source("config/rigd.toml")).loop.safety.max_failed_writes, 3);
  EXPECT_EQ(load_rigd_config(testing::source("config/rigd.sim.toml")).loop.safety.max_failed_writes,
            10);
  const RigdConfig c =
      load_rigd_config(testing::source("config/rigd.sim.toml"), {"safety.max_failed_writes=12"});
  EXPECT_EQ(c.loop.safety.max_failed_writes, 12);
}

TEST(Config, ABadLostDaqWritesLimitIsRefusedNamingTheKey) {
  const std::string zero = message_for("[safety]\nmax_failed_writes = 0\n");
  EXPECT_NE(zero.find("rigd.toml:2"), std::string::npos) << zero;
  EXPECT_NE(zero.find("'safety.max_failed_writes'"), std::string::npos) << zero;
  EXPECT_NE(zero.find("out of range [1, 1000]"), std::string::npos) << zero;
  const std::string text = message_for("[safety]\nmax_failed_writes = \"3\"\n");
  EXPECT_NE(text.find("'safety.max_failed_writes': expected an integer"), std::string::npos)
      << text;
  const std::string fraction = message_for("[safety]\nmax_failed_writes = 2.5\n");
  EXPECT_NE(fraction.find("'safety.max_failed_writes'"), std::string::npos) << fraction;
  // Not judged before the DAQ's own watchdog stops the motor: 5 periods of 1 ms vs 5 ms.
  const std::string slow = message_for("[daq]\nwatchdog_ms = 5\n[safety]\nmax_failed_writes = 5\n");
  EXPECT_NE(slow.find("key 'safety.max_failed_writes' (5 loop periods) must be shorter than "
                      "'daq.watchdog_ms' (5 ms)"),
            std::string::npos)
      << slow;
  EXPECT_EQ(message_for("[daq]\nwatchdog_ms = 5\n[safety]\nmax_failed_writes = 4\n"), "no error");
  EXPECT_NE(
      message_for("", {"safety.max_failed_writes=-1"}).find("--set safety.max_failed_writes=-1"),
      std::string::npos);
}

TEST(Config, TheRecorderRunsBelowTheLoopOrWithNormalScheduling) {
  EXPECT_EQ(load_rigd_config(testing::source("config/rigd.toml")).archive.recorder_priority, 60);
  const std::string above =
      message_for("[loop]\npriority = 50\n[archive]\nrecorder_priority = 50\n");
  EXPECT_NE(above.find("key 'archive.recorder_priority' (50) must be below 'loop.priority' (50)"),
            std::string::npos)
      << above;
  EXPECT_EQ(message_for("[loop]\npriority = 50\n[archive]\nrecorder_priority = 0\n"), "no error");
  EXPECT_EQ(message_for("[loop]\npriority = 0\n[archive]\nrecorder_priority = 60\n"), "no error")
      << "no real-time loop: not asked";
  const std::string range = message_for("[archive]\nrecorder_priority = 99\n");
  EXPECT_NE(range.find("'archive.recorder_priority'"), std::string::npos) << range;
  EXPECT_NE(range.find("rigd.toml:2"), std::string::npos) << range;
}

TEST(Config, AnAllowedOriginThatIsNotAnOriginIsRefused) {
  const std::string m = message_for("[api]\nallowed_origins = \"http://rig07:8080, rig08:8080\"\n");
  EXPECT_NE(m.find("key 'api.allowed_origins': 'rig08:8080' is not an origin"), std::string::npos)
      << m;
  EXPECT_EQ(message_for("[api]\nallowed_origins = \"http://rig07:8080, https://rig08.lab:8443\"\n"),
            "no error");
}

TEST(Config, ThePerAddressConnectionCapDefaultsToHalfTheConnectionsAndIsRangeChecked) {
  const RigdConfig shipped = load_rigd_config(testing::source("config/rigd.toml"));
  EXPECT_EQ(shipped.api.max_clients, 64);
  EXPECT_EQ(shipped.api.max_clients_per_address, 32);
  EXPECT_EQ(
      load_rigd_config(testing::source("config/rigd.sim.toml"), {"api.max_clients_per_address=4"})
          .api.max_clients_per_address,
      4);
  const std::string zero = message_for("[api]\nmax_clients_per_address = 0\n");
  EXPECT_NE(zero.find("rigd.toml:2"), std::string::npos) << zero;
  EXPECT_NE(zero.find("'api.max_clients_per_address'"), std::string::npos) << zero;
  EXPECT_NE(zero.find("out of range [1, 1024]"), std::string::npos) << zero;
  const std::string text = message_for("[api]\nmax_clients_per_address = \"8\"\n");
  EXPECT_NE(text.find("'api.max_clients_per_address': expected an integer"), std::string::npos)
      << text;
  EXPECT_NE(describe_config_keys().find("api.max_clients_per_address (an integer in [1, 1024])"),
            std::string::npos);
}

TEST(Config, AResponseTimeoutLongerThanTheLoopPeriodIsRefused) {
  const std::string m = message_for("[loop]\nrate_hz = 5000\n[daq]\nresponse_timeout_us = 700\n");
  EXPECT_NE(m.find("'daq.response_timeout_us'"), std::string::npos) << m;
}

TEST(Config, OverridesAreCheckedLikeTheFileAndNamed) {
  EXPECT_NE(message_for("", {"loop.rate_hz=99"}).find("--set loop.rate_hz=99"), std::string::npos);
  EXPECT_NE(message_for("", {"nope=1"}).find("unknown key 'nope'"), std::string::npos);
  EXPECT_NE(message_for("", {"missing-equals"}).find("expected key=value"), std::string::npos);
}

TEST(Config, RelativePathsResolveAgainstTheConfigFile) {
  testing::ScratchDir dir("config-paths");
  std::ofstream(dir.file("rigd.toml")) << "[archive]\npath = \"data/a.sqlite\"\n";
  const RigdConfig c = load_rigd_config(dir.file("rigd.toml"));
  EXPECT_EQ(c.archive.path, (dir.path() / "data/a.sqlite").string());
}

TEST(Config, EveryKeyIsDocumentedWithItsRange) {
  const std::string keys = describe_config_keys();
  EXPECT_NE(keys.find("loop.rate_hz (a number in [1000, 10000]): control and sampling rate [Hz]"),
            std::string::npos);
  EXPECT_NE(keys.find("safety.force_limit_N"), std::string::npos);
  EXPECT_NE(keys.find("safety.max_failed_writes (an integer in [1, 1000])"), std::string::npos)
      << keys;
}

}  // namespace
}  // namespace rig::config
