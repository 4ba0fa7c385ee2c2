/// \file
/// Model files on the command line: `lieflow import MODEL [--out]`, model
/// files as SCENE in simulate, `--ignore` and its report on stderr, and the
/// prismatic and fixed joints' CSV columns.
#include <gtest/gtest.h>

#include <fstream>
#include <iostream>
#include <string>

#include "model/import/model_import.hpp"
#include "tests/command_runner.hpp"

namespace {

using Outcome = lieflow::testing_support::CommandOutcome;
using lieflow::testing_support::runLieflow;
using lieflow::testing_support::slurp;
using lieflow::testing_support::testFile;

std::string model(const std::string& file) { return std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/models/" + file; }

TEST(ModelCli, ImportWritesASceneThatRunsLikeTheModel) {
  if (!lieflow::canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const std::string scene = testFile(".json"), a = testFile("_a.csv"), b = testFile("_b.csv");
  Outcome o = runLieflow("import " + model("arm6.urdf") + " --out " + scene);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_NE(slurp(scene).find("\"name\": \"j6\""), std::string::npos);
  o = runLieflow("simulate " + scene + " --integrator rkmk4 --dt 0.01 --t-end 0.3 --out " + a);
  ASSERT_EQ(o.status, 0) << o.err;
  o = runLieflow("simulate " + model("arm6.urdf") + " --integrator rkmk4 --dt 0.01 --t-end 0.3 --out " + b);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_NE(slurp(a).find("j1.phi,j1.phidot,j1.moment"), std::string::npos);
}

TEST(ModelCli, UnrepresentedFeaturesExitTwoOrAreReportedWhenIgnored) {
  if (!lieflow::canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const std::string path = model("limited.urdf");  // a joint limit and a collision shape
  Outcome o = runLieflow("simulate " + path + " --integrator rkmk4 --dt 0.01 --t-end 0.1");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("limit of joint 'hinge' (line 6)"), std::string::npos) << o.err;
  o = runLieflow("simulate " + path + " --ignore limits --integrator rkmk4 --dt 0.01 --t-end 0.1");
  EXPECT_EQ(o.status, 2);  // the collision shape is still there
  EXPECT_NE(o.err.find("collision of link 'arm' (line 10)"), std::string::npos) << o.err;
  o = runLieflow("simulate " + path + " --ignore limits,contacts --integrator rkmk4 --dt 0.01 --t-end 0.1 --stats");
  EXPECT_EQ(o.status, 0) << o.err;
  EXPECT_NE(o.err.find("ignored limits: 1 element (limit of joint 'hinge' (line 6))"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("ignored contacts: 1 element (collision of link 'arm' (line 10))"), std::string::npos) << o.err;
  o = runLieflow("simulate " + path + " --ignore limits,contacts --integrator rkmk4 --dt 0.01 --t-end 0.1 --stats "
                 "--verbose");
  EXPECT_EQ(o.status, 0) << o.err;
  EXPECT_NE(o.err.find("ignored limits: limit of joint 'hinge' (line 6)"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("ignored contacts: collision of link 'arm' (line 10)"), std::string::npos) << o.err;
  o = runLieflow("simulate pendulum --ignore limits");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("not a model file"), std::string::npos) << o.err;
  o = runLieflow("import " + path + " --ignore frobs");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("unknown feature 'frobs'"), std::string::npos) << o.err;
}

TEST(ModelCli, IgnoredElementsAreOneLinePerCategoryUnlessVerbose) {
  // A chain of 40 links, each with a collision box and a limited joint: two
  // lines (limits, contacts) with counts and the first three elements, one
  // line per element with --verbose.
  if (!lieflow::canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const std::string path = testFile("_many.urdf");
  {
    std::ofstream f(path);
    f << "<robot name=\"many\"><link name=\"l0\"/>\n";
    for (int i = 1; i <= 40; ++i)
      f << "<joint name=\"j" << i << "\" type=\"revolute\"><parent link=\"l" << i - 1 << "\"/><child link=\"l" << i
        << "\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
           "velocity=\"1\"/></joint>\n<link name=\"l"
        << i << "\"><inertial><origin xyz=\"0 0 0.05\"/><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" "
           "izz=\"0.001\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial><collision><geometry><box size=\"0.1 0.1 "
           "0.1\"/></geometry></collision></link>\n";
    f << "</robot>\n";
  }
  const auto lines = [](const std::string& text, const std::string& what) {
    int n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  Outcome o = runLieflow("import " + path + " --ignore all --out " + testFile("_many.json"));
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(lines(o.err, "\n"), 3) << o.err;  // limits, contacts, and the fixed root
  EXPECT_NE(o.err.find("ignored limits: 40 elements (limit of joint 'j1' (line 2), limit of joint 'j2' (line 4), "
                       "limit of joint 'j3' (line 6), and 37 more; --verbose lists them)"),
            std::string::npos)
      << o.err;
  EXPECT_NE(o.err.find("ignored contacts: 40 elements ("), std::string::npos) << o.err;
  o = runLieflow("import " + path + " --ignore all --verbose --out " + testFile("_many.json"));
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(lines(o.err, "ignored limits: limit of joint"), 40) << o.err;
  EXPECT_EQ(lines(o.err, "ignored contacts: collision of link"), 40) << o.err;
}

TEST(ModelCli, SliderCrankWritesThePrismaticAndFixedColumns) {
  const std::string csv = testFile(".csv");
  const Outcome o = runLieflow("simulate slider-crank --t-end 0.05 --out " + csv);
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string header = slurp(csv).substr(0, slurp(csv).find('\n'));
  EXPECT_NE(header.find("weld.fx,weld.fy,weld.fz,weld.mx,weld.my,weld.mz"), std::string::npos) << header;
  EXPECT_NE(header.find("guide.x,guide.xdot,guide.force"), std::string::npos) << header;
  EXPECT_NE(header.find("wrist.phi1,wrist.phi2"), std::string::npos) << header;
}

TEST(ModelCli, StudyWithMujocoPutsMuJoCosIntegratorsBesideLieflows) {
  const std::string dir = testFile("_study");
  Outcome o = runLieflow("study pendulum --with-mujoco --no-plots --out " + dir);
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--with-mujoco: MuJoCo runs beside lieflow on a model file"), std::string::npos) << o.err;
  if (!lieflow::canReadMjcf()) GTEST_SKIP() << "this build has no MJCF reader";
  o = runLieflow("study " + model("spinning.xml") + " --keyframe spin --with-mujoco --integrators rkmk4,lgvi "
                 "--dt 0.004,0.002 --t-end 0.2 --min-time 0.001 --no-plots --out " + dir);
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string csv = slurp(dir + "/study.csv");
  for (const char* name : {"mujoco-euler", "mujoco-rk4", "mujoco-implicit"})
    EXPECT_NE(csv.find(std::string("spinning,") + name + ",0.002"), std::string::npos) << name << "\n" << csv;
  EXPECT_NE(csv.find("MuJoCo RK4 at h = 6.25e-05 differs from it by"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",L_com_drift,energy_balance_drift"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("nan"), std::string::npos) << csv;
  const std::string drift = slurp(dir + "/drift.csv");
  EXPECT_NE(drift.find("\nmujoco-rk4,"), std::string::npos);
  o = runLieflow("simulate " + model("spinning.xml") + " --keyframe jump");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("no keyframe 'jump' (it has rest, spin)"), std::string::npos) << o.err;
  o = runLieflow("simulate pendulum --keyframe 0");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("only MJCF models have keyframes"), std::string::npos) << o.err;
}

/// The study's check of its reference against MuJoCo RK4 at the smallest
/// step: "MuJoCo RK4 at h = H differs from it by X rad" (X, or -1).
double mujocoDifference(const std::string& csv) {
  const std::string key = "differs from it by ";
  const std::size_t at = csv.find(key);
  return at == std::string::npos ? -1.0 : std::stod(csv.substr(at + key.size()));
}

TEST(ModelCli, StudyWithMujocoReadsAUrdfWithMujocosOwnReader) {
  // MuJoCo's URDF reader on the same file (meshes and visuals left out in
  // memory, welded links kept as bodies): the arm agrees with lieflow's
  // reference to round-off, fixed and with --floating-base; the hand's
  // mimics become MuJoCo joint equalities, exact in lieflow and soft in
  // MuJoCo at its stiffest (impedance 0.9999), which is their difference.
  if (!lieflow::canReadMjcf() || !lieflow::canReadUrdf()) GTEST_SKIP() << "this build lacks MuJoCo or urdfdom";
  struct Case {
    std::string args;
    double bound;
  };
  for (const Case& c : {Case{model("arm6.urdf") + " --dt 0.002", 1e-11},
                        Case{model("arm6.urdf") + " --floating-base --dt 0.002", 1e-11},
                        // Turning (--spin), both engines from the same start: what
                        // is left is MuJoCo's RK4 turning its free joint at
                        // second order (1.6e-6 rad at h = 2 ms, 1.5e-9 at the
                        // reference's h/32; a different start would differ at
                        // first order in the rate).
                        Case{model("arm6.urdf") + " --floating-base --spin 0.5,-1,2 --dt 0.002", 5e-9},
                        Case{model("hand.urdf") + " --ignore limits --dt 0.0005", 1e-6}}) {
    SCOPED_TRACE(c.args);
    const std::string dir = testFile("_urdf_study");
    const Outcome o = runLieflow("study " + c.args + " --with-mujoco --integrators rkmk4 --t-end 0.5 --min-time 0.001 "
                                 "--no-plots --out " + dir);
    ASSERT_EQ(o.status, 0) << o.err;
    const std::string csv = slurp(dir + "/study.csv");
    EXPECT_NE(csv.find(",mujoco-rk4,"), std::string::npos) << csv;
    const double difference = mujocoDifference(csv);
    std::cout << "[ measured ] " << c.args.substr(c.args.find_last_of('/') + 1)
              << ": MuJoCo RK4 on the URDF against lieflow's reference after 0.5 s: " << difference << " rad\n";
    EXPECT_GE(difference, 0.0) << csv;
    EXPECT_LE(difference, c.bound) << csv;
  }
}

}  // namespace
