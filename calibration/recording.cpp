#include "calibration/recording.hpp"

#include "model/input_file.hpp"
#include "model/scene.hpp"

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

constexpr std::array<const char*, 4> kQuaternionSuffixes = {"qw", "qx", "qy", "qz"};
constexpr std::array<const char*, 3> kRateSuffixes = {"wx", "wy", "wz"};
constexpr std::array<const char*, 3> kAccelerometerSuffixes = {"ax", "ay", "az"};
/// Body columns of the trajectory CSV that calibration does not use; they
/// still make their prefix a body.
constexpr std::array<const char*, 6> kOtherBodySuffixes = {"x", "y", "z", "vx", "vy", "vz"};

template <std::size_t N>
bool contains(const std::array<const char*, N>& list, const std::string& s) {
  for (const char* item : list)
    if (s == item) return true;
  return false;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::stringstream s(line);
  while (std::getline(s, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

std::string where(const std::string& source, int line) {
  return source + ", line " + std::to_string(line);
}

std::string where(const std::string& source, int line, const std::string& column) {
  return where(source, line) + ", column " + column;
}

/// Column indices of one body's groups (−1 where absent).
struct BodyColumns {
  std::string name;
  std::array<int, 4> quaternion{-1, -1, -1, -1};
  std::array<int, 3> rate{-1, -1, -1};
  std::array<int, 3> acc{-1, -1, -1};
};

/// Checks that a column group is complete or absent, naming what is missing.
template <std::size_t N>
bool completeGroup(const std::string& source, const std::string& body, const std::array<int, N>& cols,
                   const std::array<const char*, N>& suffixes, const char* what) {
  int present = 0;
  for (int c : cols) present += c >= 0;
  if (present == 0) return false;
  if (present < static_cast<int>(N)) {
    std::string all, missing;
    for (std::size_t i = 0; i < N; ++i) {
      all += std::string(i ? "," : "") + body + "." + suffixes[i];
      if (cols[i] < 0) missing += std::string(missing.empty() ? "" : ", ") + body + "." + suffixes[i];
    }
    throw InvalidInput(where(source, 1), "column " + missing + " missing: body '" + body + "' has part of its " +
                                             what + " (" + all + ")");
  }
  return true;
}

}  // namespace

const BodySamples* Recording::body(const std::string& name) const {
  for (const BodySamples& b : bodies)
    if (b.name == name) return &b;
  return nullptr;
}

const std::vector<double>* Recording::column(const std::string& name) const {
  for (const ScalarColumn& c : scalars)
    if (c.name == name) return &c.values;
  return nullptr;
}

std::string Recording::bodyList() const {
  std::string out;
  for (const BodySamples& b : bodies) out += (out.empty() ? "" : ", ") + b.name;
  return out.empty() ? "none" : out;
}

namespace {

/// Where a recording's header puts the time, each body's columns (grouped by
/// prefix) and the other (scalar) columns.
struct HeaderColumns {
  int time_col = -1;
  std::vector<BodyColumns> body_cols;
  std::vector<int> scalar_cols;
};

/// The header's columns: `t`, body columns grouped by prefix, everything
/// else a scalar column of `rec` (named, no values yet).
HeaderColumns readHeader(const std::vector<std::string>& header, const std::string& source, Recording* rec_out) {
  Recording& rec = *rec_out;
  HeaderColumns out;
  std::map<std::string, int> seen;
  for (int c = 0; c < static_cast<int>(header.size()); ++c) {
    const std::string& name = header[c];
    if (name.empty()) throw InvalidInput(where(source, 1), "column " + std::to_string(c + 1) + " has no name");
    if (seen.count(name))
      throw InvalidInput(where(source, 1), "column " + name + " appears twice (columns " +
                                               std::to_string(seen[name] + 1) + " and " + std::to_string(c + 1) +
                                               ")");
    seen[name] = c;
    if (name == "t") {
      out.time_col = c;
      continue;
    }
    const auto dot = name.rfind('.');
    const std::string prefix = dot == std::string::npos ? "" : name.substr(0, dot);
    const std::string suffix = dot == std::string::npos ? "" : name.substr(dot + 1);
    const bool quaternion = contains(kQuaternionSuffixes, suffix);
    const bool rate = contains(kRateSuffixes, suffix);
    const bool acc = contains(kAccelerometerSuffixes, suffix);
    if (prefix.empty() || (!quaternion && !rate && !acc && !contains(kOtherBodySuffixes, suffix))) {
      out.scalar_cols.push_back(c);
      rec.scalars.push_back(ScalarColumn{name, {}});
      continue;
    }
    auto it = out.body_cols.begin();
    while (it != out.body_cols.end() && it->name != prefix) ++it;
    if (it == out.body_cols.end()) {
      out.body_cols.push_back(BodyColumns{prefix, {-1, -1, -1, -1}, {-1, -1, -1}, {-1, -1, -1}});
      it = out.body_cols.end() - 1;
    }
    for (std::size_t i = 0; i < kQuaternionSuffixes.size(); ++i)
      if (suffix == kQuaternionSuffixes[i]) it->quaternion[i] = c;
    for (std::size_t i = 0; i < kRateSuffixes.size(); ++i)
      if (suffix == kRateSuffixes[i]) it->rate[i] = c;
    for (std::size_t i = 0; i < kAccelerometerSuffixes.size(); ++i)
      if (suffix == kAccelerometerSuffixes[i]) it->acc[i] = c;
  }
  if (out.time_col < 0) throw InvalidInput(where(source, 1), "no column t (the header must name a time column t)");

  return out;
}

/// The numbers of one data row (line `line_number`) into `values`: as many
/// cells as the header has columns, each a finite number lieflow accepts.
void readRow(const std::vector<std::string>& cells, const std::vector<std::string>& header,
             const std::string& source, int line_number, std::vector<double>* values) {
  const std::size_t ncols = header.size();
  if (cells.size() != ncols)
    throw InvalidInput(where(source, line_number), "expected " + std::to_string(ncols) +
                                                       " values (the header's columns), found " +
                                                       std::to_string(cells.size()));
  for (std::size_t c = 0; c < ncols; ++c) {
    const std::string& cell = cells[c];
    if (cell.empty()) throw InvalidInput(where(source, line_number, header[c]), "missing value");
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (end == cell.c_str() || *end != '\0')
      throw InvalidInput(where(source, line_number, header[c]), "'" + cell + "' is not a number");
    if (!std::isfinite(v))
      throw InvalidInput(where(source, line_number, header[c]), "'" + cell + "' is not finite");
    if (const std::string problem = inputNumberProblem(v); !problem.empty())
      throw InvalidInput(where(source, line_number, header[c]), problem);
    (*values)[c] = v;
  }
}

}  // namespace

Recording parseRecording(std::istream& in, const std::string& source, long max_rows) {
  Recording rec;
  rec.source = source;
  std::string line;
  if (!std::getline(in, line)) throw InvalidInput(source, "empty file (expected a header row starting with t)");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // One leading UTF-8 byte-order mark is skipped, as by the scene reader.
  if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
  // The names come back in the fits' JSON (main, secondary): UTF-8 text.
  if (!validUtf8(line)) throw InvalidInput(where(source, 1), "the header is not valid UTF-8 text");
  const std::vector<std::string> header = splitCells(line);

  const HeaderColumns columns = readHeader(header, source, &rec);
  const int time_col = columns.time_col;
  const std::vector<BodyColumns>& body_cols = columns.body_cols;
  const std::vector<int>& scalar_cols = columns.scalar_cols;

  std::vector<bool> has_q, has_w, has_a;
  for (const BodyColumns& b : body_cols) {
    has_q.push_back(completeGroup(source, b.name, b.quaternion, kQuaternionSuffixes, "orientation"));
    has_w.push_back(completeGroup(source, b.name, b.rate, kRateSuffixes, "angular velocity"));
    has_a.push_back(completeGroup(source, b.name, b.acc, kAccelerometerSuffixes, "accelerometer"));
    rec.bodies.push_back(BodySamples{b.name, {}, {}, {}});
  }

  // Rows.
  const std::size_t ncols = header.size();
  std::vector<double> values(ncols);
  int line_number = 1, first_blank = 0;
  std::string previous_time_cell;  // as written, for messages
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) {
      if (!first_blank) first_blank = line_number;
      continue;
    }
    if (first_blank) throw InvalidInput(where(source, first_blank), "empty row (missing values)");
    if (static_cast<long>(rec.time.size()) >= max_rows)
      throw limitExceeded(source, "data rows", static_cast<double>(max_rows) + 1, static_cast<double>(max_rows),
                          "`max_rows`");
    const std::vector<std::string> cells = splitCells(line);
    readRow(cells, header, source, line_number, &values);
    const double t = values[time_col];
    if (!rec.time.empty() && !(t > rec.time.back())) {
      std::ostringstream reason;
      reason << "time " << cells[time_col] << " does not increase (previous row: " << previous_time_cell << ")";
      throw InvalidInput(where(source, line_number, "t"), reason.str());
    }
    // A sampling interval below the smallest positive input: its reciprocal
    // (a rate, a frequency) would overflow; such a column is not in seconds.
    if (!rec.time.empty() && t - rec.time.back() < kMinPositiveInput)
      throw InvalidInput(where(source, line_number, "t"),
                         "the interval " + formatNumber(t - rec.time.back()) + " s from the previous row is below " +
                             formatNumber(kMinPositiveInput) + " s; is t in seconds?");
    rec.time.push_back(t);
    previous_time_cell = cells[time_col];
    for (std::size_t s = 0; s < scalar_cols.size(); ++s) rec.scalars[s].values.push_back(values[scalar_cols[s]]);
    for (std::size_t b = 0; b < body_cols.size(); ++b) {
      const BodyColumns& cols = body_cols[b];
      BodySamples& body = rec.bodies[b];
      if (has_q[b]) {
        const Eigen::Quaterniond q(values[cols.quaternion[0]], values[cols.quaternion[1]],
                                   values[cols.quaternion[2]], values[cols.quaternion[3]]);
        const double norm = q.norm();
        if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
          std::ostringstream reason;
          reason << "quaternion (" << cols.name << ".qw, .qx, .qy, .qz) has norm " << norm << ", not within "
                 << kQuaternionNormTolerance << " of 1";
          throw InvalidInput(where(source, line_number, cols.name + ".qw"), reason.str());
        }
        body.orientation.push_back(SO3d(q.normalized()));
      }
      if (has_w[b])
        body.angular_velocity.emplace_back(values[cols.rate[0]], values[cols.rate[1]], values[cols.rate[2]]);
      if (has_a[b]) body.specific_force.emplace_back(values[cols.acc[0]], values[cols.acc[1]], values[cols.acc[2]]);
    }
  }
  if (rec.time.empty()) throw InvalidInput(source, "no data rows after the header");
  return rec;
}

Recording readRecording(const std::string& path, const ResourceLimits& limits) {
  // A regular file within the size limit is parsed as it streams in (a
  // 10⁶-row recording is 0.46 GB of text, never held whole); anything else
  // (a pipe, /dev/zero) is read whole within the limit first.
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > limits.max_input_bytes)
      throw limitExceeded(path, "bytes (the file's size)", static_cast<double>(size),
                          static_cast<double>(limits.max_input_bytes), "`max_input_mb`");
    std::ifstream in(path);
    if (!in) throw InvalidInput(path, "cannot open the recording for reading");
    return parseRecording(in, path, limits.max_rows);
  }
  std::string text;
  if (!readInputFile(path, limits.max_input_bytes, &text))
    throw InvalidInput(path, "cannot open the recording for reading");
  std::istringstream in(std::move(text));
  return parseRecording(in, path, limits.max_rows);
}

JointSamples selectJoint(const Recording& recording, std::string main, std::string secondary) {
  const std::string& source = recording.source;
  if (main.empty() || secondary.empty()) {
    if (recording.bodies.size() != 2)
      throw InvalidInput(source, "the recording has " + std::to_string(recording.bodies.size()) + " bodies (" +
                                     recording.bodyList() + "): name them with `main` and `secondary`");
    const std::string& first = recording.bodies[0].name;
    const std::string& second = recording.bodies[1].name;
    if (main.empty()) main = secondary == first ? second : first;
    if (secondary.empty()) secondary = main == first ? second : first;
  }
  for (const std::string* name : {&main, &secondary})
    if (!recording.body(*name))
      throw InvalidInput(source, "no body '" + *name + "' in the recording (bodies: " + recording.bodyList() + ")");
  if (main == secondary) throw InvalidInput(source, "main and secondary are the same body '" + main + "'");
  JointSamples joint;
  joint.source = source;
  joint.time = recording.time;
  joint.main = *recording.body(main);
  joint.secondary = *recording.body(secondary);
  return joint;
}

}  // namespace calibration
}  // namespace lieflow
