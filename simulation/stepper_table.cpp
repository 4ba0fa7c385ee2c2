/// \file
/// The questions asked of the table of steppers (stepper_table.hpp), answered
/// from its rows (stepper_table_rows.hpp).
#include "simulation/stepper_table.hpp"

#include "simulation/stepper_table_rows.hpp"

namespace lieflow {

namespace {

/// The reason in the row's cell of column K (empty where it has a stepper).
template <typename K>
std::string emptyCellReason(const std::string& integrator) {
  std::string why;
  stepper_table::forEachRow([&](const auto& row) {
    using Row = std::decay_t<decltype(row)>;
    if constexpr (stepper_table::IsEmptyCell<Row, K>::value)
      if (integrator == row.name) why = row.make(K{}).why;
  });
  return why;
}

/// Why the row's cell of column K runs only when asked for (empty: it may be the default).
template <typename K>
std::string notDefaultIn(const std::string& integrator) {
  std::string why;
  stepper_table::forEachRow([&](const auto& row) {
    using Row = std::decay_t<decltype(row)>;
    if constexpr (stepper_table::HasNotDefault<Row, K>::value)
      if (integrator == row.name) why = row.notDefault(K{});
  });
  return why;
}

}  // namespace

const char* systemKindName(SystemKind kind) {
  switch (kind) {
    case SystemKind::kSingleBody: return "for a single body";
    case SystemKind::kMaximal: return "for scenes with joints";
    case SystemKind::kJointTree: return "in joint coordinates";
    case SystemKind::kJointCoupled: return "in joint coordinates with coupling rows";
    case SystemKind::kJointLoops: return "in joint coordinates with closed loops or gear rows";
  }
  return "";
}

std::string stepperUnavailable(const std::string& integrator, SystemKind kind) {
  return stepper_table::withColumn(kind, [&](auto column) { return emptyCellReason<decltype(column)>(integrator); });
}

std::string notDefaultReason(const std::string& integrator, SystemKind kind) {
  return stepper_table::withColumn(kind, [&](auto column) { return notDefaultIn<decltype(column)>(integrator); });
}

std::vector<std::string> steppersFor(SystemKind kind) {
  std::vector<std::string> names;
  stepper_table::forEachRow([&](const auto& row) {
    if (stepperUnavailable(row.name, kind).empty()) names.push_back(row.name);
  });
  return names;
}

}  // namespace lieflow
