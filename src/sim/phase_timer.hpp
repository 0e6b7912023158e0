#pragma once
// Wall time per phase of a run, for summary.json and the progress line.
#include <chrono>
#include <map>
#include <string>

namespace isph {

class PhaseTimer {
 public:
  using Clock = std::chrono::steady_clock;

  template <class F>
  void time(const std::string& phase, F&& f) {
    const auto t0 = Clock::now();
    f();
    seconds_[phase] += std::chrono::duration<double>(Clock::now() - t0).count();
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

 private:
  std::map<std::string, double> seconds_;
};

}  // namespace isph
