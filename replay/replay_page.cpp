// The page: the run's kept columns as float64 (exactly the CSV's numbers),
// the scene's data, three.js and the player, in one HTML file.
#include "replay/replay_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "liegroup/invalid_input.hpp"
#include "replay/replay_scene.hpp"

namespace lieflow {
namespace replay {

extern const char* const kPlayerJs;   // player.js, embedded (replay/CMakeLists.txt)
extern const char* const kPlayerCss;  // player.css

namespace {

std::string readWhole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ReplayUnavailable("the replay inlines three.js, which is not at " + path +
                            " (apt-get install libjs-three, or set LIEFLOW_THREE_DIR to a folder holding "
                            "build/three.min.js and examples/js/)");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// `text` safe inside a <script> element: no "</" that would close it.
std::string scriptSafe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3)) text.replace(at, 2, "<\\/");
  return text;
}

std::string htmlEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// A nice length ≥ x: 1, 2 or 5 × 10^k.
double niceCeil(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= x) return m * p;
  return 10.0 * p;
}

/// Columns the page keeps: t, each body's pose, and every column that is not
/// a body's (joint coordinates, energy, momentum, constraint error); body
/// velocities and sensor columns are left out.
struct KeptColumns {
  std::vector<int> source;  ///< index in the run
  std::vector<std::string> names;
  std::vector<int> scalars;  ///< page indices of the columns offered in the chooser
};

/// The kept columns of `run` and each body's entry of the page (its pose
/// columns' page indices, its fixed centre); InvalidInput naming the run and
/// the column when a body's pose columns are missing.
KeptColumns keptColumns(const SceneDescription& scene, const RunTable& run, nlohmann::json* bodies_out) {
  std::set<std::string> body_names;
  for (const BodyDescription& b : scene.bodies) body_names.insert(b.name);
  KeptColumns kept;
  std::map<std::string, int> page_index;
  auto keep = [&](int c) {
    page_index[run.columns[c]] = static_cast<int>(kept.source.size());
    kept.source.push_back(c);
    kept.names.push_back(run.columns[c]);
  };
  keep(0);
  nlohmann::json& bodies = *bodies_out;
  bodies = nlohmann::json::array();
  for (const BodyDescription& b : scene.bodies) {
    nlohmann::json q = nlohmann::json::array(), x = nullptr;
    for (const char* part : {"qw", "qx", "qy", "qz"}) {
      const int c = run.column(b.name + "." + part);
      if (c < 0)
        throw InvalidInput(run.source + ": column " + b.name + "." + part,
                           "missing: the scene '" + scene.name + "' has a body '" + b.name +
                               "', so its run has this column (is this the run of another scene?)");
      keep(c);
      q.push_back(page_index[b.name + "." + part]);
    }
    if (!b.rotation_only) {
      x = nlohmann::json::array();
      for (const char* part : {"x", "y", "z"}) {
        const int c = run.column(b.name + "." + part);
        if (c < 0)
          throw InvalidInput(run.source + ": column " + b.name + "." + part,
                             "missing: body '" + b.name + "' is not rotation-only in the scene '" + scene.name + "'");
        keep(c);
        x.push_back(page_index[b.name + "." + part]);
      }
    }
    bodies.push_back({{"q", q}, {"x", x}, {"fixed", {b.position.x(), b.position.y(), b.position.z()}}});
  }
  for (std::size_t c = 1; c < run.columns.size(); ++c) {
    const std::string& name = run.columns[c];
    const std::size_t dot = name.rfind('.');
    if (page_index.count(name) || (dot != std::string::npos && body_names.count(name.substr(0, dot)))) continue;
    kept.scalars.push_back(static_cast<int>(kept.source.size()));
    keep(static_cast<int>(c));
  }
  return kept;
}

/// three.js, its orbit controls and the mesh loaders `formats` need, as
/// the text between one <script> element's tags (each file in its own).
std::string inlinedScripts(const ReplayOptions& options, const std::set<std::string>& formats) {
  std::string dir = options.three_dir;
  if (dir.empty()) dir = std::getenv("LIEFLOW_THREE_DIR") ? std::getenv("LIEFLOW_THREE_DIR") : kThreeDir;
  std::string scripts = readWhole(dir + "/build/three.min.js");
  scripts += "\n</script>\n<script>\n" + scriptSafe(readWhole(dir + "/examples/js/controls/OrbitControls.js"));
  const std::map<std::string, std::string> loaders = {
      {"stl", "STLLoader.js"}, {"dae", "ColladaLoader.js"}, {"obj", "OBJLoader.js"}};
  for (const std::string& format : formats)
    scripts += "\n</script>\n<script>\n" + scriptSafe(readWhole(dir + "/examples/js/loaders/" + loaders.at(format)));

  return scripts;
}

/// The page around the run's data and the scripts.
std::string pageHtml(const std::string& title_text, const std::vector<std::string>& notes, const nlohmann::json& data,
                     const std::string& scripts) {
  const std::string title = htmlEscape(title_text);
  std::string notes_html;
  for (const std::string& n : notes) notes_html += "<li>" + htmlEscape(n) + "</li>";
  std::ostringstream page;
  page << "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>lieflow replay: " << title
       << "</title>\n<style>\n" << kPlayerCss << "</style>\n</head>\n<body>\n"
       << "<pre id=\"lieflow-errors\" hidden></pre>\n<pre id=\"lieflow-state\" hidden></pre>\n"
       // Console errors and uncaught exceptions, kept where a test can read them.
       << "<script>\nwindow.lieflowErrors = [];\n(function () {\n"
          "  const keep = (m) => { window.lieflowErrors.push(m); "
          "document.getElementById('lieflow-errors').textContent = window.lieflowErrors.join('\\n'); };\n"
          "  const original = console.error;\n"
          "  console.error = function (...a) { keep('console.error: ' + a.join(' ')); original.apply(console, a); };\n"
          "  window.addEventListener('error', (e) => keep('uncaught: ' + e.message));\n})();\n</script>\n"
       << "<header><strong>" << title << "</strong> <span class=\"dim\">lieflow replay</span>"
       << "<details><summary>notes</summary><ul id=\"notes\">" << notes_html << "</ul></details></header>\n"
       << "<div id=\"view\"></div>\n"
       << "<footer><button id=\"play\">play</button>"
          "<label>speed <select id=\"speed\"><option>0.1</option><option>0.25</option><option>0.5</option>"
          "<option selected>1</option><option>2</option><option>5</option><option>10</option></select></label>"
          "<input id=\"slider\" type=\"range\" min=\"0\" value=\"0\" step=\"1\">"
          "<span id=\"clock\"></span>"
          "<label>column <select id=\"column\"></select></label><span id=\"reading\"></span>"
          "<label><input id=\"trails\" type=\"checkbox\"> trails</label>"
          "<label><input id=\"joints\" type=\"checkbox\" checked> joints</label></footer>\n"
       << "<script id=\"lieflow-run\" type=\"application/json\">" << scriptSafe(data.dump()) << "</script>\n"
       << "<script>\n" << scripts << "\n</script>\n<script>\n" << scriptSafe(kPlayerJs) << "\n</script>\n"
       << "</body>\n</html>\n";
  return page.str();
}

}  // namespace

std::string replayPage(const SceneDescription& scene, const RunTable& run, const ReplayOptions& options,
                       ReplaySummary* summary) {
  ReplaySummary s;
  if (run.rows.empty() || run.columns.empty() || run.columns.front() != "t")
    throw InvalidInput(run.source, "has no rows (or no t column): nothing to replay");
  s.rows = run.total_rows;
  nlohmann::json bodies;
  const KeptColumns kept = keptColumns(scene, run, &bodies);
  s.columns = kept.source.size();
  s.left_out = run.columns.size() - kept.source.size();

  // Frames: within the frame budget (the table already is) and the value budget.
  const std::size_t most = std::max(kMinFrames, kValueBudget / kept.source.size());
  // Every `every`-th row and the last: ⌈n/every⌉ + 1 ≤ cap.
  const std::size_t cap = std::max<std::size_t>(2, std::min(most, options.frame_budget)), n = run.rows.size();
  const std::size_t every = n <= cap ? 1 : (n + cap - 2) / (cap - 1);
  std::vector<std::size_t> frames;
  for (std::size_t r = 0; r < run.rows.size(); r += every) frames.push_back(r);
  if (frames.back() != run.rows.size() - 1) frames.push_back(run.rows.size() - 1);
  s.frames = frames.size();
  s.stride = run.stride * every;
  std::vector<double> values;
  values.reserve(frames.size() * kept.source.size());
  for (const std::size_t r : frames)
    for (const int c : kept.source) values.push_back(run.rows[r][c]);

  // Extent: the centres' box over the run, grown by the shapes' reach.
  MeshBudget budget{kMeshBudgetBytes, {}};
  std::vector<std::string> notes;
  SceneData sd = sceneData(scene, &budget, &notes);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
  double reach = 0.0;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    bodies[k]["name"] = scene.bodies[k].name;
    bodies[k]["shapes"] = std::move(sd.bodies[k]["shapes"]);
    reach = std::max(reach, sd.reach[k]);
    for (std::size_t f = 0; f < frames.size(); ++f) {
      Eigen::Vector3d p = scene.bodies[k].position;
      if (!bodies[k]["x"].is_null())
        for (int i = 0; i < 3; ++i) p[i] = values[f * kept.source.size() + bodies[k]["x"][i].get<int>()];
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if (scene.bodies.empty()) lo = hi = Eigen::Vector3d::Zero();
  const double extent = std::max({(hi - lo).norm() + 2.0 * reach, 0.2});
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double grid = niceCeil(2.0 * std::max(lo.head<2>().cwiseAbs().maxCoeff(), hi.head<2>().cwiseAbs().maxCoeff()) + extent);
  s.boxes = sd.boxes;

  if (s.stride > 1 || s.frames < s.rows)
    notes.insert(notes.begin(), "the page holds " + std::to_string(s.frames) + " of the run's " + std::to_string(s.rows) +
                                    " rows (one in " + std::to_string(s.stride) + ", and the last): a budget of " +
                                    std::to_string(cap) + " frames");
  if (s.left_out > 0)
    notes.push_back(std::to_string(s.left_out) + " columns of body velocities and sensors are not in the page");

  const nlohmann::json data = {{"title", options.title.empty() ? scene.name : options.title},
                               {"columns", kept.names},
                               {"scalars", kept.scalars},
                               {"frames", frames.size()},
                               {"rows", s.rows},
                               {"stride", s.stride},
                               {"values", base64(values.data(), values.size() * sizeof(double))},
                               {"bodies", bodies},
                               {"ground", sd.ground},
                               {"joints", sd.joints},
                               {"extent", extent},
                               {"centre", {centre.x(), centre.y(), centre.z()}},
                               {"grid", {{"size", grid}, {"divisions", 20}}}};

  const std::string scripts = inlinedScripts(options, budget.formats);
  std::string out = pageHtml(options.title.empty() ? scene.name : options.title, notes, data, scripts);
  s.notes = notes;
  s.bytes = out.size();
  if (summary) *summary = s;
  return out;
}

}  // namespace replay
}  // namespace lieflow
