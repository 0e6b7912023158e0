#include "sim/run.hpp"

#include <omp.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>

#include "io/output.hpp"
#include "sim/run_parts.hpp"

namespace isph {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

// Async-signal-safe: sets the flag, or ends the process on the second signal.
extern "C" void on_stop_signal(int signal) {
  if (g_stop_signal != 0) _exit(128 + signal);
  g_stop_signal = signal;
  static const char note[] = "\nisph: stopping at the end of this step (a second signal stops at once)\n";
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, note, sizeof note - 1);
}

// The scene, then the loop of the stages it has: a fluid (with or without structures) or structures alone.
template <int D>
RunResult run_dimension(const CaseSpec& spec, const RunOptions& opt) {
  PhaseTimer timer;
  Scene<D> scene;
  timer.time("setup", [&] { scene = build_scene<D>(spec); });
  for (const auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return scene.has_fluid ? run_fluid<D>(spec, opt, scene, timer) : run_structure<D>(spec, opt, scene, timer);
}

}  // namespace

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  RunOptions opt = options;
  if (!opt.restart.empty() && std::filesystem::is_directory(opt.restart)) opt.restart = newest_snapshot(opt.restart);
  return spec.dimension == 3 ? run_dimension<3>(spec, opt) : run_dimension<2>(spec, opt);
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int stop_signal() { return g_stop_signal; }

}  // namespace isph
