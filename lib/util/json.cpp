#include "util/json.hpp"

#include "util/error.hpp"

#include <cmath>
#include <cstdio>
#include <cctype>
#include <cstdlib>

namespace imgmesh {

Json& Json::operator[](const std::string& key) {
  if (kind_ == Kind::Null) kind_ = Kind::Object;
  if (kind_ != Kind::Object) throw Error("JSON value is not an object");
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return items_[i];
  keys_.push_back(key);
  items_.emplace_back();
  return items_.back();
}

void Json::push_back(Json v) {
  if (kind_ == Kind::Null) kind_ = Kind::Array;
  if (kind_ != Kind::Array) throw Error("JSON value is not an array");
  items_.push_back(std::move(v));
}

bool Json::contains(const std::string& key) const {
  for (const auto& k : keys_)
    if (k == key) return true;
  return false;
}

const Json& Json::at(const std::string& key) const {
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return items_[i];
  throw Error("JSON object has no key '" + key + "'");
}

static void escape(std::string& out, const std::string& s) {
  out += '"';
  for (unsigned char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += char(c);
        }
    }
  }
  out += '"';
}

void Json::dump_to(std::string& out, int indent, int depth) const {
  auto newline = [&](int d) {
    if (indent < 0) return;
    out += '\n';
    out.append(std::size_t(indent * d), ' ');
  };
  switch (kind_) {
    case Kind::Null: out += "null"; break;
    case Kind::Bool: out += b_ ? "true" : "false"; break;
    case Kind::Integer: out += std::to_string(i_); break;
    case Kind::Number: {
      if (!std::isfinite(d_)) { out += "null"; break; }  // JSON has no NaN/inf
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", d_);
      out += buf;
      break;
    }
    case Kind::String: escape(out, s_); break;
    case Kind::Array:
    case Kind::Object: {
      const bool obj = kind_ == Kind::Object;
      out += obj ? '{' : '[';
      for (std::size_t i = 0; i < items_.size(); ++i) {
        if (i) out += ',';
        newline(depth + 1);
        if (obj) {
          escape(out, keys_[i]);
          out += indent < 0 ? ":" : ": ";
        }
        items_[i].dump_to(out, indent, depth + 1);
      }
      if (!items_.empty()) newline(depth);
      out += obj ? '}' : ']';
    }
  }
}

std::string Json::dump(int indent) const {
  std::string out;
  dump_to(out, indent, 0);
  return out;
}

namespace {
struct Parser {
  const std::string& t;
  std::size_t p = 0;
  [[noreturn]] void fail(const char* what) {
    throw Error(std::string("invalid JSON at offset ") + std::to_string(p) + ": " + what);
  }
  void ws() { while (p < t.size() && std::isspace((unsigned char)t[p])) ++p; }
  bool eat(char c) { ws(); if (p < t.size() && t[p] == c) { ++p; return true; } return false; }
  std::string str() {
    if (!eat('"')) fail("expected a string");
    std::string s;
    while (p < t.size() && t[p] != '"') {
      char c = t[p++];
      if (c == '\\') {
        if (p >= t.size()) fail("bad escape");
        char e = t[p++];
        switch (e) {
          case 'n': s += '\n'; break;
          case 't': s += '\t'; break;
          case 'r': s += '\r'; break;
          case 'b': s += '\b'; break;
          case 'f': s += '\f'; break;
          case 'u': {
            if (p + 4 > t.size()) fail("bad \\u escape");
            unsigned v = std::stoul(t.substr(p, 4), nullptr, 16);
            p += 4;
            if (v < 0x80) s += char(v);
            else if (v < 0x800) { s += char(0xC0 | (v >> 6)); s += char(0x80 | (v & 0x3F)); }
            else { s += char(0xE0 | (v >> 12)); s += char(0x80 | ((v >> 6) & 0x3F)); s += char(0x80 | (v & 0x3F)); }
            break;
          }
          default: s += e;
        }
      } else {
        s += c;
      }
    }
    if (p >= t.size()) fail("unterminated string");
    ++p;
    return s;
  }
  Json value() {
    ws();
    if (p >= t.size()) fail("unexpected end");
    char c = t[p];
    if (c == '{') {
      ++p;
      Json o = Json::object();
      if (eat('}')) return o;
      do {
        std::string k = str();
        if (!eat(':')) fail("expected ':'");
        o[k] = value();
      } while (eat(','));
      if (!eat('}')) fail("expected '}'");
      return o;
    }
    if (c == '[') {
      ++p;
      Json a = Json::array();
      if (eat(']')) return a;
      do a.push_back(value()); while (eat(','));
      if (!eat(']')) fail("expected ']'");
      return a;
    }
    if (c == '"') return Json(str());
    if (t.compare(p, 4, "true") == 0) { p += 4; return Json(true); }
    if (t.compare(p, 5, "false") == 0) { p += 5; return Json(false); }
    if (t.compare(p, 4, "null") == 0) { p += 4; return Json(); }
    const char* b = t.c_str() + p;
    char* e = nullptr;
    double d = std::strtod(b, &e);
    if (e == b) fail("unexpected character");
    std::string tok(b, static_cast<const char*>(e));
    p += std::size_t(e - b);
    if (tok.find_first_of(".eE") == std::string::npos) return Json(std::stoll(tok));
    return Json(d);
  }
};
} // namespace

Json Json::parse(const std::string& text) {
  Parser ps{text};
  Json v = ps.value();
  ps.ws();
  if (ps.p != text.size()) ps.fail("trailing characters");
  return v;
}

} // namespace imgmesh
