#pragma once
// Wall time per phase of a run, for summary.json and the progress line; on the debug device also the
// pages of device memory the host touched in each phase (core/device_emulation.hpp).
#include <chrono>
#include <map>
#include <string>

#include "core/device_emulation.hpp"

namespace isph {

class PhaseTimer {
 public:
  using Clock = std::chrono::steady_clock;

  template <class F>
  void time(const std::string& phase, F&& f) {
    const auto t0 = Clock::now();
    const long long touched = emulated_host_touches();
    f();
    seconds_[phase] += std::chrono::duration<double>(Clock::now() - t0).count();
    if (device_emulated()) host_touches_[phase] += emulated_host_touches() - touched;
  }
  double get(const std::string& phase) const {
    auto it = seconds_.find(phase);
    return it == seconds_.end() ? 0.0 : it->second;
  }
  double total() const {
    double s = 0;
    for (const auto& [k, v] : seconds_) s += v;
    return s;
  }
  const std::map<std::string, double>& phases() const { return seconds_; }
  const std::map<std::string, long long>& host_touches() const { return host_touches_; }

 private:
  std::map<std::string, double> seconds_;
  std::map<std::string, long long> host_touches_;
};

}  // namespace isph
