// Output that never leaves a partial file: everything is written to a
// temporary file beside the target (same extension, so writers that pick the
// format by extension still work) and renamed over the target on commit().
// "-" means standard output: the temporary file lives in $TMPDIR and is copied
// to stdout on commit(). Without commit() the temporary file is removed.
#pragma once
#include <fstream>
#include <string>
#include <vector>

namespace imgmesh {

class AtomicOutput {
public:
  // binary: refuse "-" when stdout is a terminal. stdout_extension: the
  // extension of the temporary file behind "-" (for writers that choose the
  // format by extension, e.g. ".nrrd").
  explicit AtomicOutput(std::string target, bool binary = false, const std::string& stdout_extension = "");
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // The path to write to now (a temporary file).
  const std::string& path() const { return tmp_; }
  // The path the user asked for ("-" for stdout).
  const std::string& target() const { return target_; }
  bool is_stdout() const { return target_ == "-"; }
  // A text/binary stream on path(), opened on first use.
  std::ofstream& stream();
  // Flush, check, and move into place (within an OutputGroup: hand the
  // file to the group). Throws Error on failure.
  void commit();

private:
  std::string target_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Standard input copied, a chunk at a time, to a temporary file in $TMPDIR
// (removed with the object): a reader then sees a file it can measure (a
// header's declared size checked against the data that follows, before
// anything is allocated) and still read as it streams. Error when standard
// input is empty.
class StdinSpool {
public:
  StdinSpool();
  ~StdinSpool();
  StdinSpool(const StdinSpool&) = delete;
  StdinSpool& operator=(const StdinSpool&) = delete;
  const std::string& path() const { return tmp_; }

private:
  std::string tmp_;
};

// All or nothing for the outputs of one run (an .ele with its .node, OUT
// and --svg): while a group lives, AtomicOutput::commit() only finishes the
// temporary file; the group's commit() moves them all into place (or copies
// them to stdout) in the order they were committed, and a group that ends
// without commit() removes them. cli::Tool::run holds one around the tool.
class OutputGroup {
public:
  OutputGroup();  // the current group until it ends
  ~OutputGroup();
  OutputGroup(const OutputGroup&) = delete;
  OutputGroup& operator=(const OutputGroup&) = delete;
  void commit();  // throws Error

private:
  friend class AtomicOutput;
  struct Finished {
    std::string tmp, target;
  };
  std::vector<Finished> finished_;
  OutputGroup* outer_;
};

// What AtomicOutput says when binary data would go to a terminal.
extern const char* const kBinaryOnTerminal;

// Throws Error naming `target` when the folder it would be written in does
// not exist ("no such folder") or is not a folder.
void check_output_folder(const std::string& target);

// Read all of a file (or "-" for stdin) into memory. Throws Error.
std::string read_all(const std::string& path);

} // namespace imgmesh
