// Device tests skip without a usable CUDA device; ISPH_REQUIRE_GPU_TESTS=1 turns the skip into a failure
// (for GPU machines, where a skip would hide a broken set-up).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "core/device_memory.hpp"

namespace isph::testing {
inline bool gpu_required() {
  const char* v = std::getenv("ISPH_REQUIRE_GPU_TESTS");
  return v && std::string(v) == "1";
}
}  // namespace isph::testing

#define ISPH_SKIP_WITHOUT_GPU()                                                          \
  do {                                                                                   \
    if (::isph::cuda_devices() == 0) {                                                   \
      if (::isph::testing::gpu_required())                                               \
        FAIL() << "ISPH_REQUIRE_GPU_TESTS=1 but no CUDA device is usable in this build"; \
      GTEST_SKIP() << "no CUDA device (or the build has no CUDA backend)";               \
    }                                                                                    \
  } while (0)
