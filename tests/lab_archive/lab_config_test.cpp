// [lab_archive] in rigd's config: off by default, every key checked, errors that name the
// file, line and key, and no password in the config file.
#include <gtest/gtest.h>

#include <fstream>

#include "rig/config/config_error.hpp"
#include "rig/config/rigd_config.hpp"
#include "test_paths.hpp"

namespace rig::config {
namespace {

std::string message_for(const std::string& lab_section) {
  testing::ScratchDir dir("lab-config");
  const std::string path = dir.file("rigd.toml");
  std::ofstream(path) << "[loop]\nrate_hz = 1000\n[lab_archive]\n" << lab_section;
  try {
    load_rigd_config(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LabArchiveConfig, IsOffByDefaultInTheShippedConfigs) {
  EXPECT_FALSE(load_rigd_config(testing::source("config/rigd.toml")).lab_archive.enabled);
  EXPECT_FALSE(load_rigd_config(testing::source("config/rigd.sim.toml")).lab_archive.enabled);
}

TEST(LabArchiveConfig, AValidSectionIsRead) {
  testing::ScratchDir dir("lab-config-ok");
  const std::string path = dir.file("rigd.toml");
  std::ofstream(path)
      << "[lab_archive]\nenabled = true\nconninfo = \"host=lab-db dbname=lab user=rig_writer\"\n"
         "password_file = \"lab.password\"\nsslmode = \"verify-full\"\nrig_id = \"rig-3\"\n";
  const RigdConfig c = load_rigd_config(path);
  EXPECT_TRUE(c.lab_archive.enabled);
  EXPECT_EQ(c.lab_archive.conninfo, "host=lab-db dbname=lab user=rig_writer");
  EXPECT_EQ(c.lab_archive.password_file, dir.file("lab.password"));  // relative to the config file
  EXPECT_EQ(c.lab_archive.sslmode, "verify-full");
  EXPECT_EQ(c.lab_archive.rig_id, "rig-3");
}

TEST(LabArchiveConfig, BadValuesAreErrorsNamingLineAndKey) {
  std::string m = message_for("sslmode = \"maybe\"\n");
  EXPECT_NE(m.find("rigd.toml:4"), std::string::npos) << m;
  EXPECT_NE(m.find("lab_archive.sslmode"), std::string::npos) << m;
  EXPECT_NE(m.find("'maybe' is not one of"), std::string::npos) << m;
  m = message_for("interval_ms = 1\n");
  EXPECT_NE(m.find("lab_archive.interval_ms"), std::string::npos) << m;
  m = message_for("enabeld = true\n");
  EXPECT_NE(m.find("unknown key 'lab_archive.enabeld'"), std::string::npos) << m;
}

TEST(LabArchiveConfig, EnabledWithoutAConnectionStringIsAnError) {
  const std::string m = message_for("enabled = true\n");
  EXPECT_NE(m.find("'lab_archive.conninfo' is required when 'lab_archive.enabled' = true"),
            std::string::npos)
      << m;
}

TEST(LabArchiveConfig, APasswordInTheConnectionStringIsRefused) {
  for (const std::string conninfo : {"host=db password=x", "postgresql://rig:secret@db/lab"}) {
    const std::string m = message_for("conninfo = \"" + conninfo + "\"\n");
    EXPECT_NE(m.find("must not hold a password: put it in 'lab_archive.password_file'"),
              std::string::npos)
        << m;
  }
  EXPECT_EQ(message_for("conninfo = \"postgresql://rig@db:5432/lab\"\n"), "no error");
}

}  // namespace
}  // namespace rig::config
