// A robot's config changed where the robot is, as a user does it:
// troupe-node --set and --print-config, troupe config compile for a board,
// and what the node says when a device it drives is not there.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace {

using troupe::testing::ChildProcess;

const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin";
const std::string kNode = kBin + "/troupe-node";
const std::string kTroupe = kBin + "/troupe";
const std::string kSource = TROUPE_SOURCE_DIR;
const std::string kPioneer = kSource + "/examples/nodes/pioneer-p3dx.json";
const std::string kKinematic = kSource + "/examples/nodes/kinematic.json";

using Result = troupe::testing::ProgramResult;

// A shell command line run to its end (bounded: a hang fails the test).
Result run(const std::string& command) {
  return troupe::testing::run_to_end({"/bin/sh", "-c", command}, 60000);
}

// The value of `key` in the printed config, after the first `after`
// (e.g. an instance's "driver_type"): the text up to the end of its line.
std::string value_after(const std::string& json, const std::string& after, const std::string& key) {
  size_t at = json.find(after);
  at = at == std::string::npos ? at : json.find("\"" + key + "\": ", at);
  if (at == std::string::npos) return "<none>";
  at += key.size() + 4;
  std::string value = json.substr(at, json.find('\n', at) - at);
  if (!value.empty() && value.back() == ',') value.pop_back();
  return value;
}

class NodeConfig : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = troupe::testing::make_temp_dir("troupe-node-config-"); }
  void TearDown() override { troupe::testing::remove_tree(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }
  std::string dir_;
};

TEST_F(NodeConfig, SetMovesThePioneerToAnotherSerialPortAndPrintConfigShowsIt) {
  Result before = run(kNode + " " + kPioneer + " --print-config");
  ASSERT_EQ(before.status, 0) << before.err;
  EXPECT_EQ(value_after(before.out, "\"p2os\"", "port"), "\"/dev/ttyS0\"") << before.out;

  Result after = run(kNode + " " + kPioneer + " --set p2os.port=/dev/ttyUSB0 --print-config");
  ASSERT_EQ(after.status, 0) << after.err;
  EXPECT_EQ(value_after(after.out, "\"p2os\"", "port"), "\"/dev/ttyUSB0\"") << after.out;
  // Nothing else moved: the laser keeps its port, the node its settings.
  EXPECT_EQ(value_after(after.out, "\"sicklms200\"", "port"), "\"/dev/ttyUSB0\"");
  EXPECT_EQ(value_after(after.out, "\"sicklms200\"", "resolution_cdeg"), "50");
  EXPECT_EQ(value_after(after.out, "{", "listen"), "\"0.0.0.0\"");
  // Options the config leaves out show the value the driver takes.
  EXPECT_EQ(value_after(after.out, "\"p2os\"", "pulse_ms"), "500");

  // What it prints is a config the node reads back as the same.
  std::string printed = write("printed.json", after.out);
  Result again = run(kNode + " " + printed + " --print-config");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(again.out, after.out);
}

TEST_F(NodeConfig, SetsApplyInOrderAndFlagsShowInPrintConfig) {
  Result r = run(kNode + " " + kPioneer +
                 " --set sicklms200.baud=9600 --set sicklms200.baud=500000 --set name=lab-pioneer"
                 " --set log_level=Debug --port 7001 --listen ::1 --print-config");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(value_after(r.out, "\"sicklms200\"", "baud"), "500000");
  EXPECT_EQ(value_after(r.out, "{", "name"), "\"lab-pioneer\"");
  EXPECT_EQ(value_after(r.out, "{", "log_level"), "\"Debug\"");
  EXPECT_EQ(value_after(r.out, "{", "port"), "7001");
  EXPECT_EQ(value_after(r.out, "{", "listen"), "\"::1\"");
}

// /etc/default/troupe-node holds TROUPE_NODE_ARGS; the unit passes it
// unquoted, split at spaces, as the shell does here.
TEST_F(NodeConfig, SetWorksFromTheUnitsArgumentVariable) {
  Result r = run("TROUPE_NODE_ARGS='--set p2os.port=/dev/ttyUSB1 --set p2os.sonar=false'; " + kNode + " " +
                 kPioneer + " $TROUPE_NODE_ARGS --print-config");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(value_after(r.out, "\"p2os\"", "port"), "\"/dev/ttyUSB1\"");
  EXPECT_EQ(value_after(r.out, "\"p2os\"", "sonar"), "false");
}

// Each mistake: exit 2, one line naming the --set and what is wrong (and
// what exists instead), nothing printed on stdout, nothing started.
TEST_F(NodeConfig, EveryBadSetSaysWhatIsWrong) {
  struct Case {
    const char* set;
    std::vector<const char*> says;
  };
  const Case cases[] = {
      {"lazer.port=/dev/ttyUSB0",
       {"--set lazer.port=/dev/ttyUSB0: ", "no driver instance 'lazer'", "p2os, sicklms200"}},
      {"p2os.prot=/dev/ttyUSB0", {"p2os has no option 'prot'", "its options: port, baud"}},
      {"p2os.baud=fast", {"'fast' is not a value of p2os.baud", "an integer from 0 to 4294967295"}},
      {"p2os.sonar=yes", {"'yes' is not a value of p2os.sonar", "true or false"}},
      {"sicklms200.pose_x=nan", {"'nan' is not a value of sicklms200.pose_x", "finite"}},
      {"sicklms200.scan_width_deg=70000",
       {"'70000' is out of range for sicklms200.scan_width_deg", "0 to 65535"}},
      {"p2os.baud=-1", {"'-1' is out of range for p2os.baud"}},
      {"log_level=debug", {"'debug' is not a value of log_level", "Error, Warn, Info, Debug"}},
      {"max_sped=1", {"no node setting 'max_sped'", "max_clients"}},
      {"drivers=none", {"drivers is a list"}},
      {"p2os.port", {"expected INSTANCE.KEY=VALUE"}},
  };
  for (const Case& c : cases) {
    Result r = run(kNode + " " + kPioneer + " --set '" + c.set + "' --print-config");
    EXPECT_EQ(r.status, 2) << c.set << ": " << r.err;
    EXPECT_EQ(r.out, "") << c.set;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const char* part : c.says) EXPECT_NE(r.err.find(part), std::string::npos) << c.set << ": " << r.err;
  }
}

TEST_F(NodeConfig, AnInstanceNameTwoInstancesShareIsRefused) {
  std::string path = write("two.json", R"({ "drivers": [
    { "driver_type": "kinematic", "provides": ["position2d:0"] },
    { "driver_type": "kinematic", "provides": ["position2d:1"] } ] })");
  Result r = run(kNode + " " + path + " --set kinematic.max_speed=0.5 --print-config");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("drivers[0] and drivers[1]"), std::string::npos) << r.err;
  // Named, each is reached; the one without options gets them.
  path = write("named.json", R"({ "drivers": [
    { "driver_type": "kinematic", "name": "left", "provides": ["position2d:0"] },
    { "driver_type": "kinematic", "name": "right", "provides": ["position2d:1"] } ] })");
  r = run(kNode + " " + path + " --set right.max_speed=0.5 --print-config");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(value_after(r.out, "\"left\"", "max_speed"), "0.5")
      << r.out;  // right's block follows left's name
  EXPECT_EQ(value_after(r.out, "\"driver_type\": \"kinematic\"", "max_speed"), "1") << r.out;
}

TEST_F(NodeConfig, PrintConfigOfABadConfigFailsSayingWhy) {
  std::string path = write("bad.json", R"({ "drivers": [ { "driver_type": "warpdrive" } ] })");
  Result r = run(kNode + " " + path + " --print-config");
  EXPECT_EQ(r.status, 78) << "EX_CONFIG: the unit does not retry a config to fix";
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("bad.json:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("driver 'warpdrive' is not compiled into board host"), std::string::npos) << r.err;
}

// troupe config compile makes what the board build's flatc makes, the node
// runs it as it runs the JSON, and --set works on the compiled form alike.
TEST_F(NodeConfig, CompiledConfigLoadsAndRunsAsTheJson) {
  const std::string bin = dir_ + "/kinematic.bin";
  Result c = run(kTroupe + " config compile " + kKinematic + " --board host -o " + bin);
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_EQ(troupe::testing::read_text(bin),
            troupe::testing::read_text(std::string(TROUPE_BINARY_DIR) + "/configs/kinematic.bin"));

  for (const std::string set : {"", " --set kinematic.max_speed=0.25 --set port=7002"}) {
    Result from_json = run(kNode + " " + kKinematic + set + " --print-config");
    Result from_bin = run(kNode + " " + bin + set + " --print-config");
    ASSERT_EQ(from_json.status, 0) << from_json.err;
    ASSERT_EQ(from_bin.status, 0) << from_bin.err;
    EXPECT_EQ(from_bin.out, from_json.out);
  }

  // And it serves.
  uint16_t port = troupe::testing::free_port();
  ChildProcess node;
  std::string error;
  ASSERT_TRUE(node.start({kNode, bin, "--port", std::to_string(port)}, dir_, "troupe-node", error)) << error;
  ASSERT_TRUE(troupe::testing::wait_for_listener(port, 5)) << node.err();
  Result ls = run(kTroupe + " ls 127.0.0.1:" + std::to_string(port));
  EXPECT_EQ(ls.status, 0) << ls.err;
  EXPECT_NE(ls.out.find("position2d:0"), std::string::npos) << ls.out;
  EXPECT_EQ(node.stop(), 0) << node.err();
}

TEST_F(NodeConfig, CompileForAnotherBoardTakesSetAndPrintShowsIt) {
  const std::string bin = dir_ + "/pioneer.bin";
  Result c = run(kTroupe + " config compile " + kPioneer + " --board pioneer-p3dx -o " + bin +
                 " --set p2os.port=/dev/ttyUSB0");
  ASSERT_EQ(c.status, 0) << c.err;
  Result p = run(kTroupe + " config print " + bin + " --board pioneer-p3dx");
  ASSERT_EQ(p.status, 0) << p.err;
  EXPECT_EQ(value_after(p.out, "\"p2os\"", "port"), "\"/dev/ttyUSB0\"") << p.out;
  // The same as the host node shows for the JSON: the union is numbered
  // per board, the options are the same.
  Result host = run(kNode + " " + kPioneer + " --set p2os.port=/dev/ttyUSB0 --print-config");
  EXPECT_EQ(p.out, host.out);
  // Another board's schema numbers other drivers: this one has one, and
  // the config's second instance is a driver it does not have.
  Result wrong = run(kTroupe + " config print " + bin + " --board diffbot-can");
  EXPECT_EQ(wrong.status, 1);
  EXPECT_NE(wrong.err.find("not a valid node config for board diffbot-can"), std::string::npos) << wrong.err;
}

TEST_F(NodeConfig, CompileRefusesADriverTheBoardLacks) {
  const std::string bin = dir_ + "/kinematic.bin";
  Result c = run(kTroupe + " config compile " + kKinematic + " --board pioneer-p3dx -o " + bin);
  EXPECT_EQ(c.status, 1);
  EXPECT_NE(c.err.find("kinematic.json:"), std::string::npos) << c.err;
  EXPECT_NE(c.err.find(
                "driver 'kinematic' is not compiled into board pioneer-p3dx (its drivers: p2os, sicklms200)"),
            std::string::npos)
      << c.err;
  EXPECT_EQ(troupe::testing::read_text(bin), "");  // nothing written

  Result board = run(kTroupe + " config compile " + kKinematic + " --board pioneer -o " + bin);
  EXPECT_EQ(board.status, 2);
  EXPECT_NE(board.err.find("no board 'pioneer'"), std::string::npos) << board.err;
  EXPECT_NE(board.err.find("pioneer-p3dx"), std::string::npos) << board.err;
}

// A CAN bus that is not there (this machine's kernel has no CAN; on one
// with CAN, no interface has this name) is what the node reports, by name:
// not a config to fix.
TEST_F(NodeConfig, AMissingCanBusIsReportedAsMissingNotAsABadConfig) {
  std::string path = write("diffbot.json", R"({ "drivers": [
    { "driver_type": "odrive_can", "driver": { "can_interface": "nocan9" }, "provides": ["position2d:0"] } ] })");
  Result r = run(kNode + " " + path + " --port 0");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("drivers[0] (odrive_can): CAN interface 'nocan9': "), std::string::npos) << r.err;
  EXPECT_TRUE(r.err.find("this kernel has no CAN support") != std::string::npos ||
              r.err.find("No such device") != std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("not starting: a device it drives is not there (the config is fine)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("the config must be fixed"), std::string::npos) << r.err;
}

}  // namespace
