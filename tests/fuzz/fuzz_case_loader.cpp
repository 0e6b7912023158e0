// libFuzzer target for the case loader (docs/RELIABILITY.md, "Fuzzing"): built with clang by
// -DISPH_FUZZ=ON, run by scripts/ci/fuzz.sh. Input format: tests/fuzz/case_input.hpp.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "case_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("isph_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  fuzz::load_case_input(std::string_view(reinterpret_cast<const char*>(data), size), dir);
  return 0;
}
