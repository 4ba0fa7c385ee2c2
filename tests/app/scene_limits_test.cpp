/// \file
/// The scene reader against inputs that used to be accepted silently or to
/// exhaust memory: keys given twice, joint names given twice, a byte-order
/// mark, files beyond the size limit, endless streams, more bodies than the
/// body limit. Each names the file, the field or the limit and its option.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "model/scene.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/command_runner.hpp"

namespace lieflow {
namespace {

const std::string kBody = R"({"name": "a", "mass": 1, "inertia": [1, 2, 3]})";

std::string errorOf(const std::string& json) {
  try {
    parseScene(json, "s.json");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(SceneLimits, AKeyGivenTwiceIsAnErrorNamingItsPath) {
  EXPECT_EQ(errorOf(R"({"name": "x", "bodies": [{"name": "a", "mass": 1, "mass": 2, "inertia": [1, 2, 3]}]})"),
            "s.json: bodies[0].mass: given twice (each key may appear once per object)");
  EXPECT_EQ(errorOf(R"({"name": "x", "name": "y", "bodies": [)" + kBody + "]}"),
            "s.json: name: given twice (each key may appear once per object)");
  EXPECT_NE(errorOf(R"({"name": "x", "bodies": [)" + kBody + R"(, {"name": "b", "mass": 1, "inertia": [1, 1, 1],
      "position": [0, 0, 1], "position": [0, 0, 2]}]})").find("bodies[1].position: given twice"),
            std::string::npos);
  // The same key in two different objects is fine.
  EXPECT_EQ(errorOf(R"({"name": "x", "bodies": [)" + kBody + R"(, {"name": "b", "mass": 1, "inertia": [1, 1, 1]}]})"), "");
}

TEST(SceneLimits, AJointNameGivenTwiceIsAnError) {
  const std::string joint = R"({"name": "j", "type": "spherical", "main": "ground", "secondary": "a",
      "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0]})";
  const std::string joint2 = R"({"name": "j", "type": "spherical", "main": "ground", "secondary": "b",
      "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0]})";
  const std::string e = errorOf(R"({"name": "x", "bodies": [)" + kBody +
                                R"(, {"name": "b", "mass": 1, "inertia": [1, 1, 1]}], "joints": [)" + joint + "," +
                                joint2 + "]}");
  EXPECT_NE(e.find("s.json: joints[1].name: duplicate joint name 'j' (also joints[0])"), std::string::npos) << e;
}

/// nlohmann echoes what it read before a syntax error; a long echo once sent
/// std::regex's recursive matcher through the stack (fuzz_scene: a brace and
/// 2000 carriage returns). The message is read by hand now, and cut.
TEST(SceneLimits, ALongEchoOfTheTextReadIsCutNotACrash) {
  for (const std::size_t n : {2000u, 200000u}) {
    const std::string e = errorOf("{\n" + std::string(n, '\r'));
    EXPECT_NE(e.find("s.json: not valid JSON: line 2, column " + std::to_string(n + 1)), std::string::npos) << e;
    const std::string read = errorOf("{\"a\": tru" + std::string(n, 'e') + "}");
    EXPECT_NE(read.find("invalid literal (read: '\"a\": tru"), std::string::npos) << read.substr(0, 200);
    EXPECT_LT(read.size(), 200u) << read.substr(0, 200);
  }
}

TEST(SceneLimits, AByteOrderMarkIsSkippedAsInRecordings) {
  const SceneDescription s = parseScene("\xEF\xBB\xBF" R"({"name": "x", "bodies": [)" + kBody + "]}", "s.json");
  EXPECT_EQ(s.name, "x");
}

TEST(SceneLimits, FilesBeyondTheSizeLimitAndEndlessStreamsAreRefused) {
  const std::string big = testing_support::testFile(".json");
  std::ofstream(big) << std::string(2 << 20, ' ') << R"({"name": "x", "bodies": [)" << kBody << "]}";
  ResourceLimits limits;
  limits.max_input_bytes = 1 << 20;
  try {
    loadScene(big, limits);
    ADD_FAILURE() << "a 2 MiB scene passed a 1 MiB limit";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("`max_input_mb`"), std::string::npos) << e.what();
  }
  // An endless stream of text is read to the limit and refused there.
  const std::string err = testing_support::testFile("_err.txt");
  const int raw = std::system(("yes | " + testing_support::lieflowBinary() +
                               " simulate /dev/stdin --max-input-mb 1 --stats >/dev/null 2>" + err).c_str());
  EXPECT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 2) << testing_support::slurp(err);
  EXPECT_NE(testing_support::slurp(err).find("--max-input-mb"), std::string::npos) << testing_support::slurp(err);
  // An endless stream of NUL bytes is not text: refused at its first byte.
  const auto o = testing_support::runLieflow("simulate /dev/zero --stats");
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("/dev/zero: holds a NUL byte at offset 0"), std::string::npos) << o.err;
}

TEST(SceneLimits, MoreBodiesThanTheLimitAreRefused) {
  ResourceLimits limits;
  limits.max_bodies = 3;
  EXPECT_THROW(loadScene("chain-4", limits), InvalidInput);
  EXPECT_EQ(loadScene("chain-3", limits).bodies.size(), 3u);
  const auto o = testing_support::runLieflow("simulate chain-100001 --t-end 0.001 --stats");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--max-bodies"), std::string::npos) << o.err;
}

}  // namespace
}  // namespace lieflow
