#include "replay/run_table.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <istream>

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace replay {

FrameDecimator::FrameDecimator(std::size_t budget) : budget_(budget < 2 ? 2 : budget) {}

void FrameDecimator::offer(const std::vector<double>& row) {
  if (offered_ % stride_ == 0) {
    kept_.push_back(row);
    if (kept_.size() > 2 * budget_) {
      // Keep rows 0, 2, 4, ... of the kept ones: the stride doubles.
      std::size_t w = 1;  // (row 0 stays where it is: no self-move)
      for (std::size_t r = 2; r < kept_.size(); r += 2) kept_[w++] = std::move(kept_[r]);
      kept_.resize(w);
      stride_ *= 2;
    }
  }
  last_ = row;
  ++offered_;
}

std::size_t FrameDecimator::extra() const {
  // Every extra-th of the n kept rows, then the last offered row when it is
  // not among them: at most `budget` rows.
  const std::size_t n = kept_.size();
  const bool last_kept = offered_ > 0 && (offered_ - 1) % stride_ == 0;
  if (n + (last_kept ? 0 : 1) <= budget_) return 1;
  return (n + budget_ - 2) / (budget_ - 1);
}

std::vector<std::vector<double>> FrameDecimator::frames() const {
  const std::size_t extra = this->extra();
  std::vector<std::vector<double>> out;
  for (std::size_t r = 0; r < kept_.size(); r += extra) out.push_back(kept_[r]);
  if (offered_ > 0 && (offered_ - 1) % (stride_ * extra) != 0) out.push_back(last_);
  return out;
}

std::size_t FrameDecimator::stride() const { return stride_ * extra(); }

RunTable tableOf(const FrameDecimator& frames, const std::vector<std::string>& columns, const std::string& source) {
  RunTable run;
  run.source = source;
  run.columns = columns;
  run.rows = frames.frames();
  run.total_rows = frames.offered();
  run.stride = frames.stride();
  return run;
}

int RunTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

}  // namespace

RunTable readRunTable(const std::string& path, std::size_t frame_budget, const ResourceLimits& limits) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InvalidInput(path, "cannot be read (no such file)");
  if (!S_ISREG(st.st_mode)) throw InvalidInput(path, "is not a regular file");
  if (static_cast<std::uint64_t>(st.st_size) > limits.max_input_bytes)
    throw limitExceeded(path, "bytes", static_cast<double>(st.st_size), static_cast<double>(limits.max_input_bytes),
                        "--max-input-mb");
  std::ifstream in(path);
  if (!in) throw InvalidInput(path, "cannot be opened");
  return parseRunTable(in, path, frame_budget, limits.max_rows);
}

RunTable parseRunTable(std::istream& in, const std::string& path, std::size_t frame_budget, long max_rows) {
  RunTable table;
  table.source = path;
  std::string line;
  if (!std::getline(in, line)) throw InvalidInput(path, "is empty: a run's CSV starts with its header row");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  table.columns = splitCsv(line);
  if (table.columns.front() != "t")
    throw InvalidInput(path + ": line 1, column 1", "the first column of a run is 't', got '" + table.columns.front() + "'");
  for (std::size_t c = 0; c < table.columns.size(); ++c)
    if (table.columns[c].empty())
      throw InvalidInput(path + ": line 1, column " + std::to_string(c + 1), "empty column name");
  FrameDecimator decimator(frame_budget);
  std::vector<double> row(table.columns.size());
  long line_number = 1;
  double previous_t = -HUGE_VAL;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (static_cast<long>(decimator.offered()) >= max_rows)
      throw limitExceeded(path, "rows", static_cast<double>(max_rows) + 1, static_cast<double>(max_rows), "--max-rows");
    const std::vector<std::string> cells = splitCsv(line);
    const std::string where = path + ": line " + std::to_string(line_number);
    if (cells.size() != table.columns.size())
      throw InvalidInput(where, "has " + std::to_string(cells.size()) + " values for " +
                                    std::to_string(table.columns.size()) + " columns");
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const char* text = cells[c].c_str();
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(text, &end);
      if (cells[c].empty() || end != text + cells[c].size() || !std::isfinite(v))
        throw InvalidInput(where + ", column " + table.columns[c],
                           "expected a finite number, got '" + cells[c].substr(0, 40) + "'");
      row[c] = v;
    }
    if (!(row[0] > previous_t))
      throw InvalidInput(where + ", column t", "times must increase (after " + std::to_string(previous_t) + ")");
    previous_t = row[0];
    decimator.offer(row);
  }
  if (in.bad()) throw InvalidInput(path, "could not be read to its end");
  if (decimator.offered() == 0) throw InvalidInput(path, "has a header and no rows: nothing to replay");
  table.rows = decimator.frames();
  table.total_rows = decimator.offered();
  table.stride = decimator.stride();
  return table;
}

}  // namespace replay
}  // namespace lieflow
