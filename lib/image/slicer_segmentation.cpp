#include "image/slicer_segmentation.hpp"
#include "util/error.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace imgmesh {
namespace {

struct Segment {
  std::string name;
  std::string label, layer;  // as the fields give them, "" when absent
};

// "Segment12_Name" -> (12, "Name"); false for other keys.
bool segment_key(const std::string& key, long& n, std::string& what) {
  if (key.compare(0, 7, "Segment") != 0) return false;
  std::size_t i = 7;
  while (i < key.size() && std::isdigit(static_cast<unsigned char>(key[i]))) ++i;
  if (i == 7 || i >= key.size() || key[i] != '_' || i - 7 > 6) return false;
  n = std::atol(key.substr(7, i - 7).c_str());
  what = key.substr(i + 1);
  return true;
}

std::string quoted(long n, const Segment& s) {
  return std::to_string(n) + (s.name.empty() ? "" : " ('" + s.name + "')");
}

// A whole number from a field, or `fallback` when the field is absent.
long long whole(const std::string& text, long long fallback, const std::string& what) {
  if (text.empty()) return fallback;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  while (end && std::isspace(static_cast<unsigned char>(*end))) ++end;
  if (!end || *end || v != std::floor(v) || std::abs(v) > 2147483647.0)
    throw Error("3D Slicer " + what + " is '" + text + "': an integer expected");
  return (long long)v;
}

} // namespace

LabelNames slicer_label_names(const std::map<std::string, std::string>& fields, unsigned layers) {
  std::map<long, Segment> segments;
  std::string representation;
  bool slicer = false;
  for (const auto& [key, value] : fields) {
    long n = 0;
    std::string what;
    if (segment_key(key, n, what)) {
      slicer = true;
      if (what == "Name") segments[n].name = value;
      else if (what == "LabelValue") segments[n].label = value;
      else if (what == "Layer") segments[n].layer = value;
    } else if (key.compare(0, 13, "Segmentation_") == 0) {
      slicer = true;
      if (key == "Segmentation_SourceRepresentation" || key == "Segmentation_MasterRepresentation")
        representation = value;
    }
  }
  if (!slicer) return {};
  if (!representation.empty() && representation != "Binary labelmap")
    throw Error("a 3D Slicer segmentation stored as '" + representation +
                "': only a binary labelmap is read as a label map");
  if (layers > 1)
    throw Error("a 3D Slicer segmentation of " + std::to_string(layers) +
                " layers (overlapping segments): only a single-layer segmentation is read as a label map "
                "(in Slicer, export the segments to a labelmap volume)");
  LabelNames names;
  std::map<long long, long> first;  // label -> the segment that named it
  for (const auto& [n, s] : segments) {
    // Before Slicer 4.11 a segment had its own layer and the value 1.
    const long long layer = whole(s.layer, n, "segment " + quoted(n, s) + "'s layer");
    const long long label = whole(s.label, 1, "segment " + quoted(n, s) + "'s label value");
    if (layer < 0 || layer >= (long long)layers)
      throw Error("3D Slicer segment " + quoted(n, s) + " is in layer " + std::to_string(layer) + ", the file has " +
                  std::to_string(layers));
    if (const auto it = first.find(label); it != first.end())
      throw Error("3D Slicer segments " + quoted(it->second, segments.at(it->second)) + " and " + quoted(n, s) +
                  " both have label value " + std::to_string(label));
    first[label] = n;
    if (!s.name.empty()) names[label] = s.name;
  }
  return names;
}

} // namespace imgmesh
