#include "util/atomic_file.hpp"

#include "util/error.hpp"
#include "util/path.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <iterator>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace imgmesh {

const char* const kBinaryOnTerminal = "refusing to write binary data to a terminal (redirect it or give a file name)";

void check_output_folder(const std::string& target) {
  const auto slash = target.find_last_of('/');
  if (slash == std::string::npos) return;  // the working folder
  const std::string dir = slash == 0 ? "/" : target.substr(0, slash);
  struct stat st;
  if (::stat(dir.c_str(), &st) != 0) throw Error(errno == ENOENT ? "no such folder" : std::strerror(errno), target);
  if (!S_ISDIR(st.st_mode)) throw Error("not a folder: " + dir, target);
}

// A new empty file dir_prefix.imgmesh-XXXXXXext; errors name `target`, the
// file the user asked for.
static std::string make_temp(const std::string& dir_prefix, const std::string& ext, const std::string& target) {
  std::string templ = dir_prefix + ".imgmesh-XXXXXX" + ext;
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  int fd = mkstemps(buf.data(), static_cast<int>(ext.size()));
  if (fd < 0) {
    const std::string why = std::strerror(errno);
    if (target == "-") throw Error("cannot create a temporary file in " + templ.substr(0, templ.rfind('/')) + ": " + why, target);
    throw Error("cannot create a file in its folder: " + why, target);
  }
  // mkstemp makes the file 0600; the output gets what open() would give it.
  const mode_t mask = umask(0);
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  close(fd);
  return std::string(buf.data());
}

namespace {

OutputGroup* current_group = nullptr;

// The last step of a commit: the finished temporary file becomes the target.
void move_into_place(const std::string& tmp, const std::string& target) {
  if (target == "-") {
    std::ifstream in(tmp, std::ios::binary);
    if (!in) throw Error("output was not written", target);
    std::cout << in.rdbuf();
    std::cout.flush();
    if (!std::cout) throw Error("write to standard output failed", target);
    std::remove(tmp.c_str());
  } else if (std::rename(tmp.c_str(), target.c_str()) != 0) {
    throw Error(std::string("cannot move output into place: ") + std::strerror(errno), target);
  }
}

} // namespace

OutputGroup::OutputGroup() : outer_(current_group) { current_group = this; }

OutputGroup::~OutputGroup() {
  for (const Finished& f : finished_) std::remove(f.tmp.c_str());
  current_group = outer_;
}

// Files first, then standard output (which cannot be taken back). A target
// that is a folder fails before anything moves; a target that exists is
// kept under a hard link until the whole set is in place. A failure moves
// every placed file back to its temporary name (removed with the group) and
// the earlier contents back, so the set lands whole or not at all.
void OutputGroup::commit() {
  for (const Finished& f : finished_) {
    struct stat st;
    if (f.target != "-" && ::stat(f.target.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
      throw Error("cannot write: it is a folder", f.target);
  }
  std::vector<std::string> backup(finished_.size());
  std::vector<bool> placed(finished_.size(), false);
  auto forget_backups = [&] {
    for (const std::string& b : backup)
      if (!b.empty()) std::remove(b.c_str());
  };
  try {
    for (std::size_t i = 0; i < finished_.size(); ++i) {
      const Finished& f = finished_[i];
      if (f.target == "-") continue;
      if (::access(f.target.c_str(), F_OK) == 0) {
        std::string b = make_temp(f.target, ".bak", f.target);
        std::remove(b.c_str());
        if (::link(f.target.c_str(), b.c_str()) != 0)
          throw Error(std::string("cannot keep the earlier file: ") + std::strerror(errno), f.target);
        backup[i] = b;
      }
      move_into_place(f.tmp, f.target);
      placed[i] = true;
    }
    for (const Finished& f : finished_)
      if (f.target == "-") move_into_place(f.tmp, f.target);
  } catch (...) {
    for (std::size_t i = finished_.size(); i-- > 0;) {
      const Finished& f = finished_[i];
      if (!placed[i]) continue;
      std::rename(f.target.c_str(), f.tmp.c_str());
      if (!backup[i].empty() && std::rename(backup[i].c_str(), f.target.c_str()) == 0) backup[i].clear();
    }
    forget_backups();
    throw;
  }
  forget_backups();
  finished_.clear();
}

StdinSpool::StdinSpool() {
  const char* tmpdir = std::getenv("TMPDIR");
  tmp_ = make_temp(std::string((tmpdir && *tmpdir) ? tmpdir : "/tmp") + "/stdin", "", "-");
  std::ofstream out(tmp_, std::ios::binary);
  std::vector<char> buf(std::size_t(1) << 20);
  std::size_t total = 0;
  while (std::cin.read(buf.data(), std::streamsize(buf.size())) || std::cin.gcount() > 0) {
    out.write(buf.data(), std::cin.gcount());
    total += std::size_t(std::cin.gcount());
  }
  out.close();
  if (!out) {
    std::remove(tmp_.c_str());
    throw Error("cannot spool standard input to " + tmp_, "-");
  }
  if (total == 0) {
    std::remove(tmp_.c_str());
    throw Error("standard input is empty", "-");
  }
}

StdinSpool::~StdinSpool() { std::remove(tmp_.c_str()); }

AtomicOutput::AtomicOutput(std::string target, bool binary, const std::string& stdout_extension)
    : target_(std::move(target)) {
  if (target_.empty()) throw Error("empty output path");
  if (target_ == "-") {
    if (binary && isatty(STDOUT_FILENO))
      throw UsageError(kBinaryOnTerminal, "-");
    const char* tmpdir = std::getenv("TMPDIR");
    std::string dir = (tmpdir && *tmpdir) ? tmpdir : "/tmp";
    tmp_ = make_temp(dir + "/stdout", stdout_extension, target_);
  } else {
    auto slash = target_.find_last_of('/');
    std::string dir = slash == std::string::npos ? "" : target_.substr(0, slash + 1);
    std::string base = slash == std::string::npos ? target_ : target_.substr(slash + 1);
    if (base.empty()) throw Error("output path names a directory", target_);
    check_output_folder(target_);
    tmp_ = make_temp(dir + base, extension_of(target_), target_);
  }
}

AtomicOutput::~AtomicOutput() {
  if (out_.is_open()) out_.close();
  if (!committed_) std::remove(tmp_.c_str());
}

std::ofstream& AtomicOutput::stream() {
  if (!out_.is_open()) {
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw Error("cannot write", target_);
    out_.precision(17);
  }
  return out_;
}

void AtomicOutput::commit() {
  if (out_.is_open()) {
    out_.flush();
    if (!out_) throw Error("write failed (disk full?)", target_);
    out_.close();
  }
  if (current_group) current_group->finished_.push_back({tmp_, target_});
  else move_into_place(tmp_, target_);
  committed_ = true;
}

std::string read_all(const std::string& path) {
  if (path == "-") {
    std::ostringstream ss;
    ss << std::cin.rdbuf();
    return ss.str();
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(std::string("cannot open: ") + std::strerror(errno), path);
  // A regular file in one read into a string of its size (a stringstream
  // copies the text several times as it grows); then whatever a pipe or a
  // growing file still has.
  std::string text;
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
    text.resize(std::size_t(st.st_size));
    in.read(text.data(), std::streamsize(text.size()));
    text.resize(std::size_t(in.gcount()));
    in.clear(in.rdstate() & std::ios::badbit);
  }
  std::ostringstream rest;
  rest << in.rdbuf();
  if (in.bad()) throw Error("read failed", path);
  text += rest.str();
  return text;
}

} // namespace imgmesh
