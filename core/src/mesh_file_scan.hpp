#pragma once
// A structural pre-scan of mesh files before CGAL's readers see them (CGAL trusts counts in
// the file: a huge PLY list count or OFF face size would hang or exhaust memory). Private to core.
#include <optional>
#include <string>

namespace camplace::core::detail {

/// Why the file cannot be handed to CGAL's readers safely (huge or inconsistent counts,
/// non-integer or out-of-range indices, non-finite coordinates), or nothing. `ext` is lower
/// case, with the dot.
std::optional<std::string> mesh_file_defect(const std::string& path, const std::string& ext);

}  // namespace camplace::core::detail
