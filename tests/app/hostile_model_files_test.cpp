/// \file
/// Model files as a hostile user writes them (issue 28): every number read
/// from MJCF and URDF is checked where it is written and named by file,
/// element (name and line) and attribute; a URDF that is not a tree, and
/// mimics that lead nowhere or in circles, are refused before any memory
/// grows; an MJCF's limits are checked before MuJoCo compiles it; a zero
/// quaternion is not silently the identity; names that would break the CSV
/// are refused. Each class is tried on every attribute of a small model, not
/// only on the examples the issue gave.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
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

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

const char* const kBadNumbers[] = {"nan", "inf", "-inf", "1e400", "1e308", "-1e200"};

/// A small MJCF: a sprung hinge, a slide, a geom-derived mass, a keyframe.
const char* const kMjcf = R"(<mujoco model="m">
  <option timestep="0.002" gravity="0 0 -9.81"/>
  <worldbody>
    <body name="arm" pos="0 0 1" quat="1 0 0 0">
      <joint name="hinge" type="hinge" axis="0 1 0" pos="0 0 0" stiffness="2" springref="0.1" damping="0.3"/>
      <inertial pos="0 0 -0.2" mass="1" diaginertia="0.01 0.01 0.002"/>
      <body name="tip" pos="0 0 -0.4" euler="0 0 0">
        <joint name="slide" type="slide" axis="0 0 1" damping="0.1"/>
        <geom name="ball" type="sphere" size="0.05" density="1000" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <keyframe><key name="k" qpos="0.2 0.01" qvel="0.5 0"/></keyframe>
</mujoco>
)";

/// A small URDF: two links on a revolute joint with a mimicking third.
const char* const kUrdf = R"(<robot name="r">
  <link name="base"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm">
    <inertial><origin xyz="0 0 -0.2" rpy="0 0 0"/><mass value="0.5"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="finger"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="twin"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 1 0"/><dynamics damping="0.1"/></joint>
  <joint name="left" type="continuous"><parent link="arm"/><child link="finger"/>
    <origin xyz="0 0.05 -0.4"/><axis xyz="1 0 0"/></joint>
  <joint name="right" type="continuous"><parent link="arm"/><child link="twin"/>
    <origin xyz="0 -0.05 -0.4"/><axis xyz="1 0 0"/><mimic joint="left" multiplier="-1" offset="0"/></joint>
</robot>
)";

/// (element label as the message gives it, attribute, the line it is on) for
/// every numeric attribute of `text`: found by pattern, so that the test
/// covers the whole template, not a hand-picked list.
struct NumericAttribute {
  std::string tag, name, attribute;
  int line;
  std::size_t at;  ///< offset of the value's first character in the text
};

std::vector<NumericAttribute> numericAttributes(const std::string& text) {
  std::vector<NumericAttribute> out;
  static const std::regex element(R"(<([a-z_]+)((?:\s+[a-z_]+="[^"]*")*)\s*/?>)");
  static const std::regex attribute(R"(([a-z_]+)="(-?[0-9][^"]*)\")");
  for (auto e = std::sregex_iterator(text.begin(), text.end(), element); e != std::sregex_iterator(); ++e) {
    const std::string attributes = (*e)[2].str();
    std::smatch name;
    const std::string element_name =
        std::regex_search(attributes, name, std::regex(R"(name="([^"]*)\")")) ? name[1].str() : std::string();
    const std::size_t base = static_cast<std::size_t>(e->position(2));
    for (auto a = std::sregex_iterator(attributes.begin(), attributes.end(), attribute); a != std::sregex_iterator();
         ++a) {
      const std::size_t at = base + static_cast<std::size_t>(a->position(2));
      const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
      out.push_back({(*e)[1].str(), element_name, (*a)[1].str(), line, at});
    }
  }
  return out;
}

/// `text` with the first number of the attribute at `at` replaced by `value`.
std::string withValue(const std::string& text, std::size_t at, const std::string& value) {
  const std::size_t end = text.find_first_of(" \"", at);
  return text.substr(0, at) + value + text.substr(end);
}

std::string label(const NumericAttribute& a) {
  return a.tag + (a.name.empty() ? std::string() : " '" + a.name + "'") + " (line " + std::to_string(a.line) +
         "), attribute " + a.attribute;
}

void expectEveryBadNumberNamed(const std::string& text, const std::string& suffix, const std::string& extra) {
  const std::vector<NumericAttribute> attributes = numericAttributes(text);
  ASSERT_GT(attributes.size(), 15u);
  const std::string path = testFile(suffix);
  for (const NumericAttribute& a : attributes)
    for (const char* bad : kBadNumbers) {
      write(path, withValue(text, a.at, bad));
      const Outcome o = runLieflow("import " + path + extra + " --out " + testFile(".json"));
      EXPECT_EQ(o.signal, 0) << a.attribute << "=" << bad;
      EXPECT_EQ(o.status, 2) << label(a) << "=" << bad << "\n" << o.err;
      EXPECT_NE(o.err.find(path + ": " + label(a) + ": "), std::string::npos)
          << "expected the element and attribute named: " << label(a) << "=" << bad << "\n" << o.err;
    }
}

TEST(HostileModelFiles, EveryBadNumberInAnMjcfIsNamedByElementLineAndAttribute) {
  if (!lieflow::canReadMjcf()) GTEST_SKIP() << "this build has no MJCF reader";
  const std::string path = testFile(".xml");
  write(path, kMjcf);
  const Outcome ok = runLieflow("import " + path + " --keyframe k --out " + testFile(".json"));
  ASSERT_EQ(ok.status, 0) << ok.err;  // the template itself is fine
  expectEveryBadNumberNamed(kMjcf, ".xml", " --keyframe k");
}

TEST(HostileModelFiles, EveryBadNumberInAUrdfIsNamedByElementLineAndAttribute) {
  if (!lieflow::canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  const std::string path = testFile(".urdf");
  write(path, kUrdf);
  const Outcome ok = runLieflow("import " + path + " --out " + testFile(".json"));
  ASSERT_EQ(ok.status, 0) << ok.err;
  expectEveryBadNumberNamed(kUrdf, ".urdf", "");
}

/// A URDF of links a, b, c and the given joints (between those links).
std::string urdfWithJoints(const std::string& joints) {
  std::string s = "<robot name=\"r\">\n";
  for (const char* l : {"a", "b", "c"})
    s += std::string(" <link name=\"") + l +
         "\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" "
         "iyz=\"0\"/></inertial></link>\n";
  return s + joints + "</robot>\n";
}

std::string joint(const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& extra = "") {
  return " <joint name=\"" + name + "\" type=\"continuous\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><axis xyz=\"0 0 1\"/>" + extra + "</joint>\n";
}

TEST(HostileModelFiles, AUrdfThatIsNotATreeOrMimicsInCirclesIsRefusedNamingTheJoints) {
  if (!lieflow::canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  struct Case {
    std::string joints, expected;
  };
  const std::string mimic_b = "<mimic joint=\"jb\"/>", mimic_c = "<mimic joint=\"jc\"/>";
  const std::vector<Case> cases = {
      {joint("j1", "a", "b") + joint("j2", "a", "c") + joint("j3", "b", "c"), "link 'c' (line 4): is the child of two joints"},
      {joint("j1", "a", "b") + joint("j2", "b", "b"), "joint 'j2' (line 6): its parent and its child are the same link"},
      {joint("j1", "a", "b") + joint("j2", "b", "c") + joint("j3", "c", "b"), "is the child of two joints"},
      {joint("jb", "a", "b", mimic_c) + joint("jc", "a", "c", mimic_b), "the mimics form a cycle"},
      {joint("jb", "a", "b", mimic_b) + joint("jc", "a", "c"), "<mimic> names the joint itself"},
      {joint("jb", "a", "b", "<mimic joint=\"nobody\"/>") + joint("jc", "a", "c"), "which the robot does not have"},
  };
  const std::string path = testFile(".urdf");
  for (const Case& c : cases) {
    write(path, urdfWithJoints(c.joints));
    // Under a 1 GiB address-space limit: a walk that revisits links would
    // grow without end (it once did, to std::bad_alloc).
    const Outcome o = runLieflow("import " + path + " --out " + testFile(".json"), 1024);
    EXPECT_EQ(o.status, 2) << c.joints << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << o.err;
  }
}

TEST(HostileModelFiles, AUrdfThatUrdfdomWouldMisreadIsRefusedNamingTheElement) {
  // urdfdom reads "1.0.0", "0x10" or two numbers for a mass without a line
  // ("joint xml is not initialized correctly"), links a joint to a link that
  // is not there, and expands entities: each is refused, named, before it.
  if (!lieflow::canReadUrdf()) GTEST_SKIP() << "this build has no URDF reader";
  struct Case {
    std::string from, to, expected;
  };
  const std::vector<Case> cases = {
      {"<mass value=\"0.5\"/>", "<mass value=\"0.5.1\"/>", "mass (line 4), attribute value: expected 1 decimal number"},
      {"<mass value=\"0.5\"/>", "<mass value=\"0x10\"/>", "mass (line 4), attribute value: expected 1 decimal number"},
      {"<mass value=\"0.5\"/>", "<mass value=\"1 2\"/>", "got '1 2'"},
      {"<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 1\"/>", "axis (line 10), attribute xyz: expected 3 decimal numbers"},
      {"<child link=\"arm\"/>", "<child link=\"elbow\"/>", "joint 'shoulder' (line 9)"},
      {"<link name=\"twin\">", "<link name=\"finger\">", "a link of this name is on line 7 too"},
      {"type=\"continuous\"><parent link=\"base\"/>", "type=\"revolute\"><parent link=\"base\"/>",
       "a revolute joint needs <limit"},
      {"<link name=\"base\">", "<link>", "link (line 2): has no name"},
      {"<robot name=\"r\">", "<!DOCTYPE r [<!ENTITY big \"x\">]>\n<robot name=\"r\">", "declares XML entities"},
  };
  const std::string path = testFile(".urdf");
  for (const Case& c : cases) {
    std::string text = kUrdf;
    ASSERT_NE(text.find(c.from), std::string::npos) << c.from;
    text.replace(text.find(c.from), c.from.size(), c.to);
    write(path, text);
    const Outcome o = runLieflow("import " + path + " --out " + testFile(".json"));
    EXPECT_EQ(o.signal, 0) << c.to;
    EXPECT_EQ(o.status, 2) << c.to << "\n" << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << c.to << "\n" << o.err;
    EXPECT_EQ(o.err.find("not initialized"), std::string::npos) << o.err;  // urdfdom's words
  }
}

TEST(HostileModelFiles, MjcfLimitsAreCheckedBeforeMujocoCompiles) {
  if (!lieflow::canReadMjcf()) GTEST_SKIP() << "this build has no MJCF reader";
  // Declared bodies against --max-bodies: refused from the files.
  std::string many = "<mujoco model=\"many\"><worldbody>\n";
  for (int i = 0; i < 2000; ++i)
    many += "<body><joint type=\"hinge\"/><geom size=\"0.1\" contype=\"0\" conaffinity=\"0\"/></body>\n";
  many += "</worldbody></mujoco>\n";
  const std::string path = testFile(".xml");
  write(path, many);
  Outcome o = runLieflow("import " + path + " --max-bodies 100 --out " + testFile(".json"));
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("needs 2000 bodies (declared in its files, before MuJoCo's compiler"), std::string::npos)
      << o.err;
  EXPECT_NE(o.err.find("--max-bodies"), std::string::npos);
  // --max-input-mb counts the included files.
  const std::string big = testFile("_part.xml");
  std::string part = "<mujoco><worldbody>\n";
  while (part.size() < (3u << 20)) part += "<!-- padding padding padding padding padding padding padding -->\n";
  write(big, part + "</worldbody></mujoco>\n");
  write(path, "<mujoco model=\"m\"><include file=\"" + big + "\"/><worldbody><body><freejoint/>"
              "<geom size=\"0.1\" contype=\"0\" conaffinity=\"0\"/></body></worldbody></mujoco>\n");
  o = runLieflow("import " + path + " --max-input-mb 2 --out " + testFile(".json"));
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("include (line 1)"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("--max-input-mb"), std::string::npos) << o.err;
  // An included endless stream, and a missing include, named as includes.
  write(path, "<mujoco model=\"m\"><include file=\"/dev/zero\"/></mujoco>\n");
  o = runLieflow("import " + path + " --out " + testFile(".json"));
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("NUL byte"), std::string::npos) << o.err;
  // Numbers in included files are checked there, naming that file.
  write(big, "<mujoco><worldbody><body name=\"inner\"><freejoint/><geom size=\"0.1\" mass=\"nan\" contype=\"0\" "
             "conaffinity=\"0\"/></body></worldbody></mujoco>\n");
  write(path, "<mujoco model=\"m\"><include file=\"" + big + "\"/></mujoco>\n");
  o = runLieflow("import " + path + " --out " + testFile(".json"));
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find(big + ": geom (line 1), attribute mass: is not a finite number"), std::string::npos) << o.err;
  // Sizes MuJoCo allocates before it reads a body: refused from the file.
  for (const char* size : {"<size nstack=\"1e12\"/>", "<size memory=\"1e15\"/>", "<size nuser_body=\"100000\"/>"}) {
    std::string text = kMjcf;
    text.replace(text.find("<worldbody>"), 11, std::string(size) + "<worldbody>");
    write(path, text);
    o = runLieflow("import " + path + " --out " + testFile(".json"), 1024);
    EXPECT_EQ(o.status, 2) << size << o.err;
    EXPECT_NE(o.err.find("is more than lieflow lets MuJoCo allocate"), std::string::npos) << o.err;
  }
}

TEST(HostileModelFiles, ZeroQuaternionsTimestepsAndBrokenXmlAreRefusedInWords) {
  if (!lieflow::canReadMjcf()) GTEST_SKIP() << "this build has no MJCF reader";
  const std::string path = testFile(".xml"), model = kMjcf;
  struct Case {
    std::string from, to, expected;
  };
  const std::vector<Case> cases = {
      {"quat=\"1 0 0 0\"", "quat=\"0 0 0 0\"", "body 'arm' (line 4), attribute quat: has norm 0"},
      {"timestep=\"0.002\"", "timestep=\"0\"", "attribute timestep: must be positive"},
      {"timestep=\"0.002\"", "timestep=\"-1\"", "attribute timestep: must be positive"},
      {"</worldbody>", "</world>", "broken XML: an element is closed by another element's end tag"},
      {"<mujoco model=\"m\">", "", "an MJCF file's root element is <mujoco>, not <option>"},
  };
  for (const Case& c : cases) {
    std::string text = model;
    text.replace(text.find(c.from), c.from.size(), c.to);
    write(path, text);
    const Outcome o = runLieflow("import " + path + " --out " + testFile(".json"));
    EXPECT_EQ(o.status, 2) << c.to << "\n" << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << o.err;
    EXPECT_EQ(o.err.find("ErrorID"), std::string::npos) << o.err;  // tinyxml2's enum, not words
  }
  // A keyframe's free-joint quaternion of norm 0.
  write(path, "<mujoco model=\"m\"><worldbody><body name=\"b\"><freejoint name=\"root\"/><geom size=\"0.1\" "
              "contype=\"0\" conaffinity=\"0\"/></body></worldbody><keyframe><key name=\"k\" qpos=\"0 0 1 0 0 0 0\"/>"
              "</keyframe></mujoco>\n");
  const Outcome o = runLieflow("import " + path + " --keyframe k --out " + testFile(".json"));
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("key 'k' (line 1), attribute qpos: the quaternion of joint 'root' (qpos[3..6]) has norm 0"),
            std::string::npos)
      << o.err;
  // MuJoCo's own refusals come as one sentence naming the line.
  std::string text = model;
  text.replace(text.find("size=\"0.05\""), 11, "size=\"0\"");
  write(path, text);
  const Outcome m = runLieflow("import " + path + " --out " + testFile(".json"));
  EXPECT_EQ(m.status, 2) << m.err;
  EXPECT_NE(m.err.find("MuJoCo's compiler refuses it: line 9"), std::string::npos) << m.err;
  EXPECT_EQ(m.err.find("Object name ="), std::string::npos) << m.err;
}

TEST(HostileModelFiles, NamesThatWouldBreakTheCsvAreRefused) {
  const std::string scene = testFile(".json");
  for (const char* name : {"a,b", "a\\\"b", "a\\nb"}) {
    write(scene, std::string(R"({"name": "s", "bodies": [{"name": ")") + name +
                     R"(", "mass": 1, "inertia": [1, 2, 3]}], "t_end": 0.01})");
    const Outcome o = runLieflow("simulate " + scene + " --t-end 0.01");
    EXPECT_EQ(o.status, 2) << name << o.err;
    EXPECT_NE(o.err.find("bodies[0].name: holds a character that would break the CSV"), std::string::npos) << o.err;
    EXPECT_TRUE(o.out.empty()) << o.out;
  }
  // Bytes that are not UTF-8 in a robot's or a joint's name (found by
  // fuzz_urdf and fuzz_mjcf: the JSON writer threw on them).
  if (lieflow::canReadMjcf()) {
    std::string text = kMjcf;
    text.replace(text.find("name=\"hinge\""), 12, "name=\"hi\xff\xffnge\"");
    const std::string path = testFile(".xml");
    write(path, text);
    const Outcome o = runLieflow("import " + path + " --out " + testFile(".json"));
    EXPECT_EQ(o.status, 2) << o.err;
    EXPECT_NE(o.err.find("(line 5): its name is not valid UTF-8 text"), std::string::npos) << o.err;
  }
  if (!lieflow::canReadUrdf()) return;
  {
    std::string text = kUrdf;
    text.replace(text.find("name=\"r\""), 8, "name=\"r\xff\x07\"");
    const std::string path = testFile(".urdf");
    write(path, text);
    const Outcome o = runLieflow("import " + path + " --out " + testFile(".json"));
    EXPECT_EQ(o.status, 2) << o.err;
    EXPECT_NE(o.err.find("the model's name is not valid UTF-8 text"), std::string::npos) << o.err;
  }
  std::string text = kUrdf;
  for (std::size_t at = text.find("\"finger\""); at != std::string::npos; at = text.find("\"finger\"", at + 1))
    text.replace(at, 8, "\"fin,ger\"");
  const std::string path = testFile(".urdf");
  write(path, text);
  const Outcome o = runLieflow("import " + path + " --out " + testFile(".json"));
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("link 'fin,ger' (line 7): its name holds a character"), std::string::npos) << o.err;
}

}  // namespace
