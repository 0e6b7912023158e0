// The `isph` command: run a case, check a case file, list the bundled cases, print the case keys.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "core/device_emulation.hpp"
#include "io/case_loader.hpp"
#include "io/case_schema.hpp"
#include "io/list_schema.hpp"
#include "sim/run.hpp"
#include "sim/scene.hpp"

namespace fs = std::filesystem;
using namespace isph;

namespace {

// Loads the case and builds its scene, so that `check` finds every problem a run would.
// Its warnings go to stderr.
CaseSpec load_and_check(const std::string& path, const std::vector<std::string>& overrides) {
  CaseSpec spec = load_case(path, overrides);
  const auto warnings = spec.dimension == 3 ? build_scene<3>(spec).warnings : build_scene<2>(spec).warnings;
  for (const auto& w : warnings) std::cerr << "warning: " << w << "\n";
  return spec;
}

int report(const CaseError& e) {
  for (const auto& p : e.problems()) std::cerr << "error: " << p << "\n";
  std::cerr << e.problems().size() << " problem(s) found\n";
  return 2;
}

// First comment line of a case file, used as its description.
std::string describe(const fs::path& file) {
  std::FILE* f = std::fopen(file.c_str(), "r");
  if (!f) return "";
  char line[512] = {};
  std::string text;
  if (std::fgets(line, sizeof line, f)) text = line;
  std::fclose(f);
  if (text.rfind("#", 0) != 0) return "";
  text = text.substr(text.find_first_not_of("# "));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

// `isph cases`: the case files of a folder, each with its first comment line.
int list_cases(const std::string& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) std::printf("%-28s %s\n", f.filename().c_str(), describe(f).c_str());
  return 0;
}

// `isph keys`: the reference of the case keys, printed, or regenerated in a markdown file's tables.
int print_keys(const std::string& docs_path) {
  if (docs_path.empty()) {
    for (const std::string& section : case_sections())
      std::printf("## %s\n\n%s\n", section.empty() ? "top level" : ("[" + section + "]").c_str(),
                  key_reference(section).c_str());
    for (const std::string& table : list_tables())
      std::printf("## %s\n\n%s\n", table.c_str(), list_key_reference(table).c_str());
    return 0;
  }
  std::ifstream in(docs_path);
  const std::string document{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::string updated = with_key_reference(document);
  if (updated != document) std::ofstream(docs_path) << updated;
  std::printf("%s: %s\n", docs_path.c_str(), updated == document ? "up to date" : "key tables regenerated");
  return 0;
}

// The options of `isph run`.
struct RunCommand {
  std::string case_path, out_dir, device = "cpu", restart;
  std::vector<std::string> overrides;
  int threads = 0;
  bool quiet = false;
};

// `isph run`: exit status 0 completed, 3 diverged, 4 interrupted (README).
int run_command(const RunCommand& c) {
  const CaseSpec spec = load_case(c.case_path, c.overrides);  // run_case reports scene problems itself
  RunOptions opt;
  opt.out_dir = c.out_dir;
  if (c.device == "debug") enable_device_emulation();
  opt.device = c.device == "cpu" ? Device::cpu : Device::cuda;
  opt.threads = c.threads;
  opt.progress = !c.quiet;
  opt.restart = c.restart;
  install_stop_handlers();
  const RunResult r = run_case(spec, opt);
  return r.status == "completed" ? 0 : r.status == "interrupted" ? 4 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"isph: coupled ISPH-TLSPH solver for hydroelastic fluid-structure interaction"};
  app.require_subcommand(1);

  RunCommand c;
  auto* run = app.add_subcommand("run", "run a case");
  run->add_option("case", c.case_path, "case file (TOML)")->required();
  run->add_option("--out", c.out_dir, "output directory (default out/<case name>)");
  run->add_option("--set", c.overrides, "override a case key: --set dotted.key=value (repeatable)");
  run->add_option("--device", c.device,
                  "cpu | cuda | debug (cuda: the particle loops run on the GPU, the state in managed memory; debug: "
                  "the cuda path run on the CPU, counting the host's touches of device memory, for testing)")
      ->check(CLI::IsMember({"cpu", "cuda", "debug"}));
  run->add_option("--threads", c.threads, "OpenMP threads (default: all cores)")->check(CLI::NonNegativeNumber);
  run->add_flag("--quiet", c.quiet, "no progress line");
  run->add_option("--restart", c.restart,
                  "continue an earlier run of the same case and --set options from its snapshot (.h5), or from the "
                  "newest whole snapshot of its output folder")
      ->check(CLI::ExistingPath);

  auto* check = app.add_subcommand("check", "validate a case file and report every problem");
  check->add_option("case", c.case_path, "case file (TOML)")->required();
  check->add_option("--set", c.overrides, "override a case key: --set dotted.key=value (repeatable)");
  bool print_resolved = false;
  check->add_flag("--resolved", print_resolved,
                  "print the case as it would run (overrides applied, every default written out: the run's "
                  "case.resolved.toml)");

  std::string cases_dir = std::string(ISPH_SOURCE_DIR) + "/cases";
  auto* cases = app.add_subcommand("cases", "list the bundled cases");
  cases->add_option("--dir", cases_dir, "folder of case files");

  std::string docs_path;
  auto* keys =
      app.add_subcommand("keys", "print the reference of the case keys, settings and lists (docs/CASES.md's tables)");
  keys->add_option("--update", docs_path, "regenerate the key tables of this markdown file in place")
      ->check(CLI::ExistingFile);

  CLI11_PARSE(app, argc, argv);

  try {
    if (*cases) return list_cases(cases_dir);
    if (*keys) return print_keys(docs_path);
    if (*check) {
      const CaseSpec spec = load_and_check(c.case_path, c.overrides);
      if (print_resolved) return std::fputs(spec.resolved_toml.c_str(), stdout) < 0 ? 1 : 0;
      std::printf("%s: ok (case '%s', %dD, dx = %g m, end_time = %g s)\n", c.case_path.c_str(), spec.name.c_str(),
                  spec.dimension, spec.dx, spec.end_time);
      return 0;
    }
    return run_command(c);
  } catch (const CaseError& e) {
    return report(e);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
