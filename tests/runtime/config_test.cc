// Node configs: a bad one names the file and the offending key or line, and
// nothing is started from it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "runtime/node_config.h"

namespace troupe {
namespace {

class ConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/troupe-config-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    for (const std::string& f : files_) unlink(f.c_str());
    rmdir(dir_.c_str());
  }
  std::string write(const std::string& name, const std::string& text) {
    std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    files_.push_back(path);
    return path;
  }
  // Loads and builds; returns the error ("" when both succeed).
  std::string problem(const std::string& json) {
    std::string path = write("node.json", json);
    LoadedConfig cfg;
    std::string error;
    if (!load_config(path, cfg, error)) return error;
    Node node(node_options(*cfg.root));
    if (!build_node(node, cfg, error)) return error;
    return "";
  }

  std::string dir_;
  std::vector<std::string> files_;
};

const char kGood[] = R"({
  "name": "base",
  "port": 7001,
  "drivers": [
    { "driver_type": "kinematic", "driver": { "max_speed": 0.7 }, "provides": ["position2d:0"] }
  ]
})";

TEST_F(ConfigTest, GoodConfigBuildsItsDevices) {
  std::string path = write("good.json", kGood);
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load_config(path, cfg, error)) << error;
  Node::Options o = node_options(*cfg.root);
  EXPECT_EQ(o.name, "base");
  EXPECT_EQ(o.port, 7001);
  EXPECT_EQ(o.listen, "localhost");  // the default when the config says nothing: both loopbacks
  Node node(o);
  ASSERT_TRUE(build_node(node, cfg, error)) << error;
  EXPECT_EQ(node.device_count(), 1u);
  EXPECT_NE(node.find_device(wire::Address(0, uint16_t(wire::Interface::Position2d), 0)), kNoDevice);
}

TEST_F(ConfigTest, UnknownKeyIsNamedWithFileLineAndColumn) {
  std::string error = problem(R"({
  "name": "base",
  "drivers": [ { "driver_type": "kinematic", "driver": { "max_sped": 0.7 }, "provides": ["position2d:0"] } ]
})");
  EXPECT_NE(error.find("node.json:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("unknown field: max_sped"), std::string::npos) << error;
}

TEST_F(ConfigTest, WrongTypeIsAnError) {
  std::string error = problem(R"({ "port": "six" })");
  EXPECT_NE(error.find("node.json:1:"), std::string::npos) << error;
}

TEST_F(ConfigTest, SyntaxErrorIsAnError) {
  std::string error = problem("{ \"name\": \"x\", ");
  EXPECT_NE(error.find("node.json:1:"), std::string::npos) << error;
}

TEST_F(ConfigTest, DriverNotOnTheBoardIsNamedWithTheBoardsDrivers) {
  std::string error = problem(R"({ "drivers": [ { "driver_type": "warpdrive", "provides": ["position2d:0"] } ] })");
  EXPECT_NE(error.find("warpdrive"), std::string::npos) << error;
  EXPECT_NE(error.find("kinematic"), std::string::npos) << error;  // what the board has
}

TEST_F(ConfigTest, BadDeviceAddressNamesTheInstanceAndEntry) {
  std::string error = problem(R"({ "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:one"] } ] })");
  EXPECT_NE(error.find("drivers[0] (kinematic): provides[0]"), std::string::npos) << error;
}

TEST_F(ConfigTest, DuplicateDeviceIsRefused) {
  std::string error = problem(R"({ "drivers": [
    { "driver_type": "kinematic", "provides": ["position2d:0"] },
    { "driver_type": "kinematic", "name": "second", "provides": ["position2d:0"] } ] })");
  EXPECT_NE(error.find("drivers[1] (second)"), std::string::npos) << error;
  EXPECT_NE(error.find("already provided"), std::string::npos) << error;
}

TEST_F(ConfigTest, UsesOfAMissingDeviceIsRefused) {
  std::string error = problem(
      R"({ "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:0"], "uses": ["ranger:0"] } ] })");
  EXPECT_NE(error.find("uses ranger:0, which no driver provides"), std::string::npos) << error;
}

TEST_F(ConfigTest, DriverSetupErrorNamesTheInstance) {
  std::string error =
      problem(R"({ "drivers": [ { "driver_type": "kinematic", "provides": ["ranger:0"], "name": "wheels" } ] })");
  EXPECT_NE(error.find("drivers[0] (wheels): kinematic provides exactly one position2d"), std::string::npos)
      << error;
  error = problem(
      R"({ "drivers": [ { "driver_type": "kinematic", "driver": { "rate_hz": 0 }, "provides": ["position2d:0"] } ] })");
  EXPECT_NE(error.find("rate_hz"), std::string::npos) << error;
}

TEST_F(ConfigTest, MissingFileSaysSo) {
  LoadedConfig cfg;
  std::string error;
  EXPECT_FALSE(load_config(dir_ + "/nope.json", cfg, error));
  EXPECT_NE(error.find("nope.json: cannot open"), std::string::npos) << error;
}

TEST_F(ConfigTest, BinaryFormLoadsTheSame) {
  std::vector<uint8_t> binary;
  std::string error;
  ASSERT_TRUE(parse_config_json(kGood, "good.json", binary, error)) << error;
  std::string path = write("good.bin", std::string(binary.begin(), binary.end()));
  LoadedConfig cfg;
  ASSERT_TRUE(load_config(path, cfg, error)) << error;
  EXPECT_EQ(node_options(*cfg.root).port, 7001);
  // A truncated binary is refused by the verifier, not read.
  std::string bad = write("bad.bin", std::string(binary.begin(), binary.begin() + long(binary.size() / 2)));
  EXPECT_FALSE(load_config(bad, cfg, error));
  EXPECT_NE(error.find("bad.bin: not a valid node config"), std::string::npos) << error;
}

// --set copies the config through its schema with one value replaced: lists
// of strings and of structs, other instances, node settings, all survive.
TEST_F(ConfigTest, SetChangesOneValueAndKeepsEverythingElse) {
  std::string path = write("desk.json", R"({
  "name": "desk",
  "clients": [{ "key": "laptop.pub", "read": ["*"] }, { "key": "robot.pub" }],
  "drivers": [
    { "driver_type": "fusion", "name": "ekf",
      "driver": { "gate": 16.5, "landmarks": [ { "id": 7, "x": 1.5, "y": -2, "a": 0.25 }, { "id": 9, "x": 3, "y": 4, "a": 0 } ] },
      "provides": ["position2d:1"], "uses": ["position2d:0"] },
    { "driver_type": "ros2", "driver": { "namespaces": ["r0", "r1"], "domain_id": 3 }, "provides": ["opaque:0"] }
  ]
})");
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load_config(path, cfg, error)) << error;
  const std::string before = config_to_json(cfg);
  ASSERT_TRUE(set_config_value(cfg, "ekf.gate=10", error)) << error;
  ASSERT_TRUE(set_config_value(cfg, "ros2.node_name=bridge", error)) << error;  // an option not given yet
  ASSERT_TRUE(set_config_value(cfg, "max_clients=8", error)) << error;
  EXPECT_FLOAT_EQ(cfg.root->drivers()->Get(0)->driver_as_fusion()->gate(), 10.0f);
  EXPECT_EQ(cfg.root->drivers()->Get(1)->driver_as_ros2()->node_name()->str(), "bridge");
  EXPECT_EQ(node_options(*cfg.root).max_clients, 8);

  std::string expected = before;
  auto replace = [&expected](const std::string& from, const std::string& to) {
    size_t at = expected.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    expected.replace(at, from.size(), to);
  };
  replace("\"gate\": 16.5", "\"gate\": 10");
  replace("\"domain_id\": 3,\n", "\"domain_id\": 3,\n        \"node_name\": \"bridge\",\n");
  replace("\"max_clients\": 64", "\"max_clients\": 8");
  EXPECT_EQ(config_to_json(cfg), expected);
  EXPECT_NE(expected.find("{ \"id\": 7, \"x\": 1.5, \"y\": -2, \"a\": 0.25 }"), std::string::npos) << expected;
  EXPECT_NE(expected.find("\"namespaces\": [\"r0\", \"r1\"]"), std::string::npos) << expected;
}

TEST_F(ConfigTest, AFailedSetLeavesTheConfigAsItWas) {
  std::string path = write("good.json", kGood);
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load_config(path, cfg, error)) << error;
  const std::vector<uint8_t> bytes = cfg.bytes;
  EXPECT_FALSE(set_config_value(cfg, "kinematic.max_speed=fast", error));
  EXPECT_FALSE(set_config_value(cfg, "kinematic.max_speed=1e39", error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
  EXPECT_EQ(cfg.bytes, bytes);
  EXPECT_FLOAT_EQ(cfg.root->drivers()->Get(0)->driver_as_kinematic()->max_speed(), 0.7f);
}

}  // namespace
}  // namespace troupe
