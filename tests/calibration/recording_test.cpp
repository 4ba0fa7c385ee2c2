/// \file
/// The recording CSV reader: body discovery from column prefixes, any subset
/// of column groups, the joint's bodies with and without --main/--secondary,
/// and every kind of bad input named by file, line and column (InvalidInput,
/// exit 2 in the command).
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "calibration/recording.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

Recording parse(const std::string& text) {
  std::istringstream in(text);
  return parseRecording(in, "rec.csv");
}

/// Expects InvalidInput whose message contains every fragment.
void expectError(const std::string& text, std::initializer_list<const char*> fragments) {
  try {
    parse(text);
    ADD_FAILURE() << "expected InvalidInput for:\n" << text;
  } catch (const InvalidInput& e) {
    for (const char* f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
  }
}

const char* kTwoBodies =
    "t,a.qw,a.qx,a.qy,a.qz,a.wx,a.wy,a.wz,b.wx,b.wy,b.wz,j.phi,energy\n"
    "0,1,0,0,0,0.1,0.2,0.3,1,2,3,0.5,7\n"
    "0.01,0,1,0,0,0.4,0.5,0.6,4,5,6,0.6,7\r\n";

TEST(CalibRecording, AByteOrderMarkIsSkippedAsInScenes) {
  const Recording r = parse(std::string("\xEF\xBB\xBF") + kTwoBodies);
  EXPECT_EQ(r.time.size(), 2u);
  EXPECT_EQ(r.bodies.size(), 2u);
}

TEST(CalibRecording, DiscoversBodiesAndTheirColumnGroups) {
  const Recording r = parse(kTwoBodies);
  ASSERT_EQ(r.bodies.size(), 2u);  // j.phi and energy are not bodies
  EXPECT_EQ(r.bodies[0].name, "a");
  EXPECT_EQ(r.bodies[1].name, "b");
  ASSERT_EQ(r.time.size(), 2u);
  EXPECT_EQ(r.time[1], 0.01);
  ASSERT_EQ(r.bodies[0].orientation.size(), 2u);
  EXPECT_TRUE(r.bodies[0].orientation[1].quaternion().coeffs().isApprox(Eigen::Vector4d(1, 0, 0, 0)));  // (x,y,z,w)
  EXPECT_EQ(r.bodies[0].angular_velocity[1], Eigen::Vector3d(0.4, 0.5, 0.6));
  EXPECT_FALSE(r.bodies[1].hasOrientation());
  EXPECT_EQ(r.bodies[1].angular_velocity[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(r.bodyList(), "a, b");
  // The other columns are kept by name (the spring fit reads j.phi).
  ASSERT_EQ(r.scalars.size(), 2u);
  ASSERT_NE(r.column("j.phi"), nullptr);
  EXPECT_EQ(*r.column("j.phi"), (std::vector<double>{0.5, 0.6}));
  EXPECT_EQ(r.column("energy")->size(), 2u);
  EXPECT_EQ(r.column("a.wx"), nullptr);  // body columns are not scalars
  EXPECT_EQ(r.column("nope"), nullptr);
}

TEST(CalibRecording, NormalizesNearUnitQuaternions) {
  const Recording r = parse("t,a.qw,a.qx,a.qy,a.qz\n0,0.7071068,0.7071068,0,0\n");
  EXPECT_NEAR(r.bodies[0].orientation[0].quaternion().norm(), 1.0, 1e-15);
}

TEST(CalibRecording, SelectsTheJoint) {
  const Recording r = parse(kTwoBodies);
  JointSamples j = selectJoint(r, "", "");
  EXPECT_EQ(j.main.name, "a");
  EXPECT_EQ(j.secondary.name, "b");
  j = selectJoint(r, "b", "");
  EXPECT_EQ(j.secondary.name, "a");
  j = selectJoint(r, "", "a");
  EXPECT_EQ(j.main.name, "b");
  EXPECT_THROW(selectJoint(r, "a", "a"), InvalidInput);
  try {
    selectJoint(r, "c", "a");
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("no body 'c' in the recording (bodies: a, b)"), std::string::npos) << e.what();
  }
  const Recording three = parse("t,a.wx,a.wy,a.wz,b.wx,b.wy,b.wz,c.x,c.y,c.z\n0,1,2,3,4,5,6,7,8,9\n");
  EXPECT_EQ(three.bodies.size(), 3u);
  EXPECT_THROW(selectJoint(three, "", ""), InvalidInput);  // three bodies: names needed
  EXPECT_EQ(selectJoint(three, "b", "a").main.name, "b");
}

TEST(CalibRecording, BadInputNamesLineAndColumn) {
  const std::string header = "t,a.wx,a.wy,a.wz\n";
  expectError(header + "0,1,,3\n", {"rec.csv, line 2, column a.wy", "missing value"});
  expectError(header + "0,1,abc,3\n", {"line 2, column a.wy", "'abc' is not a number"});
  expectError(header + "0,1,2,3\n0.1,1,nan,3\n", {"line 3, column a.wy", "not finite"});
  expectError(header + "0,1,2,3\n0.1,1,inf,3\n", {"line 3, column a.wy", "not finite"});
  expectError(header + "0,1,2,3\n0.1,1,1e999,3\n", {"line 3, column a.wy", "not finite"});
  expectError(header + "0,1,2\n", {"line 2", "expected 4 values", "found 3"});
  expectError(header + "0,1,2,3,4\n", {"line 2", "found 5"});
  expectError(header + "0,1,2,3,\n", {"line 2", "found 5"});
  expectError(header + "0,1,2,3\n0,1,2,3\n", {"line 3, column t", "does not increase"});
  expectError(header + "0,1,2,3\n\n0.1,1,2,3\n", {"line 3", "empty row"});
  expectError(header, {"no data rows"});
  expectError("", {"empty file"});
  expectError("a.wx,a.wy,a.wz\n1,2,3\n", {"line 1", "no column t"});
  expectError("t,a.wx,a.wy\n0,1,2\n", {"line 1", "column a.wz missing", "a.wx,a.wy,a.wz"});
  expectError("t,a.qw,a.qx,a.qz\n0,1,0,0\n", {"column a.qy missing"});
  expectError("t,a.wx,a.wx,a.wz\n0,1,2,3\n", {"column a.wx appears twice"});
  expectError("t,a.qw,a.qx,a.qy,a.qz\n0,0.5,0,0,0\n", {"line 2, column a.qw", "norm 0.5"});
}

TEST(CalibRecording, TrailingBlankLinesAreFine) {
  EXPECT_EQ(parse("t,a.wx,a.wy,a.wz\n0,1,2,3\n\n\n").time.size(), 1u);
}

TEST(CalibRecording, MissingFileIsBadInput) {
  EXPECT_THROW(readRecording("/nonexistent/recording.csv"), InvalidInput);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
