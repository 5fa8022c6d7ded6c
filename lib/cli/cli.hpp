// The command-line plumbing every tool shares (doc/design.md "Command-line
// conventions"): CLI11 set-up with the common flags, exit codes, one-line
// errors, --stats JSON and terminal progress. A tool is:
//
//   int main(int argc, char** argv) {
//     imgmesh::cli::Tool tool("img2wc", "Make a binary image well-composed");
//     std::string in, out;
//     tool.app.add_option("IN", in, "input image")->required();
//     tool.add_seed();
//     return tool.run(argc, argv, [&] {
//       const auto result = imgmesh::library_call(...);   // write the output
//       return tool.finish(result);
//     });
//
// A library result type has `Json to_json() const` (what --stats shows of
// it) and `std::string failed_guarantee() const` (which guarantee it could
// not meet, in words; empty when all hold): finish() is the one path from a
// result to the stats and the exit status. Whole-run time is measured here
// ("seconds"), not in the libraries.
//   }
#pragma once
#include "util/json.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace imgmesh::cli {

// What a data output carries: binary data is refused on a terminal.
enum class Stream { Text, Binary };

enum ExitCode : int {
  kOk = 0,         // done
  kFailure = 1,    // runtime or input error
  kUsage = 2,      // usage error
  kGuarantee = 3,  // output written, but a requested guarantee was not met
};

class Tool {
public:
  Tool(std::string name, std::string description);

  CLI::App app;
  Json stats = Json::object();  // written to --stats FILE|- at the end

  // Optional common options (the always-present ones are -h, --version,
  // -q, -v, --stats, --progress).
  void add_seed(std::uint64_t default_seed = 0);
  void add_threads();

  // Declares that `path` (an option's variable) names a data output, "-"
  // being standard output. Checked after parsing, before any work: "-" there
  // with --stats - is a usage error (one stream cannot carry both), binary
  // data is refused on a terminal, and a file's folder must exist. `used`
  // (default: always) says whether this run writes the output at all.
  void data_output(const std::string& path, Stream kind = Stream::Text, std::function<bool()> used = {});
  // The path for data_output of a tool whose data always goes to stdout.
  static const std::string kStdout;

  // Prints `report` on stdout as the run's one JSON object; with --stats -
  // the stats join it (after its keys) and all is printed at the end.
  void print_json(const Json& report);

  // The result's to_json() entries join the stats; a failed guarantee gives
  // kGuarantee (else kOk) and is said on stderr ("guarantee not met: ...",
  // even with --quiet) once the outputs are written.
  template <class Result> int finish(const Result& result) {
    return finish(result.to_json(), result.failed_guarantee());
  }
  int finish(const Json& result, const std::string& failed_guarantee);

  // Parse, run body, catch: prints "name: path: what" on stderr and returns
  // the exit code. Writes --stats (with "tool", "version", "exit_status",
  // "seconds") even when body returns kGuarantee.
  int run(int argc, char** argv, const std::function<int()>& body);

  const std::string& name() const { return name_; }
  bool quiet() const { return quiet_; }
  bool verbose() const { return verbose_; }
  std::uint64_t seed() const { return seed_; }
  int threads() const { return threads_; }  // >= 1
  // Progress wanted: stderr is a terminal or --progress, and not --quiet.
  bool progress() const { return progress_; }

  // A line on stderr, "name: msg", unless --quiet.
  void info(const std::string& msg) const;
  // Only with --verbose.
  void debug(const std::string& msg) const;
  // A progress line (overwritten in place on a terminal) when progress().
  void report_progress(const std::string& msg) const;
  double elapsed() const;

  // The SYNOPSIS and OPTIONS sections of the man page in roff, made from
  // app's options (names, type names, descriptions, defaults): what the
  // hidden flag --help-man prints. man/manpage.cmake puts them at the
  // markers of the hand-written man/NAME.1.in, and that file's note on an
  // option in place of the option's ".\" @NOTE --name@" line.
  std::string man_sections() const;

private:
  // A line on stderr, "name: msg", even with --quiet.
  void say(const std::string& msg) const;
  std::string failed_guarantee_;  // finish()'s, for kGuarantee
  struct DataOutput {
    const std::string* path;
    Stream kind;
    std::function<bool()> used;
  };
  void add_help_man();
  void check_outputs() const;
  void write_stats(int code, const std::string& error) const;

  std::string name_;
  std::string stats_path_;
  std::vector<DataOutput> outputs_;
  Json stdout_json_;  // print_json's report, held for --stats -
  bool has_stdout_json_ = false;
  bool quiet_ = false, verbose_ = false, progress_flag_ = false, progress_ = false;
  std::uint64_t seed_ = 0;
  int threads_ = 1;
  std::chrono::steady_clock::time_point start_;
  mutable bool progress_dirty_ = false;
};

} // namespace imgmesh::cli
