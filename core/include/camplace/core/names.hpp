#pragma once
/// The words camplace uses in files, on the command line and in reports, and the enums they
/// name: one table per enum, so every module maps names the same way.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "camplace/core/scene.hpp"

namespace camplace::core {

/// How a voxel takes its label (SPEC §5).
enum class LabelMode {
  center,       ///< the label of the voxel's centre (the paper's basic version)
  conservative  ///< free only when every point of the voxel is free
};

/// Which pipeline evaluates a configuration (SPEC §5–6).
enum class Pipeline { voxel, exact, both };

/// The name table of an enum: `values` lists every enumerator with its name.
template <class Enum>
struct EnumNames;

template <>
struct EnumNames<LabelMode> {
  static constexpr std::array<std::pair<LabelMode, std::string_view>, 2> values{
      {{LabelMode::center, "center"}, {LabelMode::conservative, "conservative"}}};
};
template <>
struct EnumNames<Pipeline> {
  static constexpr std::array<std::pair<Pipeline, std::string_view>, 3> values{
      {{Pipeline::voxel, "voxel"}, {Pipeline::exact, "exact"}, {Pipeline::both, "both"}}};
};
template <>
struct EnumNames<FovShape> {
  static constexpr std::array<std::pair<FovShape, std::string_view>, 3> values{
      {{FovShape::cone, "cone"}, {FovShape::pyramid, "pyramid"}, {FovShape::frustum, "frustum"}}};
};
template <>
struct EnumNames<DynamicMode> {
  static constexpr std::array<std::pair<DynamicMode, std::string_view>, 2> values{
      {{DynamicMode::masked, "masked"}, {DynamicMode::modelled, "modelled"}}};
};

/// The name of an enumerator ("center", "pyramid", ...).
template <class Enum>
std::string name_of(Enum value) {
  for (const auto& [v, name] : EnumNames<Enum>::values) {
    if (v == value) return std::string(name);
  }
  return "?";
}

/// The enumerator with this name, or nullopt.
template <class Enum>
std::optional<Enum> from_name(std::string_view name) {
  for (const auto& [v, n] : EnumNames<Enum>::values) {
    if (n == name) return v;
  }
  return std::nullopt;
}

/// Every name of the enum, in declaration order (for validators and messages).
template <class Enum>
std::vector<std::string> names_of() {
  std::vector<std::string> out;
  for (const auto& entry : EnumNames<Enum>::values) out.emplace_back(entry.second);
  return out;
}

/// "\"a\", \"b\" or \"c\"" for messages.
template <class Enum>
std::string names_listed() {
  std::string out;
  const auto& values = EnumNames<Enum>::values;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out += i + 1 == values.size() ? " or " : ", ";
    out += "\"" + std::string(values[i].second) + "\"";
  }
  return out;
}

}  // namespace camplace::core
