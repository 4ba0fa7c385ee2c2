/// \file
/// Runs as a hostile user starts them (issue 28), one test per class of what
/// was not answered cleanly: overflowing springs, starts that fail at once,
/// refusals that must leave nothing behind, outputs that are devices or
/// links, inputs that never end, relative errors against a reference near
/// zero, numbers in messages, and MuJoCo beside lieflow on models whose
/// bodies have no names.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "model/import/model_import.hpp"
#include "tests/command_runner.hpp"

namespace {

using Outcome = lieflow::testing_support::CommandOutcome;
using lieflow::testing_support::runLieflow;
using lieflow::testing_support::slurp;
using lieflow::testing_support::testFile;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string scene(const std::string& name) { return std::string(LIEFLOW_SOURCE_DIR) + "/scenes/" + name + ".json"; }

/// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

/// No message of lieflow's shows a library's internals or a number no one
/// can read: "0.000000" (%f of a small number), 30 digits in a row
/// (std::to_string of a huge one), nlohmann's, tinyxml2's, Ceres' or MuJoCo's
/// own codes.
void expectReadableMessage(const std::string& err) {
  EXPECT_FALSE(contains(err, "0.000000")) << err;
  EXPECT_FALSE(std::regex_search(err, std::regex("[0-9]{30}"))) << err;
  for (const char* internal : {"json.exception", "ErrorID", "Residual and Jacobian", "Object name =",
                               "tangent coordinates", "std::bad_alloc"})
    EXPECT_FALSE(contains(err, internal)) << err;
}

TEST(HostileRuns, ASpringWhoseEnergyWouldOverflowIsRefusedWhereItIsRead) {
  // rest_angle 1e200 once crashed the row writer: ½k(φ − φ₀)² overflowed.
  const std::string path = testFile(".json");
  std::ofstream(path) << replaced(slurp(scene("spring-hinge")), "\"rest_angle\": 0.1", "\"rest_angle\": 1e200");
  ASSERT_TRUE(contains(slurp(path), "1e200"));
  for (const std::string& extra : {std::string(), std::string(" --stats"), std::string(" --formulation joint"),
                                   " --integrator lgvi --out " + testFile(".csv")}) {
    const Outcome o = runLieflow("simulate " + path + " --t-end 0.01" + extra);
    EXPECT_EQ(o.signal, 0) << extra;
    EXPECT_EQ(o.status, 2) << extra << o.err;
    EXPECT_TRUE(contains(o.err, "joints[0].spring.rest_angle: 1e+200 is beyond ±1e+30")) << o.err;
    EXPECT_TRUE(o.out.empty()) << o.out;
  }
  EXPECT_FALSE(std::ifstream(testFile(".csv") + ".partial").good());
}

TEST(HostileRuns, ARunThatFailsAtItsFirstStateSaysWhyWithoutACrash) {
  // Within the bounds, a spring of 1e30 N m/rad at 1e-2 s blows up at once;
  // every integrator ends in exit 1 with its reason (it once segfaulted
  // writing a last row no state had filled).
  const std::string path = testFile(".json");
  std::ofstream(path) << replaced(slurp(scene("spring-hinge")), "\"stiffness\": 12.0", "\"stiffness\": 1e30");
  ASSERT_TRUE(contains(slurp(path), "1e30"));
  for (const char* integrator : {"rkmk4", "rkmk-euler", "cf4", "lgvi", "genalpha", "rkmk45"}) {
    const Outcome o = runLieflow("simulate " + path + " --t-end 0.05 --dt 0.01 --integrator " + integrator);
    EXPECT_EQ(o.signal, 0) << integrator;
    EXPECT_TRUE(o.status == 0 || o.status == 1) << integrator << ": " << o.err;
    if (o.status == 1) {
      EXPECT_TRUE(contains(o.err, "failed")) << o.err;
    }
    EXPECT_FALSE(std::regex_search(o.out, std::regex("(^|,)-?(nan|inf)(,|$)", std::regex::multiline))) << o.out;
  }
}

TEST(HostileRuns, RefusedRunsLeaveNothingBehind) {
  const std::string csv = testFile(".csv");
  std::remove(csv.c_str());
  for (const char* bad : {"--options bogus=1", "--options rho_inf=2 --integrator genalpha", "--max-steps 5",
                          "--t-end 1e9", "--dt 1e-320"}) {
    const Outcome o = runLieflow(std::string("simulate pendulum ") + bad + " --out " + csv);
    EXPECT_EQ(o.status, 2) << bad << o.err;
    EXPECT_FALSE(std::ifstream(csv).good()) << bad;
    EXPECT_FALSE(std::ifstream(csv + ".partial").good()) << bad << ": a .partial file was left behind";
    const Outcome s = runLieflow(std::string("simulate pendulum ") + bad);
    EXPECT_EQ(s.status, 2) << bad;
    EXPECT_TRUE(s.out.empty()) << bad << ": wrote " << s.out;  // not even the CSV header
    expectReadableMessage(s.err);
  }
  const std::string dir = testFile("_study/sub");
  const std::string upside_down = std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/scenes/gimbal-upside-down.json";
  for (const std::string bad : {std::string("pendulum --integrators bogus"), upside_down + " --formulation joint",
                                std::string("pendulum --max-steps 5"), std::string("pendulum --options bogus=1")}) {
    const Outcome o = runLieflow(std::string("study ") + bad + " --t-end 0.05 --no-plots --out " + dir);
    EXPECT_EQ(o.status, 2) << bad << o.err;
    EXPECT_FALSE(std::filesystem::exists(testFile("_study"))) << bad << ": an empty output directory was left";
  }
  const Outcome st = runLieflow("stability pendulum --integrators bogus --no-plots --out " + dir);
  EXPECT_EQ(st.status, 2) << st.err;
  EXPECT_FALSE(std::filesystem::exists(testFile("_study")));
}

TEST(HostileRuns, AStudyNoIntegratorCanRunIsRefusedBeforeItsReference) {
  // (a gimbal hung from its secondary body, tests/data/scenes: every
  // built-in scene now has joint coordinates, slider-crank's weld among them.)
  for (const std::string s : {std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/scenes/gimbal-upside-down.json"}) {
    const Outcome o = runLieflow(std::string("study ") + s + " --formulation joint --t-end 0.05 --no-plots --out " +
                                 testFile("_out"));
    EXPECT_EQ(o.status, 2) << s << o.err;
    EXPECT_TRUE(contains(o.err, "--formulation: joint coordinates cannot represent this scene")) << o.err;
    EXPECT_FALSE(contains(o.err, "computing the reference")) << o.err;
  }
}

TEST(HostileRuns, OutputsThatAreDevicesOrLinksAreWrittenNotReplaced) {
  const Outcome o = runLieflow("simulate pendulum --t-end 0.01 --out /dev/null");
  EXPECT_EQ(o.status, 0) << o.err;
  struct stat st;
  ASSERT_EQ(stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null was replaced";
  const std::string target = testFile("_target.csv"), link = testFile("_link.csv");
  std::remove(target.c_str());
  std::remove(link.c_str());
  ASSERT_EQ(symlink(target.c_str(), link.c_str()), 0);
  const Outcome l = runLieflow("simulate pendulum --t-end 0.01 --out " + link);
  EXPECT_EQ(l.status, 0) << l.err;
  struct stat ls;
  ASSERT_EQ(lstat(link.c_str(), &ls), 0);
  EXPECT_TRUE(S_ISLNK(ls.st_mode)) << "the link was replaced by a file";
  EXPECT_TRUE(contains(slurp(target), "rod.qw")) << "the link's target was not written";
}

TEST(HostileRuns, InputsThatNeverEndOrNeverStartAreRefused) {
  const std::string fifo = testFile(".json");
  std::remove(fifo.c_str());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const Outcome o = runLieflow("simulate " + fifo + " --stats");  // no program writes to it
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_TRUE(contains(o.err, "is empty")) << o.err;
  std::remove(fifo.c_str());
  const Outcome d = runLieflow("simulate " + std::string(LIEFLOW_SOURCE_DIR) + "/scenes --stats");
  EXPECT_EQ(d.status, 2) << d.err;
  EXPECT_TRUE(contains(d.err, "is a directory")) << d.err;
}

TEST(HostileRuns, RelativeErrorsDoNotExplodeAgainstAReferenceNearZero) {
  // A free body at rest with 1e-300 rad/s, falling: the study's relative
  // errors were its round-off divided by 1e-300.
  const std::string path = testFile(".json");
  std::ofstream(path) << R"({"name": "resting", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "b", "mass": 1, "inertia": [1, 2, 3], "angular_velocity": [1e-300, 0, 0],
                "velocity": [0, 0, 1e-300]}],
    "integrator": {"name": "rkmk4", "dt": 0.01}, "t_end": 0.2})";
  const std::string dir = testFile("_study");
  const Outcome o = runLieflow("study " + path + " --integrators rkmk4,lgvi --min-time 0.001 --no-plots --out " + dir);
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string csv = slurp(dir + "/study.csv") + slurp(dir + "/drift.csv");
  // Every number in both files is a small error or a count or a time.
  const std::regex large("[-0-9.]+e\\+([0-9]+)");
  for (auto it = std::sregex_iterator(csv.begin(), csv.end(), large);
       it != std::sregex_iterator(); ++it)
    EXPECT_LT(std::stoi((*it)[1].str()), 6) << "a value of " << (*it)[0].str() << " in\n" << csv;
}

TEST(HostileRuns, NumbersInMessagesAreReadable) {
  const std::string rec = testFile(".csv");
  ASSERT_EQ(runLieflow("simulate hinge-pair --t-end 1 --out " + rec).status, 0);
  for (const char* cutoff : {"4.6e-8", "1e-300", "1e300", "490"}) {
    const Outcome o = runLieflow("calibrate hinge " + rec + " --low-pass " + std::string(cutoff));
    EXPECT_EQ(o.signal, 0) << cutoff;
    EXPECT_EQ(o.status, 2) << cutoff << o.err;
    expectReadableMessage(o.err);
  }
  const Outcome t = runLieflow("simulate pendulum --dt 1e-320 --t-end 0.01");
  EXPECT_EQ(t.status, 2);
  EXPECT_FALSE(contains(t.err, "inf steps")) << t.err;
  expectReadableMessage(t.err);
}

TEST(HostileRuns, GyroscopesOnlyOnARecordingWithIdleAccelerometersStillAnswers) {
  // hinge-pair has no gravity and its sensors sit at the centres of mass: the
  // accelerometers of `--imu` read zero, and the joint-centre solve once
  // failed with Ceres' "Residual and Jacobian evaluation failed", throwing
  // the axes' answer away.
  const std::string rec = testFile(".csv");
  ASSERT_EQ(runLieflow("simulate hinge-pair --imu --t-end 2 --noise-gyro 0.01 --seed 1 --out " + rec).status, 0);
  const Outcome o = runLieflow("calibrate hinge " + rec + " --use gyroscopes");
  EXPECT_EQ(o.status, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "\"axis_main\"")) << o.out;
  EXPECT_TRUE(contains(o.out, "\"anchor_note\"")) << o.out;
  expectReadableMessage(o.err + o.out);
}

TEST(HostileRuns, RecordingsTooShortForAFitAreAnsweredInWords) {
  // Two or three rows with --fit-time-offset once aborted in Ceres (a
  // parameter block with no residual); the likelihood fit read past its
  // differencing stencil.
  const std::string rec = testFile(".csv");
  ASSERT_EQ(runLieflow("simulate hinge-pair --t-end 1 --out " + rec).status, 0);
  const std::string full = slurp(rec);
  for (int rows : {1, 2, 3, 6}) {
    std::size_t end = 0;
    for (int k = 0; k <= rows; ++k) end = full.find('\n', end) + 1;  // the header and `rows` rows
    const std::string path = testFile("_short.csv");
    std::ofstream(path) << full.substr(0, end);
    for (const char* flags : {"hinge", "hinge --fit-time-offset", "hinge --fit-gyro-bias", "hinge --estimator likelihood",
                              "hinge --estimator likelihood --fit-time-offset", "universal --fit-time-offset",
                              "universal --fit-gyro-bias", "spherical"}) {
      const std::string command = std::string("calibrate ") + flags;
      const Outcome o = runLieflow(command.substr(0, command.find(' ', 10)) + " " + path + command.substr(
                                       std::min(command.size(), command.find(' ', 10))));
      EXPECT_EQ(o.signal, 0) << rows << flags;
      EXPECT_TRUE(o.status == 1 || o.status == 2) << rows << " rows" << flags << ": " << o.status << o.err << o.out;
      EXPECT_FALSE(o.err.empty()) << rows << flags;
      expectReadableMessage(o.err + o.out);
    }
  }
}

TEST(HostileRuns, SceneFileMessagesAreWordsWithTheLine) {
  const std::string path = testFile(".json");
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"{\"name\": \"s\",\n \"bodies\": [}", "not valid JSON: line 2, column "},
      {"{\"name\": \"s\", \"bodies\": [{\"name\": \"b\", \"mass\": 1e999999, \"inertia\": [1, 2, 3]}]}",
       "the number 1e999999 overflows a double"},
      {"{\"name\": \"s\", \"bodies\": [{\"name\": \"b\", \"mass\": 1, \"inertia\": [1e-40, 1e-40, 1e-40]}]}",
       "bodies[0].inertia: principal moment 1e-40 is below"},
      {"{\"name\": \"s\", \"bodies\": [{\"name\": \"b\", \"mass\": 1e-40, \"inertia\": [1, 2, 3]}]}",
       "bodies[0].mass"},
      {"{\"name\": \"s\", \"bodies\": [{\"name\": \"b\", \"mass\": 1, \"inertia\": [1, 2, 3]}], \"joints\": [{\"name\": "
       "\"b\", \"type\": \"spherical\", \"main\": \"ground\", \"secondary\": \"b\", \"anchor_main\": [0, 0, 0], \"anchor_secondary\": [0, 0, 0]}]}",
       "joints[0].name: 'b' is also the name of bodies[0]"},
  };
  for (const Case& c : cases) {
    std::ofstream(path) << c.text;
    const Outcome o = runLieflow("simulate " + path + " --t-end 0.01");
    EXPECT_EQ(o.status, 2) << c.text << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << c.text << "\n" << o.err;
    EXPECT_EQ(o.err.find("parse_error"), std::string::npos) << o.err;
    expectReadableMessage(o.err);
  }
}

TEST(HostileRuns, MujocoBesideLieflowOnBodiesWithoutNames) {
  const std::string model = "/usr/share/mujoco/model/slider_crank/slider_crank.xml";
  if (!lieflow::canReadMjcf() || !std::ifstream(model).good()) GTEST_SKIP() << "no MuJoCo or its sample models";
  const std::string dir = testFile("_study");
  const Outcome o = runLieflow("study " + model + " --ignore all --with-mujoco --integrators rkmk4 --dt 0.002,0.001"
                               " --t-end 0.01 --min-time 1e-4 --no-plots --out " + dir);
  EXPECT_EQ(o.status, 0) << o.err;
  const std::string csv = slurp(dir + "/study.csv");
  EXPECT_TRUE(contains(csv, "mujoco-rk4")) << csv;
  EXPECT_FALSE(contains(o.out, "WARNING")) << o.out;  // MuJoCo's warnings stay off stdout
}

}  // namespace
