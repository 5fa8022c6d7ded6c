// 3D Slicer's segmentation file (.seg.nrrd): a NRRD label map whose
// key/value fields describe its segments (Slicer's developer guide,
// "Segmentation labelmap file format"): SegmentN_Name, SegmentN_LabelValue
// (the segment's value in its layer) and SegmentN_Layer for N = 0, 1, ...,
// and Segmentation_* fields for the whole. Segments that overlap lie in
// separate layers, a first "list" axis of the file (read by ITK as pixel
// components); files written before Slicer 4.11 have one layer a segment,
// holding 1, and no LabelValue or Layer field. Plain C++ on the fields as
// strings: io.cpp hands them over from ITK's dictionary.
#pragma once
#include <map>
#include <string>

namespace imgmesh {

// A label's name where the file gives one.
using LabelNames = std::map<long long, std::string>;

// The names of a segmentation's labels, from its fields, for a file of
// `layers` layers; empty when no field is Slicer's. Throws Error (naming
// no file) on what cannot be read as one label map: several layers
// (overlapping segments), a source representation other than a binary
// labelmap, a segment in a layer the file lacks, a label value that is
// not an integer, two segments of one layer with one label value.
LabelNames slicer_label_names(const std::map<std::string, std::string>& fields, unsigned layers);

} // namespace imgmesh
