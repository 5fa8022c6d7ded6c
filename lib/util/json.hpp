// A small ordered JSON value for --stats reports: objects keep insertion
// order so reports read in the order the tool fills them.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

class Json {
public:
  enum class Kind { Null, Bool, Number, Integer, String, Array, Object };

  Json() = default;
  Json(bool b) : kind_(Kind::Bool), b_(b) {}
  Json(int v) : kind_(Kind::Integer), i_(v) {}
  Json(long v) : kind_(Kind::Integer), i_(v) {}
  Json(long long v) : kind_(Kind::Integer), i_(v) {}
  Json(unsigned v) : kind_(Kind::Integer), i_(static_cast<long long>(v)) {}
  Json(unsigned long v) : kind_(Kind::Integer), i_(static_cast<long long>(v)) {}
  Json(unsigned long long v) : kind_(Kind::Integer), i_(static_cast<long long>(v)) {}
  Json(double v) : kind_(Kind::Number), d_(v) {}
  Json(const char* s) : kind_(Kind::String), s_(s) {}
  Json(std::string s) : kind_(Kind::String), s_(std::move(s)) {}
  template <class T> Json(const std::vector<T>& v) : kind_(Kind::Array) {
    for (const auto& x : v) items_.emplace_back(x);
  }

  static Json object() { Json j; j.kind_ = Kind::Object; return j; }
  static Json array() { Json j; j.kind_ = Kind::Array; return j; }

  // Object access: inserts (keeping order) when the key is new.
  Json& operator[](const std::string& key);
  // Array append.
  void push_back(Json v);

  Kind kind() const { return kind_; }
  bool contains(const std::string& key) const;
  const Json& at(const std::string& key) const;
  const std::vector<Json>& items() const { return items_; }
  const std::vector<std::string>& keys() const { return keys_; }  // object keys, parallel to items()
  double number() const { return kind_ == Kind::Integer ? double(i_) : d_; }
  long long integer() const { return kind_ == Kind::Integer ? i_ : static_cast<long long>(d_); }
  const std::string& string() const { return s_; }
  bool boolean() const { return b_; }

  // Compact when indent < 0, else pretty-printed.
  std::string dump(int indent = 2) const;
  // Parses a JSON text (for tests and tools that read reports). Throws Error.
  static Json parse(const std::string& text);

private:
  void dump_to(std::string& out, int indent, int depth) const;
  Kind kind_ = Kind::Null;
  bool b_ = false;
  long long i_ = 0;
  double d_ = 0;
  std::string s_;
  std::vector<Json> items_;                 // array items or object values
  std::vector<std::string> keys_;           // object keys, parallel to items_
};

} // namespace imgmesh
