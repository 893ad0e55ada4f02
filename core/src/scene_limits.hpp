#pragma once
// The largest lists a scene may give (docs/scene-format.md#limits): each bounds the work of
// loading and of every evaluation, so that no input of a few kilobytes makes camplace run for
// minutes before it says anything. Private to core.
#include <cstddef>
#include <string>

#include "camplace/core/json_reader.hpp"

namespace camplace::core::detail {

/// Keep-out boxes: the load-time check that every camera has somewhere to go, and the repair of
/// each blocked position during a search, try every pair and triple of the boxes' planes
/// (cubic in their number).
constexpr std::size_t kMaxKeepOut = 32;
constexpr std::size_t kMaxMounts = 256;
constexpr std::size_t kMaxCameraModels = 256;
constexpr std::size_t kMaxTimeSteps = 100000;
/// Objects of one list (static obstacles, a step's dynamic obstacles or critical objects, an
/// event's targets).
constexpr std::size_t kMaxObjects = 10000;
constexpr std::size_t kMaxEvents = 1000;
constexpr std::size_t kMaxRobots = 64;
constexpr std::size_t kMaxPeopleZones = 1000;
/// Vertices or triangles of a mesh given inline.
constexpr std::size_t kMaxInlineMesh = 1000000;
/// Points of a people zone's polygon, postures of a zone.
constexpr std::size_t kMaxSmallList = 1000;

/// The size of the JSON array `list`; fails naming the limit when it holds more than `max`
/// entries ("at most 32 keep-out boxes, found 40").
inline std::size_t limited_size(const JsonNode& list, std::size_t max, const std::string& what) {
  const std::size_t n = list.array_size();
  if (n > max) {
    list.fail("at most " + std::to_string(max) + " " + what + ", found " + std::to_string(n) +
              " (a limit of camplace that bounds the work of loading and evaluating a scene)");
  }
  return n;
}

}  // namespace camplace::core::detail
