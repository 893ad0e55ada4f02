#pragma once
/// The one limit on thread counts that every camplace option and evaluator shares.

namespace camplace::core {

/// Largest thread count any option (`--threads`, VoxelOptions::threads, Python `threads=`)
/// accepts.
constexpr int kMaxThreads = 256;

/// The cores of this machine (std::thread::hardware_concurrency()), clamped to 1..kMaxThreads.
int machine_cores();

}  // namespace camplace::core
