// Robots' URDF files (urdfdom): the model, its joints, their limits and mimic chains
// (docs/robots.md).
#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <set>
#include <sstream>

#include "camplace/core/error.hpp"
#include "robot_parts.hpp"

namespace camplace::core::detail::robot_parts {

namespace {

/// Collects what urdfdom reports through console_bridge while it parses (it prints to stderr
/// otherwise) and restores the previous handler and level afterwards.
class ConsoleCapture : public console_bridge::OutputHandler {
 public:
  ConsoleCapture()
      : previous_(console_bridge::getOutputHandler()), level_(console_bridge::getLogLevel()) {
    console_bridge::useOutputHandler(this);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  }
  ~ConsoleCapture() override {
    console_bridge::useOutputHandler(previous_);
    console_bridge::setLogLevel(level_);
  }
  ConsoleCapture(const ConsoleCapture&) = delete;
  ConsoleCapture& operator=(const ConsoleCapture&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_.push_back(trim(text));
  }
  /// The errors, joined by "; ".
  std::string errors() const {
    std::string out;
    for (const auto& e : errors_) out += (out.empty() ? "" : "; ") + e;
    return out;
  }

 private:
  console_bridge::OutputHandler* previous_;
  console_bridge::LogLevel level_;
  std::vector<std::string> errors_;
};

}  // namespace

bool is_movable(const urdf::Joint& j) {
  return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS ||
         j.type == urdf::Joint::PRISMATIC;
}

bool has_limits(const urdf::Joint& j) {
  return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::PRISMATIC;
}

RobotModel read_urdf(const JsonNode& urdf_node, const std::string& path,
                     const std::string& scene_file) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) urdf_node.fail("URDF file " + path + " does not exist");
  if (!std::filesystem::is_regular_file(path, ec))
    urdf_node.fail("URDF file " + path + " is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) urdf_node.fail("URDF file " + path + " cannot be opened");
  std::stringstream buffer;
  buffer << in.rdbuf();
  RobotModel model;
  model.entry = urdf_node.pointer();
  // urdfdom ignores elements it does not know: a xacro file would parse into a robot without
  // the links its macros make.
  if (buffer.str().find("<xacro:") != std::string::npos) {
    urdf_node.fail("URDF file " + path +
                   " contains xacro macros (<xacro:...>): expand it first, e.g. xacro "
                   "robot.urdf.xacro > robot.urdf (ROS 2: ros2 run xacro xacro "
                   "robot.urdf.xacro > robot.urdf)");
  }
  {
    ConsoleCapture capture;
    try {
      model.urdf = urdf::parseURDF(buffer.str());
    } catch (const std::exception& e) {
      urdf_node.fail("URDF file " + path + " cannot be parsed: " + e.what());
    }
    if (!model.urdf) {
      const std::string why = capture.errors();
      urdf_node.fail("URDF file " + path + " cannot be parsed" +
                     (why.empty() ? std::string(" (urdfdom gave no reason)") : ": " + why));
    }
  }
  const auto joint_fail = [&](const std::string& name, const std::string& reason) {
    throw InputError(scene_file, model.entry + " (joint " + in_quotes(name) + ")", reason);
  };
  for (const auto& [name, joint] : model.urdf->joints_) {
    JointMotion m;
    m.joint = joint.get();
    if (joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR) {
      joint_fail(name, std::string("joint type \"") +
                           (joint->type == urdf::Joint::FLOATING ? "floating" : "planar") +
                           "\" is not supported (only revolute, continuous, prismatic and "
                           "fixed joints): a robot's base is placed with \"base\"");
    }
    if (joint->type == urdf::Joint::UNKNOWN) joint_fail(name, "joint type is unknown");
    if (is_movable(*joint)) {
      const Vec3 axis(joint->axis.x, joint->axis.y, joint->axis.z);
      if (!(axis.norm() > 1e-12) || !axis.allFinite()) joint_fail(name, "joint axis is zero");
      m.axis = axis.normalized();
      if (has_limits(*joint) && !joint->limits) joint_fail(name, "joint has no <limit>");
      if (has_limits(*joint) && !(joint->limits->lower <= joint->limits->upper)) {
        joint_fail(name, "joint limits are empty: lower " + format_number(joint->limits->lower) +
                             " > upper " + format_number(joint->limits->upper));
      }
      if (!joint->mimic) model.movable.push_back(name);
    }
    model.joints[name] = m;
  }
  // Columns in the order of `movable` (joint names sorted); then mimic joints resolved through
  // chains of mimics to the column they follow.
  for (std::size_t c = 0; c < model.movable.size(); ++c)
    model.joints[model.movable[c]].column = static_cast<int>(c);
  for (auto& [name, m] : model.joints) {
    if (!is_movable(*m.joint) || !m.joint->mimic) continue;
    double multiplier = 1.0, offset = 0.0;
    std::string current = name;
    std::set<std::string> seen{name};
    while (true) {
      const urdf::JointMimic& mimic = *model.joints.at(current).joint->mimic;
      const auto target = model.joints.find(mimic.joint_name);
      if (target == model.joints.end() || !is_movable(*target->second.joint)) {
        joint_fail(name, "joint mimics " + in_quotes(mimic.joint_name) +
                             ", which is not a movable joint of the robot");
      }
      // value(current) = mimic.multiplier · value(target) + mimic.offset
      offset += multiplier * mimic.offset;
      multiplier *= mimic.multiplier;
      if (!target->second.joint->mimic) {
        m.column = target->second.column;
        break;
      }
      current = target->first;
      if (!seen.insert(current).second) joint_fail(name, "mimic joints form a cycle");
    }
    m.multiplier = multiplier;
    m.offset = offset;
  }
  return model;
}

}  // namespace camplace::core::detail::robot_parts
