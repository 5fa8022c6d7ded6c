#include "cli/cli.hpp"

#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <iostream>
#include <new>
#include <thread>
#include <unistd.h>

namespace imgmesh::cli {

Tool::Tool(std::string name, std::string description)
    : app(std::move(description), name), name_(std::move(name)),
      start_(std::chrono::steady_clock::now()) {
  app.set_version_flag("--version", std::string(name_) + " (imgmesh) " IMGMESH_VERSION);
  app.add_flag("-q,--quiet", quiet_, "Print nothing on stderr but errors");
  app.add_flag("-v,--verbose", verbose_, "Print more about what is done");
  app.add_option("--stats", stats_path_, "Write a JSON report (counts, timings, guarantees) to FILE, or - for stdout")
      ->type_name("FILE|-");
  app.add_flag("--progress", progress_flag_, "Show progress on stderr even when it is not a terminal");
}

void Tool::add_seed(std::uint64_t default_seed) {
  seed_ = default_seed;
  app.add_option("--seed", seed_, "Seed of the random choices (same input and seed give the same output)")
      ->capture_default_str();
}

void Tool::add_threads() {
  threads_ = int(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--threads", threads_, "Number of threads (default: all cores)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
}

void Tool::info(const std::string& msg) const {
  if (quiet_) return;
  if (progress_dirty_) { std::cerr << "\r\033[K"; progress_dirty_ = false; }
  std::cerr << name_ << ": " << msg << '\n';
}

void Tool::debug(const std::string& msg) const {
  if (verbose_) info(msg);
}

void Tool::report_progress(const std::string& msg) const {
  if (!progress_) return;
  if (isatty(STDERR_FILENO)) {
    std::cerr << "\r\033[K" << name_ << ": " << msg << std::flush;
    progress_dirty_ = true;
  } else {
    std::cerr << name_ << ": " << msg << '\n';
  }
}

double Tool::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

int Tool::finish(const Json& result, const std::string& failed_guarantee) {
  if (result.kind() == Json::Kind::Object)
    for (std::size_t i = 0; i < result.keys().size(); ++i) stats[result.keys()[i]] = result.items()[i];
  if (failed_guarantee.empty()) return kOk;
  info("guarantee not met: " + failed_guarantee);
  return kGuarantee;
}

int Tool::run(int argc, char** argv, const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    std::cerr << name_ << ": " << what << " (see " << name_ << " --help)\n";
    return kUsage;
  }
  if (verbose_) quiet_ = false;
  progress_ = !quiet_ && (progress_flag_ || isatty(STDERR_FILENO));
  start_ = std::chrono::steady_clock::now();

  int code = kFailure;
  std::string error;
  try {
    code = body();
  } catch (const UsageError& e) {
    error = e.message();
    code = kUsage;
  } catch (const Error& e) {
    error = e.message();
  } catch (const std::bad_alloc&) {
    error = "out of memory (the input is too large for this machine)";
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (progress_dirty_) { std::cerr << "\r\033[K"; progress_dirty_ = false; }
  if (!error.empty()) {
    // One line: collapse any newline a library message may carry.
    for (char& c : error)
      if (c == '\n' || c == '\r') c = ' ';
    std::cerr << name_ << ": " << error << '\n';
  }
  if (!stats_path_.empty() && code != kUsage) {
    try {
      Json report = Json::object();
      report["tool"] = name_;
      report["version"] = IMGMESH_VERSION;
      report["exit_status"] = code;
      report["seconds"] = elapsed();
      if (!error.empty()) report["error"] = error;
      // The tool's own entries follow the common ones.
      if (stats.kind() == Json::Kind::Object)
        for (std::size_t i = 0; i < stats.keys().size(); ++i) report[stats.keys()[i]] = stats.items()[i];
      AtomicOutput out(stats_path_);
      out.stream() << report.dump(2) << '\n';
      out.commit();
    } catch (const Error& e) {
      std::cerr << name_ << ": " << e.message() << '\n';
      if (code == kOk) code = kFailure;
    }
  }
  return code;
}

} // namespace imgmesh::cli
