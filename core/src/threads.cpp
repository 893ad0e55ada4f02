#include "camplace/core/threads.hpp"

#include <algorithm>
#include <thread>

namespace camplace::core {

int machine_cores() {
  const unsigned cores = std::thread::hardware_concurrency();
  return static_cast<int>(std::clamp(cores, 1u, static_cast<unsigned>(kMaxThreads)));
}

}  // namespace camplace::core
