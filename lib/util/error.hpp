// Errors the library reports to the tools. The library never prints and never
// exits: it throws, and the tool turns the exception into one line on stderr
// ("tool: path: what is wrong") and an exit status (doc/design.md "Code rules").
#pragma once
#include <stdexcept>
#include <string>

namespace imgmesh {

// Bad input or a runtime failure: exit status 1.
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& what, std::string path = {})
      : std::runtime_error(what), path_(std::move(path)) {}
  // The file the error is about, or empty.
  const std::string& path() const { return path_; }
  // "path: what" or "what".
  std::string message() const;

private:
  std::string path_;
};

// Wrong use of the command line that CLI11 cannot see: exit status 2.
class UsageError : public Error {
public:
  using Error::Error;
};

// Runs f(); an Error from it that names no file is thrown again naming
// `path` (the input the failing computation worked on). Usage errors pass as
// they are.
template <class F> auto naming_input(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    if (!e.path().empty()) throw;
    throw Error(e.what(), path);
  }
}

} // namespace imgmesh
