/// \file
/// The `lieflow` command as users and scripts see it: exit statuses, the
/// CSV contract (header, first row t = 0, last row t_end whatever --every
/// is, 17 significant digits) and the --stats JSON keys.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/command_runner.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using Outcome = lieflow::testing_support::CommandOutcome;

Outcome run(const std::string& args) { return lieflow::testing_support::runLieflow(args); }

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string line;
  while (std::getline(s, line)) out.push_back(line);
  return out;
}

TEST(Cli, HelpAndListsSucceed) {
  for (const char* args : {"--help", "simulate --help", "study --help", "integrators", "scenes", "integrators --help"}) {
    const Outcome o = run(args);
    EXPECT_EQ(o.status, 0) << args << ": " << o.err;
    EXPECT_FALSE(o.out.empty()) << args;
  }
  const Outcome list = run("integrators");
  for (const char* name : {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk6", "rkmk45", "cg3", "cf4", "lgvi",
                           "splitting", "genalpha", "exact"})
    EXPECT_NE(list.out.find(name), std::string::npos) << name;
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(run("frobnicate").status, 2);
  EXPECT_EQ(run("simulate").status, 2);
  EXPECT_EQ(run("simulate heavy-top --dt -1").status, 2);
  EXPECT_EQ(run("simulate heavy-top --bogus 1").status, 2);
  const Outcome o = run("simulate heavy-top --integrator nope");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("nope"), std::string::npos) << o.err;
  const Outcome bad_scene = run("simulate /nonexistent/scene.json");
  EXPECT_EQ(bad_scene.status, 2);
  EXPECT_NE(bad_scene.err.find("/nonexistent/scene.json"), std::string::npos) << bad_scene.err;
}

TEST(Cli, BadSceneFileNamesFileFieldAndReason) {
  const std::string path = testing::TempDir() + "bad_scene.json";
  std::ofstream(path) << R"({"name": "x", "bodies": [{"name": "b", "mass": 1, "inertia": [1, 1, 5]}]})";
  const Outcome o = run("simulate " + path + " --integrator rkmk4 --dt 0.01 --t-end 1");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find(path), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("bodies[0].inertia"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("triangle"), std::string::npos) << o.err;
}

TEST(Cli, CsvHasFirstAndLastRowsWhateverEvery) {
  const std::string csv = testing::TempDir() + "traj.csv";
  const Outcome o = run("simulate abaqus-force-free --integrator rkmk4 --dt 0.01 --every 7 --out " + csv);
  ASSERT_EQ(o.status, 0) << o.err;
  std::ifstream f(csv);
  std::stringstream s;
  s << f.rdbuf();
  const std::vector<std::string> rows = lines(s.str());
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(rows[0],
            "t,body.qw,body.qx,body.qy,body.qz,body.wx,body.wy,body.wz,energy,Lx,Ly,Lz,constraint_error");
  EXPECT_EQ(rows[1].substr(0, 2), "0,");
  EXPECT_EQ(rows.back().substr(0, 2), "2,");
  EXPECT_EQ(rows.size(), 1u + 1u + 200u / 7u + 1u);  // header, t = 0, every 7th, t = 2
  // 17 significant digits: ω₃ = 2π prints as 6.2831853071795862.
  EXPECT_NE(rows[1].find("6.2831853071795862"), std::string::npos) << rows[1];
}

TEST(Cli, AModelOrSceneWithoutAnIntegratorRunsTheNamedDefault) {
  // No integrator object, no step: rkmk4 at MuJoCo's 0.002 s, or shorter for
  // a fast scene (0.05/omega), said on stderr and in --stats.
  const std::string plain = lieflow::testing_support::testFile("no_integrator.json"),
                    fast = lieflow::testing_support::testFile("fast_no_integrator.json");
  std::ofstream(plain) << R"({"name": "plain", "gravity": [0, 0, -9.81], "t_end": 0.1,
    "bodies": [{"name": "b", "mass": 1, "inertia": [1, 2, 3], "angular_velocity": [0.1, 0.2, 0.3]}]})";
  std::ofstream(fast) << R"({"name": "fast", "gravity": [0, 0, 0], "t_end": 0.01,
    "bodies": [{"name": "b", "mass": 1, "inertia": [1, 2, 3], "angular_velocity": [0, 0, 300]}]})";
  const Outcome o = run("simulate " + plain + " --stats");
  ASSERT_EQ(o.status, 0) << o.err;
  const auto stats = nlohmann::json::parse(o.out);
  EXPECT_EQ(stats["integrator"], "rkmk4");
  EXPECT_EQ(stats["dt"], 0.002);
  EXPECT_NE(o.err.find("names no integrator: running rkmk4 at dt = 0.002 s"), std::string::npos) << o.err;
  // |omega| = 300 rad/s: 0.05/300 = 1.67e-4, rounded down to 1e-4.
  const Outcome f = run("simulate " + fast + " --stats");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_EQ(nlohmann::json::parse(f.out)["dt"], 1e-4);
  // --dt alone keeps the default integrator; --integrator alone the default step.
  const Outcome d = run("simulate " + plain + " --dt 0.01 --stats");
  EXPECT_EQ(nlohmann::json::parse(d.out)["dt"], 0.01);
  EXPECT_NE(d.err.find("names no integrator: running rkmk4 at dt = 0.01 s"), std::string::npos) << d.err;
  const Outcome i = run("simulate " + plain + " --integrator cf4 --stats");
  EXPECT_EQ(nlohmann::json::parse(i.out)["integrator"], "cf4");
  EXPECT_NE(i.err.find("names no step: running cf4 at dt = 0.002 s"), std::string::npos) << i.err;
  // A scene that names both says nothing.
  EXPECT_EQ(run("simulate heavy-top --t-end 0.01 --stats").err, "");
}

TEST(Cli, ChecksAtTheRowsUnlessCheckEveryAsksForMore) {
  const Outcome sparse = run("simulate chain-3 --t-end 1 --every 1000000 --stats");
  const Outcome dense = run("simulate chain-3 --t-end 1 --every 1000000 --check-every 1 --stats");
  ASSERT_EQ(sparse.status, 0) << sparse.err;
  ASSERT_EQ(dense.status, 0) << dense.err;
  const auto s = nlohmann::json::parse(sparse.out), d = nlohmann::json::parse(dense.out);
  EXPECT_EQ(s["checked_every"], 1000000);
  EXPECT_EQ(d["checked_every"], 1);
  EXPECT_LE(s["energy_drift"].get<double>(), d["energy_drift"].get<double>());
  EXPECT_EQ(run("simulate chain-3 --check-every 0").status, 2);
}

TEST(Cli, StatsJsonHasTheContractKeys) {
  const Outcome o = run("simulate heavy-top --integrator cf4 --stats");
  ASSERT_EQ(o.status, 0) << o.err;
  for (const char* key : {"\"integrator\"", "\"dt\"", "\"steps\":2000", "\"wall_seconds\"", "\"ns_per_step\"",
                          "\"energy_drift\"", "\"momentum_drift\"", "\"constraint_error\"",
                          "\"newton_iterations_mean\"", "\"failed\":false", "\"failure\""})
    EXPECT_NE(o.out.find(key), std::string::npos) << key << " in " << o.out;
}

TEST(Cli, BlowUpExitsOneWithMessageAndNoNaN) {
  const std::string csv = testing::TempDir() + "blowup.csv";
  const Outcome o = run("simulate heavy-top --integrator rkmk-euler --dt 0.001 --stats --out " + csv);
  EXPECT_EQ(o.status, 1);
  EXPECT_NE(o.err.find("blow-up"), std::string::npos) << o.err;
  EXPECT_NE(o.out.find("\"failed\":true"), std::string::npos) << o.out;
  std::ifstream f(csv);
  std::stringstream s;
  s << f.rdbuf();
  EXPECT_EQ(s.str().find("nan"), std::string::npos);
}

TEST(Cli, PendulumOnARevoluteJointKeepsItsConstraint) {
  const Outcome o = run("simulate pendulum --stats");
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string key = "\"constraint_error\":";
  const auto pos = o.out.find(key);
  ASSERT_NE(pos, std::string::npos) << o.out;
  EXPECT_LE(std::stod(o.out.substr(pos + key.size())), 1e-10) << o.out;
  EXPECT_NE(o.out.find("\"failed\":false"), std::string::npos) << o.out;
}

TEST(Cli, BadJointExitsTwoNamingFileAndField) {
  const std::string path = testing::TempDir() + "bad_joint.json";
  std::ofstream(path) << R"({"name": "x", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "rod", "mass": 1, "inertia": [0.1, 0.1, 0.01], "position": [0, 0, -0.5]}],
    "joints": [{"name": "hinge", "type": "revolute", "main": "ground", "secondary": "rod",
                "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 0, 0]}]})";
  const Outcome o = run("simulate " + path + " --integrator rkmk4 --dt 0.01 --t-end 1");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find(path), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("joints[0] (hinge).axis_main"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("zero"), std::string::npos) << o.err;
}

}  // namespace

namespace {

TEST(Cli, StudyWritesCsvAndErrorsShrinkAtFourthOrder) {
  const std::string dir = testing::TempDir() + "study_cli";
  const Outcome o = run("study abaqus-force-free --integrators rkmk4,lgvi --dt 0.02,0.01 --min-time 0.001 "
                        "--no-plots --out " + dir);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_NE(o.out.find("exact flow"), std::string::npos) << o.out;
  std::ifstream f(dir + "/study.csv");
  std::stringstream s;
  s << f.rdbuf();
  const std::vector<std::string> rows = lines(s.str());
  ASSERT_EQ(rows.size(), 5u) << s.str();
  auto error_of = [&](const std::string& row) {
    std::stringstream r(row);
    std::string cell;
    for (int i = 0; i < 8; ++i) std::getline(r, cell, ',');
    return std::stod(cell);  // orientation_error column
  };
  // rows: header, rkmk4 0.02, rkmk4 0.01, lgvi 0.02, lgvi 0.01
  const double rk4_ratio = error_of(rows[1]) / error_of(rows[2]);
  const double lgvi_ratio = error_of(rows[3]) / error_of(rows[4]);
  EXPECT_NEAR(std::log2(rk4_ratio), 4.0, 0.3) << rows[1] << "\n" << rows[2];
  EXPECT_NEAR(std::log2(lgvi_ratio), 2.0, 0.3) << rows[3] << "\n" << rows[4];
  std::ifstream drift(dir + "/drift.csv");
  EXPECT_TRUE(drift.good());
}

/// The reference of a scene with joints claims Richardson's fifteenth of
/// |y_h − y_2h| only where a run at 4h shows fourth order: with steps so
/// short that the runs differ by round-off, its error is that difference.
TEST(Cli, StudyReferenceErrorIsRichardsonOnlyWhereTheStepsShowFourthOrder) {
  const std::string dir = testing::TempDir() + "study_reference";
  const Outcome truncation = run("study double-pendulum --integrators rkmk4 --dt 0.01 --t-end 0.2 "
                                 "--min-time 0.001 --no-plots --out " + dir);
  ASSERT_EQ(truncation.status, 0) << truncation.err;
  EXPECT_NE(truncation.out.find("by Richardson"), std::string::npos) << truncation.out;
  EXPECT_NE(truncation.out.find(": fourth order)"), std::string::npos) << truncation.out;
  const Outcome roundoff = run("study double-pendulum --integrators rkmk4 --dt 0.001 --t-end 0.004 "
                               "--min-time 0.001 --no-plots --out " + dir);
  ASSERT_EQ(roundoff.status, 0) << roundoff.err;
  EXPECT_EQ(roundoff.out.find("by Richardson"), std::string::npos) << roundoff.out;
  EXPECT_NE(roundoff.out.find("(round-off: the run at"), std::string::npos) << roundoff.out;
}

}  // namespace
