#include "cli/cli.hpp"

#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <iostream>
#include <new>
#include <set>
#include <thread>
#include <unistd.h>
#include <vector>

namespace imgmesh::cli {

Tool::Tool(std::string name, std::string description)
    : app(std::move(description), name), name_(std::move(name)),
      start_(std::chrono::steady_clock::now()) {
  app.set_version_flag("--version", std::string(name_) + " (imgmesh) " IMGMESH_VERSION);
  app.add_flag("-q,--quiet", quiet_, "Print nothing on stderr but errors");
  app.add_flag("-v,--verbose", verbose_, "Print more about what is done");
  app.add_option("--stats", stats_path_, "Write a JSON report (counts, timings, guarantees) to FILE, or - for stdout when the data does not go there")
      ->type_name("FILE|-");
  app.add_flag("--progress", progress_flag_, "Show progress on stderr even when it is not a terminal");
  add_help_man();
}

void Tool::add_seed(std::uint64_t default_seed) {
  seed_ = default_seed;
  app.add_option("--seed", seed_, "Seed of the random choices (same input and seed give the same output)")
      ->capture_default_str();
}

void Tool::add_threads() {
  threads_ = int(std::max(1u, std::thread::hardware_concurrency()));
  // The range and the default in the words: not CLI11's "INT:INT in
  // [1 - 1024]", nor this machine's core count as if it were the default.
  app.add_option("--threads", threads_, "Number of threads, 1 to 1024 (default: all cores)")
      ->type_name("N")
      ->check(CLI::Range(1, 1024).description(""));
}

const std::string Tool::kStdout = "-";

void Tool::data_output(const std::string& path, Stream kind, std::function<bool()> used) {
  outputs_.push_back({&path, kind, std::move(used)});
}

void Tool::check_outputs() const {
  for (const DataOutput& o : outputs_) {
    const std::string& path = *o.path;
    if (path.empty() || (o.used && !o.used())) continue;  // not written by this run
    if (path != "-") {
      check_output_folder(path);
    } else if (stats_path_ == "-") {
      throw UsageError("the data goes to standard output: give --stats a file name");
    } else if (o.kind == Stream::Binary && isatty(STDOUT_FILENO)) {
      throw UsageError(kBinaryOnTerminal, "-");
    }
  }
  if (!stats_path_.empty() && stats_path_ != "-") check_output_folder(stats_path_);
}

void Tool::print_json(const Json& report) {
  if (stats_path_ == "-") {
    stdout_json_ = report;
    has_stdout_json_ = true;
  } else {
    std::cout << report.dump(2) << "\n";
  }
}

void Tool::info(const std::string& msg) const {
  if (!quiet_) say(msg);
}

void Tool::say(const std::string& msg) const {
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

void Tool::add_help_man() {
  // Like --version: the callback runs before required options are checked.
  // The empty group hides it from --help.
  app.add_flag_callback("--help-man", [this] {
       std::cout << man_sections();
       throw CLI::Success();
     })->group("");
}

namespace {

// Text for roff: a backslash is \e, a minus sign \-, and a line must not
// start with a control character.
std::string roff(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\\') out += "\\e";
    else if (c == '-') out += "\\-";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out.insert(0, "\\&");
  return out;
}

// The entries of the object `from` set in `to`, in their order.
void add_entries(Json& to, const Json& from) {
  if (from.kind() != Json::Kind::Object) return;
  for (std::size_t i = 0; i < from.keys().size(); ++i) to[from.keys()[i]] = from.items()[i];
}

bool repeatable(const CLI::Option* o) { return o->get_expected_max() >= CLI::detail::expected_max_vector_size; }
// Flags have no type name.
bool takes_value(const CLI::Option* o) { return o->get_type_size() != 0 && !o->get_type_name().empty(); }

// The option as the SYNOPSIS shows it: one name (the first long one) and its value.
std::string synopsis_item(const CLI::Option* o) {
  std::string item;
  if (!o->nonpositional()) {
    item = "\\fI" + roff(o->get_name(true)) + "\\fR";
  } else {
    const std::string name = o->get_lnames().empty() ? "-" + o->get_snames().front() : "--" + o->get_lnames().front();
    item = "\\fB" + roff(name) + "\\fR";
    if (takes_value(o)) item += " \\fI" + roff(o->get_type_name()) + "\\fR";
  }
  if (!o->get_required()) item = "[" + item + "]";
  if (repeatable(o)) item += "...";
  return item;
}

// The option's tag line in OPTIONS: every name, then its value.
std::string options_tag(const CLI::Option* o) {
  if (!o->nonpositional()) return "\\fI" + roff(o->get_name(true)) + "\\fR";
  std::string tag;
  for (const auto& s : o->get_snames()) tag += (tag.empty() ? "" : ", ") + std::string("\\fB") + roff("-" + s) + "\\fR";
  for (const auto& l : o->get_lnames()) tag += (tag.empty() ? "" : ", ") + std::string("\\fB") + roff("--" + l) + "\\fR";
  if (takes_value(o)) tag += " \\fI" + roff(o->get_type_name()) + "\\fR";
  if (repeatable(o)) tag += " ...";
  return tag;
}

std::string option_names(const std::set<CLI::Option*>& options) {
  std::string names;
  for (const CLI::Option* o : options) names += (names.empty() ? "" : ", ") + std::string("\\fB") + roff(o->get_name()) + "\\fR";
  return names;
}

} // namespace

std::string Tool::man_sections() const {
  // Positionals first, as --help lists them; hidden options (empty group) left out.
  std::vector<const CLI::Option*> options;
  for (const CLI::Option* o : app.get_options())
    if (!o->get_group().empty() && !o->nonpositional()) options.push_back(o);
  for (const CLI::Option* o : app.get_options())
    if (!o->get_group().empty() && o->nonpositional()) options.push_back(o);

  std::string out = ".\\\" @SYNOPSIS@\n.B " + roff(name_) + "\n";
  for (const CLI::Option* o : options) out += synopsis_item(o) + "\n";
  out += ".\\\" @OPTIONS@\n";
  for (const CLI::Option* o : options) {
    out += ".TP\n" + options_tag(o) + "\n";
    std::string body = o->get_description();
    if (!body.empty() && body.back() != '.') body += '.';
    out += roff(body) + "\n";
    // A description that speaks of its default (e.g. "all cores") has the
    // one that holds on every machine.
    if (takes_value(o) && !o->get_default_str().empty() && body.find("default") == std::string::npos &&
        body.find("Default") == std::string::npos)
      out += "Default: " + roff(o->get_default_str()) + ".\n";
    if (o->get_required() && o->nonpositional()) out += "Required.\n";
    if (repeatable(o) && o->nonpositional()) out += "May be given more than once.\n";
    if (!o->get_needs().empty()) out += "Needs " + option_names(o->get_needs()) + ".\n";
    if (!o->get_excludes().empty()) out += "Excludes " + option_names(o->get_excludes()) + ".\n";
    const std::string key = !o->nonpositional()          ? o->get_name(true)
                            : !o->get_lnames().empty() ? "--" + o->get_lnames().front()
                                                       : "-" + o->get_snames().front();
    out += ".\\\" @NOTE " + key + "@\n";
  }
  return out;
}

int Tool::finish(const Json& result, const std::string& failed_guarantee) {
  add_entries(stats, result);
  if (failed_guarantee.empty()) return kOk;
  failed_guarantee_ = failed_guarantee;  // said by run() once the outputs are written
  return kGuarantee;
}

// The --stats report: the common entries, then the tool's own.
void Tool::write_stats(int code, const std::string& error) const {
  Json report = has_stdout_json_ ? stdout_json_ : Json::object();
  report["tool"] = name_;
  report["version"] = IMGMESH_VERSION;
  report["exit_status"] = code;
  report["seconds"] = elapsed();
  if (!error.empty()) report["error"] = error;
  add_entries(report, stats);
  AtomicOutput out(stats_path_);
  out.stream() << report.dump(2) << '\n';
  out.commit();
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
  bool stats_unwritable = false;  // its folder is missing: said once, not again
  bool stats_written = false;
  try {
    OutputGroup outputs;  // exit 1 or 2 leaves no output
    check_outputs();
    const int done = body();
    if (done == kOk || done == kGuarantee) {
      // What the body printed must have reached stdout; the --stats report
      // joins the group, so that the outputs and it land together.
      std::cout.flush();
      if (!std::cout) throw Error("write to standard output failed", "-");
      if (!stats_path_.empty()) write_stats(done, "");
      outputs.commit();
      stats_written = !stats_path_.empty();
    }
    code = done;
  } catch (const UsageError& e) {
    error = e.message();
    code = kUsage;
  } catch (const Error& e) {
    error = e.message();
    stats_unwritable = e.path() == stats_path_;
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
  } else if (code == kGuarantee) {
    // An error of its own kind: said even with --quiet, as errors are.
    say("guarantee not met: " + failed_guarantee_);
  }
  if (!stats_path_.empty() && code != kUsage && !stats_unwritable && !stats_written) {
    try {
      write_stats(code, error);
    } catch (const Error& e) {
      std::cerr << name_ << ": " << e.message() << '\n';
      if (code == kOk) code = kFailure;
    }
  }
  return code;
}

} // namespace imgmesh::cli
