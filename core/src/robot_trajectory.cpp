// Robots' joint trajectories (CSV file or inline JSON rows), checked against the URDF's joints
// and limits, their sampling and linear interpolation (docs/robots.md).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include "camplace/core/error.hpp"
#include "robot_parts.hpp"

namespace camplace::core::detail::robot_parts {

namespace {

/// Slack (rad or m) of the joint limit check: values computed elsewhere may round past a limit.
constexpr double kLimitSlack = 1e-9;
/// At most this many samples per robot (an "every_s" far below the trajectory's length would
/// otherwise make millions of time steps).
constexpr int kMaxSamples = 100000;
// Trajectory times (s) beyond this are refused: differences and interpolation stay finite.
constexpr double kMaxTime = 1e9;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "(none)" : out;
}

/// Checks one joint value of a trajectory row against the joint's limits.
void check_limits(const RobotModel& model, int column, double value, const std::string& file,
                  const std::string& entry, const std::string& row) {
  const urdf::Joint& j = *model.joints.at(model.movable[column]).joint;
  if (!has_limits(j)) return;
  const double lo = j.limits->lower, hi = j.limits->upper;
  if (value < lo - kLimitSlack || value > hi + kLimitSlack) {
    const char* unit = j.type == urdf::Joint::PRISMATIC ? " m" : " rad";
    throw InputError(file, entry,
                     "joint " + in_quotes(j.name) + " value " + format_number(value) + unit +
                         " at " + row + " is outside its limits [" + format_number(lo) + ", " +
                         format_number(hi) + "]" + unit);
  }
}

std::string movable_list(const RobotModel& model) {
  return "the robot's movable joints are: " + joined(model.movable);
}

/// Why a name is not a trajectory column ("" when it is one).
std::string not_a_column(const RobotModel& model, const std::string& name) {
  const auto it = model.joints.find(name);
  if (it == model.joints.end())
    return "unknown joint " + in_quotes(name) + " (" + movable_list(model) + ")";
  if (!is_movable(*it->second.joint))
    return "joint " + in_quotes(name) + " is fixed and takes no value (" + movable_list(model) +
           ")";
  if (it->second.joint->mimic) {
    return "joint " + in_quotes(name) + " mimics " +
           in_quotes(it->second.joint->mimic->joint_name) +
           ": its value follows from that joint's, leave it out";
  }
  return "";
}

std::optional<double> parse_number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
    return std::nullopt;
  return v;
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

}  // namespace

Trajectory read_csv_trajectory(const JsonNode& node, const std::string& path,
                               const RobotModel& model) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) node.fail("trajectory file " + path + " does not exist");
  if (!std::filesystem::is_regular_file(path, ec))
    node.fail("trajectory file " + path + " is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) node.fail("trajectory file " + path + " cannot be opened");
  Trajectory traj;
  std::vector<int> columns;  // header column k (k ≥ 1) → movable column
  std::vector<std::string> header;
  std::string line;
  int line_no = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    const std::string at_line = "line " + std::to_string(line_no);
    const std::vector<std::string> cells = split_csv(text);
    if (!have_header) {
      have_header = true;
      header = cells;
      if (cells[0] != "t") {
        throw InputError(path, at_line,
                         "the header's first column must be \"t\" (the time in s), found " +
                             in_quotes(cells[0]));
      }
      std::vector<bool> given(model.movable.size(), false);
      for (std::size_t k = 1; k < cells.size(); ++k) {
        const std::string& name = cells[k];
        const std::string column_entry = at_line + ", column " + std::to_string(k + 1);
        if (name.empty()) throw InputError(path, column_entry, "empty column name");
        const std::string why = not_a_column(model, name);
        if (!why.empty()) throw InputError(path, column_entry, why);
        const int c = model.joints.at(name).column;
        if (given[c])
          throw InputError(path, column_entry, "joint " + in_quotes(name) + " is given twice");
        given[c] = true;
        columns.push_back(c);
      }
      std::vector<std::string> missing;
      for (std::size_t c = 0; c < given.size(); ++c)
        if (!given[c]) missing.push_back(model.movable[c]);
      if (!missing.empty()) {
        throw InputError(path, at_line,
                         "the header has no column for the movable joints " + joined(missing) +
                             " (every movable joint that mimics no other must be given)");
      }
      continue;
    }
    if (cells.size() != header.size()) {
      throw InputError(path, at_line,
                       "the row has " + std::to_string(cells.size()) + " values, the header " +
                           std::to_string(header.size()) + " columns");
    }
    std::vector<double> row(model.movable.size(), 0.0);
    double t = 0.0;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::string cell_entry = at_line + ", column " + in_quotes(header[k]);
      const auto v = parse_number(cells[k]);
      if (!v) throw InputError(path, cell_entry, in_quotes(cells[k]) + " is not a finite number");
      if (k == 0) {
        t = *v;
      } else {
        check_limits(model, columns[k - 1], *v, path, cell_entry, at_line);
        row[columns[k - 1]] = *v;
      }
    }
    if (!(std::abs(t) <= kMaxTime)) {
      throw InputError(
          path, at_line + ", column \"t\"",
          "time " + format_number(t) + " s is beyond ±" + format_number(kMaxTime) + " s");
    }
    if (!traj.times.empty() && !(t > traj.times.back())) {
      throw InputError(path, at_line + ", column \"t\"",
                       "time " + format_number(t) + " s is not after the previous row's " +
                           format_number(traj.times.back()) + " s: times must increase strictly");
    }
    traj.times.push_back(t);
    traj.values.push_back(std::move(row));
  }
  if (traj.times.empty()) {
    throw InputError(path, "",
                     have_header ? "the trajectory has a header but no rows (at least one needed)"
                                 : "the trajectory is empty: it needs a header \"t,<joint>,...\" "
                                   "and at least one row");
  }
  return traj;
}

Trajectory read_json_trajectory(const JsonNode& list, const RobotModel& model) {
  Trajectory traj;
  if (list.array_size() == 0) list.fail("the trajectory needs at least one row");
  for (std::size_t r = 0; r < list.array_size(); ++r) {
    const JsonNode row_node = list.at(r);
    row_node.only_keys({"t", "joints"});
    const JsonNode t_node = row_node.at("t");
    const double t = t_node.number();
    if (!(std::abs(t) <= kMaxTime))
      t_node.fail("time " + format_number(t) + " s is beyond ±" + format_number(kMaxTime) + " s");
    if (!traj.times.empty() && !(t > traj.times.back())) {
      t_node.fail("time " + format_number(t) + " s is not after the previous row's " +
                  format_number(traj.times.back()) + " s: times must increase strictly");
    }
    const JsonNode joints = row_node.at("joints");
    if (!joints.is_object()) joints.fail("expected an object {\"joint\": value, ...}");
    std::vector<double> row(model.movable.size(), 0.0);
    std::vector<bool> given(model.movable.size(), false);
    for (const auto& item : joints.value().items()) {
      const JsonNode v = joints.at(item.key());
      const std::string why = not_a_column(model, item.key());
      if (!why.empty()) v.fail(why);
      const int c = model.joints.at(item.key()).column;
      const double value = v.number();
      check_limits(model, c, value, v.file(), v.pointer(), "row " + std::to_string(r));
      row[c] = value;
      given[c] = true;
    }
    std::vector<std::string> missing;
    for (std::size_t c = 0; c < given.size(); ++c)
      if (!given[c]) missing.push_back(model.movable[c]);
    if (!missing.empty()) {
      joints.fail("row " + std::to_string(r) + " gives no value for the movable joints " +
                  joined(missing) + " (every movable joint that mimics no other must be given)");
    }
    traj.times.push_back(t);
    traj.values.push_back(std::move(row));
  }
  return traj;
}

/// The sample times: one per row, `steps` evenly spaced, or `every_s` apart (and the last).
std::vector<double> sample_times(const Trajectory& traj, const JsonNode* sample) {
  if (!sample) return traj.times;
  sample->only_keys({"steps", "every_s"});
  if (sample->has("steps") == sample->has("every_s"))
    sample->fail("give exactly one of \"steps\" or \"every_s\"");
  const double t0 = traj.times.front(), t1 = traj.times.back();
  std::vector<double> times;
  if (sample->has("steps")) {
    const int n = sample->at("steps").integer_in(1, kMaxSamples);
    for (int k = 0; k < n; ++k)
      times.push_back(k == n - 1 && n > 1 ? t1 : t0 + (t1 - t0) * (double(k) / std::max(1, n - 1)));
    return times;
  }
  const JsonNode dt_node = sample->at("every_s");
  const double dt = dt_node.number();
  if (!(dt > 0)) dt_node.fail("every_s must be positive");
  const double count = std::floor((t1 - t0) / dt);
  if (count + 2 > kMaxSamples) {
    dt_node.fail("every_s " + format_number(dt) + " s over " + format_number(t1 - t0) +
                 " s gives more than " + std::to_string(kMaxSamples) + " samples");
  }
  for (int k = 0;; ++k) {
    const double t = t0 + k * dt;
    // A sample within a millionth of dt of the end is the end itself.
    if (t >= t1 - 1e-6 * dt) break;
    times.push_back(t);
  }
  times.push_back(t1);
  return times;
}

/// Joint values (trajectory columns) at time t, linear between the rows around it.
std::vector<double> interpolate(const Trajectory& traj, double t) {
  const auto& ts = traj.times;
  if (t <= ts.front()) return traj.values.front();
  if (t >= ts.back()) return traj.values.back();
  const std::size_t i =
      std::upper_bound(ts.begin(), ts.end(), t) - ts.begin();  // ts[i-1] ≤ t < ts[i]
  const double s = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
  std::vector<double> q(traj.values[i].size());
  for (std::size_t c = 0; c < q.size(); ++c)
    q[c] = (1 - s) * traj.values[i - 1][c] + s * traj.values[i][c];
  return q;
}

}  // namespace camplace::core::detail::robot_parts
