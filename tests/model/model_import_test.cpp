/// \file
/// Model files as scenes (model/import/), against references that do not
/// come from the importer:
///  * the same six-joint arm as URDF (urdfdom) and as MJCF (MuJoCo's
///    compiler) gives the same scene and the same trajectory (1e-10);
///  * every MJCF joint lieflow maps (free, ball, two hinges as a universal
///    joint with springs about springref and dashpots, a sprung slide) against
///    MuJoCo's own RK4 on the same model;
///  * welded links merged: the arm's tool and base (parallel-axis theorem by hand);
///  * `lieflow import` writes a scene file that reads back to the same text;
///  * what lieflow cannot represent is refused naming the elements and lines,
///    and with --ignore the run lists them; broken files name file, line and reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "model/import/model_import.hpp"
#include "model/scene.hpp"
#include "model/scene_writer.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/model/model_files.hpp"
#include "tests/simulation/scene_trajectory.hpp"

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace lieflow {
namespace {

using namespace scene_testing;  // NOLINT: Trajectory, simulate, model, refusal

/// A model file written for one test (removed at the end of the test).
class TempModel {
 public:
  TempModel(const std::string& name, const std::string& text)
      : path_(std::string(LIEFLOW_BINARY_DIR) + "/model_import_test_" + name) {
    std::ofstream(path_) << text;
  }
  ~TempModel() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

void expectContains(const std::string& text, std::initializer_list<const char*> parts) {
  for (const char* p : parts) EXPECT_NE(text.find(p), std::string::npos) << "'" << p << "' not in: " << text;
}

bool haveBothReaders() { return canReadUrdf() && canReadMjcf(); }

TEST(ModelImport, ArmFromUrdfAndFromMjcfIsTheSameScene) {
  if (!haveBothReaders()) GTEST_SKIP() << "this build reads " << (canReadUrdf() ? "URDF" : "no URDF") << " and "
                                       << (canReadMjcf() ? "MJCF" : "no MJCF");
  const SceneDescription u = importModel(model("arm6.urdf"), {});
  const SceneDescription x = importModel(model("arm6.xml"), {});
  // The base is welded to the world (ground), the tool merged into link6.
  ASSERT_EQ(u.bodies.size(), 6u);
  ASSERT_EQ(x.bodies.size(), 6u);
  ASSERT_EQ(u.joints.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(u.bodies[i].name, x.bodies[i].name);
    EXPECT_NEAR(u.bodies[i].mass, x.bodies[i].mass, 1e-15);
    EXPECT_LE((u.bodies[i].inertia - x.bodies[i].inertia).norm(), 1e-15);
    EXPECT_LE((u.bodies[i].position - x.bodies[i].position).norm(), 1e-15);
    EXPECT_EQ(u.joints[i].name, x.joints[i].name);
    EXPECT_LE((u.joints[i].axis_main - x.joints[i].axis_main).norm(), 1e-15);
    EXPECT_NEAR(u.joints[i].coordinates[0].damping, x.joints[i].coordinates[0].damping, 0.0);
  }
  EXPECT_EQ(u.joints[0].main, "ground");
  // link6 + tool by hand: m = 0.3, c = (0.2·c6 + 0.1·ct)/0.3 along the arm.
  const BodyDescription& l6 = u.bodies[5];
  EXPECT_EQ(l6.name, "link6");
  EXPECT_NEAR(l6.mass, 0.3, 1e-15);
  const Eigen::Vector3d j6(0.3 + 0.25 + 0.06 + 0.05, 0.0, 0.1 + 0.2);  // joint j6 at the zero configuration
  const Eigen::Vector3d c6 = j6 + Eigen::Vector3d(0.02, 0, 0), ct = j6 + Eigen::Vector3d(0.07, 0.02, 0);
  EXPECT_LE((l6.position - (0.2 * c6 + 0.1 * ct) / 0.3).norm(), 1e-15);
  Eigen::Matrix3d I = Eigen::Vector3d(0.0001, 0.00015, 0.00015).asDiagonal();
  I += Eigen::Matrix3d(Eigen::Vector3d(0.00002, 0.00003, 0.00003).asDiagonal());
  for (const auto& [m, c] : {std::pair<double, Eigen::Vector3d>{0.2, c6}, {0.1, ct}}) {
    const Eigen::Vector3d d = c - l6.position;
    I += m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  EXPECT_LE((l6.inertia - I).norm(), 1e-15);

  // The same trajectory from both files: the arm falls from horizontal.
  const Trajectory a = simulate(u, "rkmk4", 1e-3, 1.0, 50);
  const Trajectory b = simulate(x, "rkmk4", 1e-3, 1.0, 50);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  double worst = 0.0;
  for (std::size_t r = 0; r < a.rows.size(); ++r)
    for (std::size_t c = 0; c < a.rows[r].size(); ++c) worst = std::max(worst, std::abs(a.rows[r][c] - b.rows[r][c]));
  std::cout << "[ measured ] arm6 URDF vs MJCF: max |difference| over every column and row = " << worst << "\n";
  EXPECT_LE(worst, 1e-10);
  EXPECT_GT(std::abs(a.at(a.rows.size() - 1, "j2.phi")), 0.5);  // it fell
}

TEST(ModelImport, UrdfInertiaKeepsItsProductsOfInertiaAndFrames) {
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  // One link, its joint frame turned 90° about z, its inertial frame turned
  // by rpy (0, 0, π/2) more: body axes are the link frame, so the scene's
  // inertia is R_z(π/2) I R_z(π/2)ᵀ of the tensor as written.
  const TempModel urdf("products.urdf", R"(<robot name="r"><link name="base"/>
<joint name="j" type="continuous"><parent link="base"/><child link="a"/><origin xyz="0 0 1" rpy="0 0 1.5707963267948966"/></joint>
<link name="a"><inertial><origin xyz="0.1 0 0" rpy="0 0 1.5707963267948966"/><mass value="2"/>
<inertia ixx="0.4" iyy="0.5" izz="0.6" ixy="0.01" ixz="-0.02" iyz="0.03"/></inertial></link></robot>)");
  const SceneDescription s = importModel(urdf.path(), {});
  Eigen::Matrix3d I;
  I << 0.4, 0.01, -0.02, 0.01, 0.5, 0.03, -0.02, 0.03, 0.6;
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LE((s.bodies[0].inertia - Rz * I * Rz.transpose()).norm(), 1e-15);
  // The centre: 0.1 m along the link's x, which is the world's y.
  EXPECT_LE((s.bodies[0].position - Eigen::Vector3d(0, 0.1, 1)).norm(), 1e-15);
  EXPECT_LE(s.bodies[0].orientation.angularDistance(Eigen::Quaterniond(Rz)), 1e-15);
}

TEST(ModelImport, WrittenSceneReadsBackToTheSameText) {
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const std::string text = sceneToJson(importModel(model("arm6.urdf"), {}));
  const std::string again = sceneToJson(parseScene(text, "arm6.json"));
  EXPECT_EQ(text, again);
  expectContains(text, {"\"name\": \"arm6\"", "\"type\": \"revolute\"", "\"damper\""});
}

#ifdef LIEFLOW_HAVE_MUJOCO
/// MuJoCo's RK4 on `path` for t_end at step h, returning the bodies' centres
/// of mass (xipos) at the end, bodies 1 … n.
std::vector<Eigen::Vector3d> mujocoCentres(const std::string& path, double h, double t_end) {
  char error[512] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(path.c_str(), nullptr, error, sizeof(error)), mj_deleteModel);
  EXPECT_TRUE(m) << error;
  if (!m) return {};
  m->opt.integrator = mjINT_RK4;
  m->opt.timestep = h;
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m.get()), mj_deleteData);
  const long steps = std::lround(t_end / h);
  for (long k = 0; k < steps; ++k) mj_step(m.get(), d.get());
  mj_forward(m.get(), d.get());
  std::vector<Eigen::Vector3d> out;
  for (int b = 1; b < m->nbody; ++b) out.emplace_back(d->xipos[3 * b], d->xipos[3 * b + 1], d->xipos[3 * b + 2]);
  return out;
}

/// The largest distance between lieflow's rkmk4 and MuJoCo's RK4 centres of
/// mass after t_end at step h on the model file `path`, over the bodies both
/// have (a link merged with a welded one has another centre and is left out);
/// `travel` gets the largest distance a centre moved.
double worstCentreDistance(const std::string& path, const ModelImportOptions& options, double h, double t_end,
                           double* travel) {
  const SceneDescription scene = importModel(path, options);
  const Trajectory tr = simulate(scene, "rkmk4", h, t_end, 1000);
  const std::vector<Eigen::Vector3d> ref = mujocoCentres(path, h, t_end);
  char error[512] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(path.c_str(), nullptr, error, sizeof(error)),
                                                 mj_deleteModel);
  double worst = 0.0;
  *travel = 0.0;
  const std::size_t last = tr.rows.size() - 1;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const std::string& n = scene.bodies[b].name;
    // Scene bodies are the MJCF bodies that move, in model order.
    const Eigen::Vector3d p(tr.at(last, n + ".x"), tr.at(last, n + ".y"), tr.at(last, n + ".z"));
    const int mj_index = mj_name2id(m.get(), mjOBJ_BODY, n.c_str()) - 1;
    EXPECT_GE(mj_index, 0) << n;
    if (mj_index < 0 || m->body_weldid[mj_index + 1] != mj_index + 1) continue;
    bool merged = false;  // a welded child merged into this link moves its centre
    for (int c = 1; c < m->nbody; ++c) merged = merged || (m->body_parentid[c] == mj_index + 1 && m->body_jntnum[c] == 0);
    if (merged) continue;
    worst = std::max(worst, (p - ref[mj_index]).norm());
    *travel = std::max(*travel, (p - scene.bodies[b].position).norm());
  }
  return worst;
}

TEST(ModelImport, EveryMappedMjcfJointAgreesWithMuJoCo) {
  // Both fourth order at h = 1e-4 for 0.5 s: what remains is the mapping.
  for (const char* file : {"mechanism.xml", "arm6.xml"}) {
    double travel = 0.0;
    const double worst = worstCentreDistance(model(file), {}, 1e-4, 0.5, &travel);
    std::cout << "[ measured ] " << file << ": lieflow rkmk4 vs MuJoCo RK4, h = 1e-4, t = 0.5 s: max centre distance "
              << worst << " m (largest travel " << travel << " m)\n";
    EXPECT_LE(worst, 1e-8) << file;
    EXPECT_GT(travel, 0.05) << file;
  }
}

TEST(ModelImport, MujocosOwnSwitchesAreTakenAsMujocoTakesThem) {
  // <flag gravity/passive/equality="disable"> switch MuJoCo's gravity, the
  // joints' springs and dashpots, and its equality constraints off: the
  // import takes them as MuJoCo does (it once read gravity and the springs
  // regardless), checked against MuJoCo on the same file.
  std::ifstream in(model("mechanism.xml"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string option = "<option gravity=\"0 0 -9.81\" timestep=\"0.001\"/>";
  ASSERT_NE(text.find(option), std::string::npos);
  for (const char* flags : {"gravity=\"disable\"", "passive=\"disable\"", "gravity=\"disable\" passive=\"disable\""}) {
    std::string changed = text;
    changed.replace(changed.find(option), option.size(),
                    "<option gravity=\"0 0 -9.81\" timestep=\"0.001\"><flag " + std::string(flags) + "/></option>");
    const TempModel file("switches.xml", changed);
    const SceneDescription s = importModel(file.path(), {});
    const bool no_gravity = std::string(flags).find("gravity") != std::string::npos;
    const bool no_passive = std::string(flags).find("passive") != std::string::npos;
    EXPECT_EQ(s.gravity.norm(), no_gravity ? 0.0 : 9.81) << flags;
    bool sprung = false;
    for (const JointDescription& j : s.joints)
      for (const CoordinateDescription& c : j.coordinates) sprung = sprung || c.stiffness != 0.0 || c.damping != 0.0;
    EXPECT_EQ(sprung, !no_passive) << flags;
    double travel = 0.0;
    const double worst = worstCentreDistance(file.path(), {}, 1e-4, 0.3, &travel);
    EXPECT_LE(worst, 1e-8) << flags;
    if (no_gravity && no_passive)
      EXPECT_LE(travel, 1e-12) << "nothing drives the mechanism at rest, yet it moved";
    else
      EXPECT_GT(travel, 1e-3) << flags;
  }
  // The medium (density, viscosity, wind) has no model in lieflow: refused
  // naming the option's line, or ignored by name and listed.
  std::string fluid = text;
  fluid.replace(fluid.find(option), option.size(), "<option gravity=\"0 0 -9.81\" density=\"1.2\" viscosity=\"2e-5\"/>");
  const TempModel medium("medium.xml", fluid);
  expectContains(refusal(medium.path()), {"medium.xml", "fluid", "option (line 8)", "density 1.2"});
  const SceneDescription s = importModel(medium.path(), parseIgnoreList("fluid"));
  bool listed = false;
  for (const std::string& note : s.import_notes) listed = listed || note.find("fluid") != std::string::npos;
  EXPECT_TRUE(listed);
}

/// MuJoCo's compiler errors name the element and line as MuJoCo reports
/// them ("Element 'joint', line 5"; "Object name = j, id = 1, line = 6"),
/// read by hand from its message, also when an element's tag is long.
TEST(ModelImport, MujocoCompilerErrorsNameTheElementAndLine) {
  const auto refusal = [](const char* name, const std::string& text) {
    const TempModel file(name, text);
    try {
      importModel(file.path(), {});
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  expectContains(refusal("bogus.xml", "<mujoco>\n<worldbody>\n<body name=\"a\">\n<geom type=\"sphere\" size=\"0.1\"/>\n"
                                      "<joint type=\"hinge\" bogus=\"1\"/>\n</body>\n</worldbody>\n</mujoco>\n"),
                 {"line 5, <joint>: ", "unrecognized attribute: 'bogus'"});
  expectContains(refusal("twice.xml", "<mujoco>\n<worldbody>\n<body name=\"a\">\n<geom type=\"sphere\" size=\"0.1\"/>\n"
                                      "<joint name=\"j\" type=\"hinge\"/>\n<joint name=\"j\" type=\"hinge\"/>\n"
                                      "</body>\n</worldbody>\n</mujoco>\n"),
                 {"line 6, 'j': ", "repeated name"});
  const std::string tag(20000, 'x');
  EXPECT_NE(refusal("long-tag.xml", "<mujoco>\n<worldbody>\n<" + tag + "/>\n</worldbody>\n</mujoco>\n"), "");
}

TEST(ModelImport, AJointNamedLikeABodyIsRenamedAndSaysSo) {
  // Scene names are one namespace (columns, --columns, calibration's
  // --main/--secondary): MJCF and URDF allow a joint and a body of one name.
  const TempModel file("same-name.xml", R"(<mujoco><worldbody><body name="arm" pos="0 0 1">
  <joint name="arm" type="hinge" axis="0 1 0"/>
  <inertial pos="0.2 0 0" mass="1" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>)");
  const SceneDescription s = importModel(file.path(), {});
  ASSERT_EQ(s.joints.size(), 1u);
  EXPECT_EQ(s.joints[0].name, "arm_joint");
  bool said = false;
  for (const std::string& note : s.import_notes) said = said || note.find("renamed joint 'arm'") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(ModelImport, HumanoidSpinningInFreeFallAgreesWithMuJoCo) {
  // MuJoCo's humanoid with contacts, limits, armature and actuators left out
  // on both sides, released in free fall turning at 2 rad/s about a tilted
  // axis: the joints' springs and dashpots flex under the spin.
  const std::string humanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";
  if (!std::ifstream(humanoid)) GTEST_SKIP() << "needs libmujoco-samples";
  SceneDescription scene = importModel(humanoid, parseIgnoreList("all"));
  const Eigen::Vector3d w(0.6, -1.2, 1.5);  // rad/s, world
  const Eigen::Vector3d c0 = scene.bodies[0].position;
  for (BodyDescription& b : scene.bodies) {
    b.angular_velocity = b.orientation.inverse() * w;
    b.velocity = w.cross(b.position - c0);
  }
  const double h = 1e-4, t_end = 1.0;
  const Trajectory tr = simulate(scene, "rkmk4", h, t_end, 10000);

  char error[512] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(humanoid.c_str(), nullptr, error, sizeof(error)), mj_deleteModel);
  ASSERT_TRUE(m) << error;
  m->opt.integrator = mjINT_RK4;
  m->opt.timestep = h;
  m->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_LIMIT | mjDSBL_ACTUATION;
  for (int i = 0; i < m->nv; ++i) m->dof_armature[i] = m->dof_frictionloss[i] = 0.0;
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m.get()), mj_deleteData);
  mj_kinematics(m.get(), d.get());
  // The root's free joint: velocity of the torso frame's origin (world) and
  // its angular velocity in the torso frame.
  const int torso = mj_name2id(m.get(), mjOBJ_BODY, "torso");
  const Eigen::Vector3d x0(d->xpos[3 * torso], d->xpos[3 * torso + 1], d->xpos[3 * torso + 2]);
  const Eigen::Vector3d v0 = w.cross(x0 - c0);
  const Eigen::Quaterniond q0(d->xquat[4 * torso], d->xquat[4 * torso + 1], d->xquat[4 * torso + 2], d->xquat[4 * torso + 3]);
  const Eigen::Vector3d w_local = q0.inverse() * w;
  for (int i = 0; i < 3; ++i) {
    d->qvel[i] = v0[i];
    d->qvel[3 + i] = w_local[i];
  }
  for (long k = 0; k < std::lround(t_end / h); ++k) mj_step(m.get(), d.get());
  mj_kinematics(m.get(), d.get());
  double worst = 0.0, worst_angle = 0.0, bend = 0.0;
  const std::size_t last = tr.rows.size() - 1;
  for (const BodyDescription& b : scene.bodies) {
    const int id = mj_name2id(m.get(), mjOBJ_BODY, b.name.c_str());
    ASSERT_GE(id, 0) << b.name;
    const Eigen::Quaterniond qm(d->xquat[4 * id], d->xquat[4 * id + 1], d->xquat[4 * id + 2], d->xquat[4 * id + 3]);
    worst_angle = std::max(worst_angle, tr.orientation(last, b.name).angularDistance(qm));
    // Centres: a merged group's centre from its MuJoCo bodies (a body
    // without joints belongs to its parent's group).
    double mass = 0.0;
    Eigen::Vector3d mc = Eigen::Vector3d::Zero();
    for (int k = 1; k < m->nbody; ++k) {
      int root = k;
      while (m->body_jntnum[root] == 0 && m->body_parentid[root] != 0) root = m->body_parentid[root];
      if (root != id) continue;
      mass += m->body_mass[k];
      mc += m->body_mass[k] * Eigen::Vector3d(d->xipos[3 * k], d->xipos[3 * k + 1], d->xipos[3 * k + 2]);
    }
    const Eigen::Vector3d p(tr.at(last, b.name + ".x"), tr.at(last, b.name + ".y"), tr.at(last, b.name + ".z"));
    worst = std::max(worst, (p - mc / mass).norm());
  }
  for (int j = 0; j < m->njnt; ++j)
    if (m->jnt_type[j] == mjJNT_HINGE) bend = std::max(bend, std::abs(d->qpos[m->jnt_qposadr[j]]));
  std::cout << "[ measured ] humanoid (" << scene.bodies.size() << " bodies, " << m->nv
            << " degrees of freedom), spinning in free fall, lieflow rkmk4 vs MuJoCo RK4 at h = 1e-4 after 1 s: "
               "centres "
            << worst << " m, orientations " << worst_angle << " rad (largest hinge angle " << bend << " rad)\n";
  EXPECT_LE(worst, 1e-8);
  EXPECT_LE(worst_angle, 1e-8);
  EXPECT_GT(bend, 0.05);
}
#endif

/// Two pendulums on hinges about y from one parent (the ground), the second
/// coupled to the first with multiplier −2: URDF <mimic>, MJCF equality joint.
constexpr const char* kMimicUrdf = R"(<robot name="geared"><link name="base"/>
<joint name="drive" type="continuous"><parent link="base"/><child link="driver"/><axis xyz="0 1 0"/></joint>
<link name="driver"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.001" iyy="0.004" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="follow" type="continuous"><parent link="base"/><child link="follower"/><origin xyz="0.5 0 0"/><axis xyz="0 1 0"/>
<mimic joint="drive" multiplier="-2" offset="0"/></joint>
<link name="follower"><inertial><origin xyz="0.05 0 0"/><mass value="0.5"/><inertia ixx="0.001" iyy="0.002" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>)";
constexpr const char* kMimicMjcf = R"(<mujoco model="geared"><worldbody>
<body name="driver"><joint name="drive" type="hinge" axis="0 1 0"/><inertial pos="0.1 0 0" mass="1" diaginertia="0.001 0.004 0.004"/></body>
<body name="follower" pos="0.5 0 0"><joint name="follow" type="hinge" axis="0 1 0"/><inertial pos="0.05 0 0" mass="0.5" diaginertia="0.001 0.002 0.002"/></body>
</worldbody><equality><joint name="gearing" joint1="follow" joint2="drive" polycoef="0 -2 0 0 0"/></equality></mujoco>)";

TEST(ModelImport, CouplingsBecomeCouplingRowsThatHoldTheRatio) {
  if (!haveBothReaders()) GTEST_SKIP() << "this build lacks a model reader";
  const TempModel urdf("geared.urdf", kMimicUrdf), mjcf("geared.xml", kMimicMjcf);
  for (const std::string& path : {urdf.path(), mjcf.path()}) {
    for (const std::string formulation : {"maximal", "joint"}) {
      SCOPED_TRACE(path + " in " + formulation + " coordinates");
      const SceneDescription s = importModel(path, {});
      ASSERT_EQ(s.joints.size(), 3u);
      EXPECT_EQ(s.joints[2].type, "coupling");
      EXPECT_EQ(s.joints[2].carrier, "ground");
      EXPECT_DOUBLE_EQ(s.joints[2].ratio, 2.0);
      const Trajectory tr = simulate(s, "rkmk4", 1e-3, 1.0, 50, formulation);
      double err = 0.0;
      for (std::size_t r = 0; r < tr.rows.size(); ++r)
        err = std::max(err, std::abs(tr.at(r, "follow.phi") + 2.0 * tr.at(r, "drive.phi")));
      std::cout << "[ measured ] " << path.substr(path.find_last_of('/') + 1) << " (" << formulation
                << "): max |q_follow + 2 q_drive| = " << err << " rad over 1 s (the driver turned "
                << tr.at(tr.rows.size() - 1, "drive.phi") << " rad)\n";
      EXPECT_LE(err, 1e-9);
      EXPECT_GT(std::abs(tr.at(tr.rows.size() - 1, "drive.phi")), 0.3);
    }
  }
}


TEST(ModelImport, PrismaticFingersMimicEachOtherOnAMovingHand) {
  // The hand starts turned 1 rad about the wrist: gravity swings it and
  // slides the fingers along their (tilted) axes; each coupling holds its
  // ratio while the fingers and the thumb move.
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  // tests/data/models/hand.urdf: a hand on a wrist hinge, two prismatic
  // fingers (the second mimics the first, as the Panda's do) and a revolute
  // thumb that mimics the first finger's slide (2 rad per metre).
  ModelImportOptions options;
  options.ignore = {"limits"};
  SceneDescription s = importModel(model("hand.urdf"), options);
  ASSERT_EQ(s.joints.size(), 6u);
  EXPECT_EQ(s.joints[4].type, "coupling");
  EXPECT_TRUE(s.joints[4].slide_main);
  EXPECT_TRUE(s.joints[4].slide_secondary);
  EXPECT_EQ(s.joints[4].carrier, "hand");
  EXPECT_FALSE(s.joints[5].slide_secondary);
  s.joints[0].initial_angles[0] = 1.0;
  // The bodies at the wrist's 1 rad: the scene's poses are the reference's.
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX()));
  for (BodyDescription& b : s.bodies) {
    b.orientation = turn * b.orientation;
    b.position = turn * b.position;
  }
  for (const std::string formulation : {"maximal", "joint"}) {
    SCOPED_TRACE(formulation);
    const Trajectory tr = simulate(s, "rkmk4", 1e-4, 1.0, 100, formulation);
    double pair = 0.0, thumb = 0.0, travel = 0.0;
    for (std::size_t r = 0; r < tr.rows.size(); ++r) {
      const double x1 = tr.at(r, "finger1.x");
      pair = std::max(pair, std::abs(tr.at(r, "finger2.x") - x1));
      thumb = std::max(thumb, std::abs(tr.at(r, "thumb.phi") - 2.0 * x1));
      travel = std::max(travel, std::abs(x1));
    }
    std::cout << "[ measured ] prismatic mimic (" << tr.result.formulation << "): max |x2 - x1| = " << pair
              << " m, max |phi_thumb - 2 x1| = " << thumb << " rad; the fingers slid up to " << travel << " m\n";
    EXPECT_LE(pair, 1e-10);
    EXPECT_LE(thumb, 1e-10);
    EXPECT_GT(travel, 1e-3);
  }
}

TEST(ModelImport, MimicsAnywhereInTheTreeHoldTheirRatios) {
  // A double pendulum (shoulder, elbow); a flap hinged to the ground mimics
  // the elbow (a coupling of joints with different parents), a finger hung
  // from the forearm mimics the elbow too (the follower's parent is the
  // leader's child), and a welded tag carries a <mimic> that has nothing to
  // couple (left out with a note, as PAL's Talos has them).
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const TempModel urdf("tree_mimic.urdf", R"(<robot name="tree"><link name="base"/>
<joint name="shoulder" type="continuous"><parent link="base"/><child link="upper"/><axis xyz="0 1 0"/></joint>
<link name="upper"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.001" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="elbow" type="continuous"><parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/><axis xyz="0 1 0"/></joint>
<link name="fore"><inertial><origin xyz="0.15 0 0.02"/><mass value="0.6"/><inertia ixx="0.001" iyy="0.005" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="flap" type="continuous"><parent link="base"/><child link="flapper"/><origin xyz="0 0.3 0"/><axis xyz="1 0 0"/>
<mimic joint="elbow" multiplier="-0.5" offset="0"/></joint>
<link name="flapper"><inertial><origin xyz="0 0 -0.1"/><mass value="0.3"/><inertia ixx="0.002" iyy="0.002" izz="0.0005" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="finger" type="continuous"><parent link="fore"/><child link="digit"/><origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>
<mimic joint="elbow" multiplier="1.5" offset="0"/></joint>
<link name="digit"><inertial><origin xyz="0.05 0 0"/><mass value="0.1"/><inertia ixx="0.0001" iyy="0.0002" izz="0.0002" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="tag_weld" type="fixed"><parent link="fore"/><child link="tag"/><origin xyz="0.1 0 0"/><mimic joint="elbow"/></joint>
<link name="tag"><inertial><mass value="0.05"/><inertia ixx="0.0001" iyy="0.0001" izz="0.0001" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>)");
  const SceneDescription s = importModel(urdf.path(), {});
  bool noted = false;
  for (const std::string& note : s.import_notes)
    noted = noted || note.find("ignored mimics of fixed joints (no coordinate to couple): joint 'tag_weld'") == 0;
  EXPECT_TRUE(noted);
  for (const std::string formulation : {"maximal", "joint"}) {
    SCOPED_TRACE(formulation);
    const Trajectory tr = simulate(s, "rkmk4", 1e-3, 1.0, 50, formulation);
    double flap = 0.0, finger = 0.0;
    for (std::size_t r = 0; r < tr.rows.size(); ++r) {
      flap = std::max(flap, std::abs(tr.at(r, "flap.phi") + 0.5 * tr.at(r, "elbow.phi")));
      finger = std::max(finger, std::abs(tr.at(r, "finger.phi") - 1.5 * tr.at(r, "elbow.phi")));
    }
    std::cout << "[ measured ] mimics across the tree (" << formulation << "): max |q_flap + q_elbow/2| = " << flap
              << " rad, max |q_finger - 1.5 q_elbow| = " << finger << " rad (the elbow turned up to "
              << tr.at(tr.rows.size() - 1, "elbow.phi") << " rad)\n";
    // Joint coordinates hold the rates on the coordinates themselves (round-
    // off); maximal coordinates hold them on the bodies' velocities, and the
    // angles drift by the integrator's truncation error, as for the gears.
    const double bound = formulation == "joint" ? 1e-12 : 1e-8;
    EXPECT_LE(flap, bound);
    EXPECT_LE(finger, bound);
    EXPECT_GT(std::abs(tr.at(tr.rows.size() - 1, "elbow.phi")), 0.05);
  }
}

TEST(ModelImport, MjcfConnectAndWeldCloseLoopsExactly) {
  if (!canReadMjcf()) GTEST_SKIP() << "this build has no MJCF reader";
  // A crank on a hinge and a rocker on a ball joint from the world, a
  // coupler hinged to the crank and connected to the rocker's tip (a loop),
  // and a free lamp welded to the coupler.
  const TempModel mjcf("loop.xml", R"(<mujoco model="loop"><worldbody>
<body name="crank"><joint name="crank_pivot" type="hinge" axis="0 1 0"/><inertial pos="0.05 0 0.1" mass="0.5" diaginertia="0.002 0.002 0.0001"/>
  <body name="coupler" pos="0 0 0.2"><joint name="knuckle" type="hinge" axis="0 1 0"/><inertial pos="0.2 0 0" mass="1" diaginertia="0.0001 0.014 0.014"/></body>
</body>
<body name="rocker" pos="0.4 0 0"><joint name="rocker_ball" type="ball"/><inertial pos="0 0 0.1" mass="0.5" diaginertia="0.002 0.002 0.0001"/></body>
<body name="lamp" pos="0.2 0.1 0.25"><freejoint/><inertial pos="0 0 0" mass="0.2" diaginertia="0.0001 0.0001 0.0001"/></body>
</worldbody><equality>
<connect name="closure" body1="coupler" body2="rocker" anchor="0.4 0 0"/>
<weld name="mount" body1="coupler" body2="lamp"/>
</equality></mujoco>)");
  const SceneDescription s = importModel(mjcf.path(), {});
  ASSERT_EQ(s.joints.size(), 5u);
  EXPECT_EQ(s.joints[3].type, "spherical");
  EXPECT_EQ(s.joints[3].name, "closure");
  EXPECT_EQ(s.joints[4].type, "fixed");
  // Released off the dead position: the loop swings under gravity.
  const Trajectory tr = simulate(s, "rkmk4", 1e-3, 1.0, 50);
  EXPECT_LE(tr.result.constraint_error, 1e-10);
  EXPECT_LE(tr.result.energy_drift, 1e-6);
  double lamp = 0.0;  // the lamp stays where the weld holds it on the coupler
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const Eigen::Quaterniond qc = tr.orientation(r, "coupler");
    const Eigen::Vector3d pc(tr.at(r, "coupler.x"), tr.at(r, "coupler.y"), tr.at(r, "coupler.z"));
    const Eigen::Vector3d pl(tr.at(r, "lamp.x"), tr.at(r, "lamp.y"), tr.at(r, "lamp.z"));
    lamp = std::max(lamp, (qc.inverse() * (pl - pc) - Eigen::Vector3d(0.0, 0.1, 0.05)).norm());
  }
  EXPECT_LE(lamp, 1e-10);
}

TEST(ModelImport, AUrdfFloatsWithItsRootOnAFreeJoint) {
  // --floating-base: the arm's base is a body on a free joint, not the
  // ground. Released at rest under gravity, the whole robot's centre of mass
  // falls as a point, z0 − g t²/2, whatever its damped joints do inside.
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const SceneDescription fixed = importModel(model("arm6.urdf"), {});
  ModelImportOptions floating;
  floating.floating_base = true;
  const SceneDescription s = importModel(model("arm6.urdf"), floating);
  EXPECT_EQ(s.bodies.size(), fixed.bodies.size() + 1);
  for (const std::string& note : s.import_notes) EXPECT_EQ(note.find("fixed to the world"), std::string::npos) << note;
  const double t_end = 0.5, g = 9.81;
  const Trajectory tr = simulate(s, "rkmk4", 1e-3, t_end, 100);
  double mass = 0.0;
  Eigen::Vector3d c0 = Eigen::Vector3d::Zero(), c1 = Eigen::Vector3d::Zero();
  const std::size_t last = tr.rows.size() - 1;
  for (const BodyDescription& b : s.bodies) {
    mass += b.mass;
    c0 += b.mass * b.position;
    c1 += b.mass * Eigen::Vector3d(tr.at(last, b.name + ".x"), tr.at(last, b.name + ".y"), tr.at(last, b.name + ".z"));
  }
  c0 /= mass;
  c1 /= mass;
  const Eigen::Vector3d expected = c0 + Eigen::Vector3d(0.0, 0.0, -0.5 * g * t_end * t_end);
  std::cout << "[ measured ] arm6.urdf with a floating base, free fall 0.5 s: centre of mass off the parabola by "
            << (c1 - expected).norm() << " m\n";
  EXPECT_LE((c1 - expected).norm(), 1e-10);
  // MJCF names its own free bodies.
  if (canReadMjcf()) expectContains(refusal(model("arm6.xml"), floating), {"arm6.xml", "`floating_base`"});
}

TEST(ModelImport, SpinTurnsEveryFreeTreeRigidlyAboutItsCentre) {
  // --spin ω: the floating arm turns as one rigid body about its centre of
  // mass. Read back by the simulator (its own kinematics): every joint's
  // rate is zero, the centre of mass does not move, and each body turns at ω
  // (world axes), its centre at ω × (c_i − c).
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  ModelImportOptions options;
  options.floating_base = true;
  options.has_spin = true;
  options.spin = {{0.5, -1.0, 2.0}};
  const Eigen::Vector3d omega(0.5, -1.0, 2.0);
  const SceneDescription s = importModel(model("arm6.urdf"), options);
  const Trajectory tr = simulate(s, "rkmk4", 1e-3, 1e-3);
  double mass = 0.0;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero(), centre = Eigen::Vector3d::Zero();
  for (const BodyDescription& b : s.bodies) {
    mass += b.mass;
    centre += b.mass * b.position;
    momentum += b.mass * Eigen::Vector3d(tr.at(0, b.name + ".vx"), tr.at(0, b.name + ".vy"), tr.at(0, b.name + ".vz"));
  }
  centre /= mass;
  EXPECT_LE(momentum.norm(), 1e-12 * mass);
  for (const BodyDescription& b : s.bodies) {
    const Eigen::Quaterniond q(tr.at(0, b.name + ".qw"), tr.at(0, b.name + ".qx"), tr.at(0, b.name + ".qy"),
                               tr.at(0, b.name + ".qz"));
    const Eigen::Vector3d w_body(tr.at(0, b.name + ".wx"), tr.at(0, b.name + ".wy"), tr.at(0, b.name + ".wz"));
    EXPECT_LE((q * w_body - omega).norm(), 1e-12) << b.name;
    const Eigen::Vector3d v(tr.at(0, b.name + ".vx"), tr.at(0, b.name + ".vy"), tr.at(0, b.name + ".vz"));
    EXPECT_LE((v - omega.cross(b.position - centre)).norm(), 1e-12) << b.name;
  }
  for (const char* joint : {"j1", "j2", "j3", "j4", "j5", "j6"})
    EXPECT_LE(std::abs(tr.at(0, std::string(joint) + ".phidot")), 1e-12) << joint;
  // A fixed base has nothing free to turn.
  options.floating_base = false;
  expectContains(refusal(model("arm6.urdf"), options), {"arm6.urdf", "`spin`", "`floating_base`"});
}

TEST(ModelImport, WhatLieflowCannotRepresentIsListedByNameAndLine) {
  if (!canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  // A revolute joint with limits and a link with a collision shape.
  const std::string urdf = model("limited.urdf");
  expectContains(refusal(urdf),
                 {"limited.urdf", "limit of joint 'hinge' (line 6)", "collision of link 'arm' (line 10)",
                  "`ignore` contacts,limits"});
  ModelImportOptions ignore = parseIgnoreList("contacts,limits");
  const SceneDescription s = importModel(urdf, ignore);
  // What was ignored, and that the URDF's root is fixed to the world.
  ASSERT_EQ(s.import_notes.size(), 3u);
  expectContains(s.import_notes[0] + "\n" + s.import_notes[1], {"contacts: collision of link 'arm'", "limits: limit of joint 'hinge'"});
  expectContains(s.import_notes[2], {"the root link", "is fixed to the world", "`floating_base`"});
  EXPECT_EQ(s.joints[0].type, "revolute");
}

TEST(ModelImport, BadModelsNameTheFileElementAndReason) {
  if (!haveBothReaders()) GTEST_SKIP() << "this build lacks a model reader";
  const TempModel broken("broken.urdf", "<robot name=\"r\">\n  <link name=\"a\">\n</robot>\n");
  expectContains(refusal(broken.path()), {"broken.urdf: line", "broken XML"});
  const TempModel massless("massless.urdf", R"(<robot name="r"><link name="base"/>
<joint name="j" type="continuous"><parent link="base"/><child link="ghost"/></joint>
<link name="ghost"/></robot>)");
  expectContains(refusal(massless.path()), {"massless.urdf", "link 'ghost' (line 3)", "no mass"});
  const TempModel unknown("unknown.urdf", R"(<robot name="r"><link name="base"/>
<joint name="j" type="twisty"><parent link="base"/><child link="a"/></joint>
<link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)");
  expectContains(refusal(unknown.path()), {"unknown.urdf", "joint 'j' (line 2)", "'twisty' is not a URDF joint type"});
  const TempModel planar("planar.urdf", R"(<robot name="r"><link name="base"/>
<joint name="p" type="planar"><parent link="base"/><child link="a"/></joint>
<link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)");
  expectContains(refusal(planar.path()), {"planar.urdf", "joint 'p' (line 2)", "planar"});
  const TempModel three("three.xml", R"(<mujoco><worldbody><body name="b">
  <joint name="a" type="hinge" axis="1 0 0"/><joint name="c" type="hinge" axis="0 1 0"/><joint name="d" type="hinge" axis="1 1 0"/>
  <inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>)");
  expectContains(refusal(three.path()), {"three.xml", "body 'b' (line 1)", "3 joints (a, c, d)"});
  const TempModel notmodel("nomodel.xml", "<robot name=\"r\"/>");
  expectContains(refusal(notmodel.path()), {"nomodel.xml", "<mujoco>"});
  expectContains(refusal(model("does-not-exist.urdf")), {"does-not-exist.urdf", "cannot open"});
  try {
    parseIgnoreList("contacts,gravity");
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    expectContains(e.what(), {"`ignore`", "gravity", "contacts"});
  }
}

TEST(ModelImport, MuJoCosHumanoidIsRefusedWithWhatItLacks) {
  const std::string humanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";
  if (!canReadMjcf() || !std::ifstream(humanoid)) GTEST_SKIP() << "needs MJCF and libmujoco-samples";
  expectContains(refusal(humanoid), {"humanoid.xml", "contacts", "limits", "armature", "actuators"});
  // With those ignored it imports: its hips are gimbals, its waist and
  // shoulders universal joints, its ankles offset universal joints.
  const SceneDescription s = importModel(humanoid, parseIgnoreList("all"));
  EXPECT_FALSE(s.import_notes.empty());
  int gimbals = 0, offsets = 0;
  for (const JointDescription& j : s.joints) {
    gimbals += j.type == "gimbal";
    offsets += j.offset;
  }
  EXPECT_EQ(gimbals, 2);
  EXPECT_EQ(offsets, 2);
}

}  // namespace
}  // namespace lieflow
