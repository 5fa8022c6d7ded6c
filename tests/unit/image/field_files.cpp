// The writers of field_files.hpp: each header as its format's documentation
// spells it (MetaIO's fields, teem's NRRD0004 fields, the NIfTI-1 header's
// byte offsets), the voxels and the compressed streams through zlib.
#include "field_files.hpp"

#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace imgmesh::test {

const std::array<VoxelType, 6> kIntegerTypes{{
    {"unsigned_char", 1, false, "MET_UCHAR", "uint8", 2},
    {"char", 1, true, "MET_CHAR", "int8", 256},
    {"unsigned_short", 2, false, "MET_USHORT", "uint16", 512},
    {"short", 2, true, "MET_SHORT", "int16", 4},
    {"unsigned_int", 4, false, "MET_UINT", "uint32", 768},
    {"int", 4, true, "MET_INT", "int32", 8},
}};

Volume volume_of(const VoxelType& type) {
  Volume v;
  v.type = type;
  const int bits = 8 * type.bytes;
  const double lo = type.is_signed ? -std::ldexp(1.0, bits - 1) : 0.0;
  const double hi = type.bytes == 4 ? 2147483647.0 : (type.is_signed ? -lo - 1 : std::ldexp(1.0, bits) - 1);
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> u(lo, hi);
  v.values.resize(v.size[0] * v.size[1] * v.size[2]);
  for (long long& x : v.values) x = (long long)std::floor(u(rng));
  v.values[0] = (long long)lo;  // the type's extremes
  v.values[1] = (long long)hi;
  return v;
}

std::array<double, 9> oblique_rotation() {
  // Rz(30 degrees) * Rx(20 degrees).
  const double a = M_PI / 6, b = M_PI / 9;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
  return {ca, -sa * cb, sa * sb, sa, ca * cb, -ca * sb, 0, sb, cb};
}

std::array<double, 9> permuted_axes() {
  // Axis 0 runs along +z, axis 1 along -x, axis 2 along +y.
  return {0, -1, 0, 0, 0, 1, 1, 0, 0};
}

std::string voxel_bytes(const Volume& v, bool big_endian) {
  std::string out;
  const int n = v.type.bytes;
  for (long long x : v.values) {
    const auto u = static_cast<unsigned long long>(x);
    for (int b = 0; b < n; ++b) out.push_back(char((u >> (8 * (big_endian ? n - 1 - b : b))) & 0xff));
  }
  return out;
}

std::string deflate_bytes(const std::string& raw, bool gzip) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, gzip ? 31 : 15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("deflate");
  std::string out(deflateBound(&z, uLong(raw.size())) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = uInt(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(&out[0]);
  z.avail_out = uInt(out.size());
  if (deflate(&z, Z_FINISH) != Z_STREAM_END) throw std::runtime_error("deflate");
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

namespace {
std::string folder_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

std::string numbers(std::initializer_list<double> xs, const char* sep = " ") {
  std::ostringstream s;
  s.precision(17);
  bool first = true;
  for (double x : xs) {
    s << (first ? "" : sep) << x;
    first = false;
  }
  return s.str();
}
} // namespace

// ITK's MetaImageIO writes TransformMatrix with the direction of axis i as
// its i-th triple; VTK's vtkMetaImageWriter names the byte order
// ElementByteOrderMSB and adds ElementNumberOfChannels.
void write_metaimage(const std::string& header, const Volume& v, const MetaOptions& o) {
  const auto& d = v.direction;
  const std::string raw = voxel_bytes(v, o.big_endian);
  std::ostringstream h;
  h << "ObjectType = Image\nNDims = 3\nBinaryData = True\n"
    << (o.vtk_style ? "ElementByteOrderMSB = " : "BinaryDataByteOrderMSB = ") << (o.big_endian ? "True" : "False") << '\n'
    << "CompressedData = " << (o.compressed ? "True" : "False") << '\n';
  const bool list = o.data == "LIST" || o.data.find('%') != std::string::npos;
  std::string data = raw;
  if (o.compressed && !list) data = deflate_bytes(raw, false);
  if (o.compressed && !list && o.declare_size) h << "CompressedDataSize = " << data.size() << '\n';
  h << "TransformMatrix = " << numbers({d[0], d[3], d[6], d[1], d[4], d[7], d[2], d[5], d[8]}) << '\n'
    << "Offset = " << numbers({v.origin[0], v.origin[1], v.origin[2]}) << '\n'
    << "CenterOfRotation = 0 0 0\nAnatomicalOrientation = RAI\n"
    << "ElementSpacing = " << numbers({v.spacing[0], v.spacing[1], v.spacing[2]}) << '\n'
    << "DimSize = " << v.size[0] << ' ' << v.size[1] << ' ' << v.size[2] << '\n';
  if (o.vtk_style) h << "ElementNumberOfChannels = 1\n";
  if (o.header_bytes > 0) {
    h << "HeaderSize = " << o.header_bytes << '\n';
    data = std::string(std::size_t(o.header_bytes), '\x7f') + data;
  }
  h << "ElementType = " << v.type.meta << '\n';
  if (!list) {
    h << "ElementDataFile = " << o.data << '\n';
    if (o.data == "LOCAL") {
      write_bytes(header, h.str() + data);
    } else {
      write_bytes(header, h.str());
      write_bytes(folder_of(header) + o.data, data);
    }
    return;
  }
  // One file a slice (the last axis), named in the header or by the pattern.
  const std::size_t slice = raw.size() / v.size[2];
  std::string names;
  for (std::size_t k = 0; k < v.size[2]; ++k) {
    char name[256];
    if (o.data == "LIST") std::snprintf(name, sizeof name, "slice%zu.raw", k);
    else std::snprintf(name, sizeof name, o.data.c_str(), int(k + 1));
    names += std::string(name) + '\n';
    const std::string bytes = raw.substr(k * slice, slice);
    write_bytes(folder_of(header) + name, o.compressed ? deflate_bytes(bytes, false) : bytes);
  }
  if (o.data == "LIST") h << "ElementDataFile = LIST\n" << names;
  else h << "ElementDataFile = " << o.data << " 1 " << v.size[2] << " 1\n";
  write_bytes(header, h.str());
}

// teem's fields; "space directions" holds each axis's step (direction times
// spacing), in RAS when asked (x and y negated from LPS).
void write_nrrd(const std::string& header, const Volume& v, const NrrdOptions& o) {
  const double f = o.ras ? -1 : 1;
  const auto& d = v.direction;
  const auto& s = v.spacing;
  std::ostringstream h;
  h.precision(17);
  h << "NRRD0004\n# Complete NRRD file format specification at:\n# http://teem.sourceforge.net/nrrd/format.html\n"
    << "type: " << v.type.nrrd << '\n';
  if (o.list_axis > 0)
    h << "dimension: 4\nspace: " << (o.ras ? "right-anterior-superior" : "left-posterior-superior") << '\n'
      << "sizes: " << o.list_axis << ' ';
  else
    h << "dimension: 3\nspace: " << (o.ras ? "right-anterior-superior" : "left-posterior-superior") << '\n'
      << "sizes: ";
  h << v.size[0] << ' ' << v.size[1] << ' ' << v.size[2] << "\nspace directions: " << (o.list_axis > 0 ? "none " : "");
  for (int c = 0; c < 3; ++c)
    h << '(' << numbers({f * d[c] * s[c], f * d[3 + c] * s[c], d[6 + c] * s[c]}, ",") << ')' << (c < 2 ? " " : "\n");
  h << "kinds: " << (o.list_axis > 0 ? "list " : "") << "domain domain domain\n";
  if (v.type.bytes > 1) h << "endian: " << (o.big_endian ? "big" : "little") << '\n';
  h << "encoding: " << (o.gzip ? "gzip" : "raw") << '\n'
    << "space origin: (" << numbers({f * v.origin[0], f * v.origin[1], v.origin[2]}, ",") << ")\n";
  for (const std::string& kv : o.fields) h << kv << '\n';
  std::string raw = voxel_bytes(v, o.big_endian);
  if (o.list_axis > 0) {  // every layer holds the volume's value at each voxel
    std::string layered;
    const std::size_t b = std::size_t(v.type.bytes);
    for (std::size_t i = 0; i < raw.size(); i += b)
      for (int l = 0; l < o.list_axis; ++l) layered += raw.substr(i, b);
    raw = layered;
  }
  const std::string data = o.gzip ? deflate_bytes(raw, true) : raw;
  if (o.data_file.empty()) {
    write_bytes(header, h.str() + "\n" + data);
  } else {
    write_bytes(header, h.str() + "data file: " + o.data_file + "\n");
    write_bytes(folder_of(header) + o.data_file, data);
  }
}

namespace {
// A NIfTI-1 header in either byte order.
struct NiftiHeader {
  std::string b = std::string(348, '\0');
  bool big = false;
  void put(int at, const void* p, int n) {
    unsigned char bytes[8];
    std::memcpy(bytes, p, std::size_t(n));
    for (int i = 0; i < n; ++i) b[std::size_t(at + i)] = char(bytes[big ? n - 1 - i : i]);  // the machine is little-endian
  }
  void i32(int at, std::int32_t v) { put(at, &v, 4); }
  void i16(int at, std::int16_t v) { put(at, &v, 2); }
  void f32(int at, double v) {
    const float f = float(v);
    put(at, &f, 4);
  }
};

// niftilib's nifti_mat44_to_quatern for an orthonormal R (row-major):
// (b, c, d, qfac), qfac -1 when R is improper (its third column negated).
std::array<double, 4> quaternion_of(std::array<double, 9> r) {
  const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                     r[2] * (r[3] * r[7] - r[4] * r[6]);
  const double qfac = det < 0 ? -1 : 1;
  for (int i = 2; i < 9; i += 3) r[std::size_t(i)] *= qfac;
  double a = r[0] + r[4] + r[8] + 1, b, c, d;
  if (a > 0.5) {
    a = 0.5 * std::sqrt(a);
    b = 0.25 * (r[7] - r[5]) / a;
    c = 0.25 * (r[2] - r[6]) / a;
    d = 0.25 * (r[3] - r[1]) / a;
  } else {
    const double xd = 1 + r[0] - (r[4] + r[8]), yd = 1 + r[4] - (r[0] + r[8]), zd = 1 + r[8] - (r[0] + r[4]);
    if (xd > 1) {
      b = 0.5 * std::sqrt(xd);
      c = 0.25 * (r[1] + r[3]) / b;
      d = 0.25 * (r[2] + r[6]) / b;
      a = 0.25 * (r[7] - r[5]) / b;
    } else if (yd > 1) {
      c = 0.5 * std::sqrt(yd);
      b = 0.25 * (r[1] + r[3]) / c;
      d = 0.25 * (r[5] + r[7]) / c;
      a = 0.25 * (r[2] - r[6]) / c;
    } else {
      d = 0.5 * std::sqrt(zd);
      b = 0.25 * (r[2] + r[6]) / d;
      c = 0.25 * (r[5] + r[7]) / d;
      a = 0.25 * (r[3] - r[1]) / d;
    }
    if (a < 0) b = -b, c = -c, d = -d;
  }
  return {b, c, d, qfac};
}
} // namespace

// NIfTI's world is RAS: the affine is diag(-1, -1, 1) times ITK's LPS one.
void write_nifti(const std::string& path, const Volume& v, const NiftiOptions& o) {
  NiftiHeader h;
  h.big = o.big_endian;
  h.i32(0, 348);
  h.b[38] = 'r';
  const std::int16_t dims[8] = {std::int16_t(o.time_axis ? 4 : 3), std::int16_t(v.size[0]), std::int16_t(v.size[1]), std::int16_t(v.size[2]), 1, 1, 1, 1};
  for (int i = 0; i < 8; ++i) h.i16(40 + 2 * i, dims[i]);
  h.i16(70, std::int16_t(v.type.nifti));
  h.i16(72, std::int16_t(8 * v.type.bytes));
  std::array<double, 9> ras = v.direction;
  for (int i = 0; i < 6; ++i) ras[std::size_t(i)] = -ras[std::size_t(i)];
  const auto q = quaternion_of(ras);
  const double pixdim[8] = {o.qform ? q[3] : 1.0, v.spacing[0], v.spacing[1], v.spacing[2], 1, 1, 1, 1};
  for (int i = 0; i < 8; ++i) h.f32(76 + 4 * i, pixdim[i]);
  h.f32(108, 352);  // vox_offset
  h.f32(112, o.nibabel ? std::nan("") : 1.0);  // scl_slope
  if (o.nibabel) h.f32(116, std::nan(""));      // scl_inter
  h.b[123] = 2;     // xyzt_units: mm
  const double origin[3] = {-v.origin[0], -v.origin[1], v.origin[2]};
  if (o.qform) {
    h.i16(252, 1);  // NIFTI_XFORM_SCANNER_ANAT
    for (int i = 0; i < 3; ++i) h.f32(256 + 4 * i, q[std::size_t(i)]);
    for (int i = 0; i < 3; ++i) h.f32(268 + 4 * i, origin[i]);
  }
  if (o.sform) {
    h.i16(254, o.nibabel ? 2 : 1);  // NIFTI_XFORM_ALIGNED_ANAT, NIFTI_XFORM_SCANNER_ANAT
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) h.f32(280 + 16 * r + 4 * c, ras[std::size_t(3 * r + c)] * v.spacing[std::size_t(c)]);
      h.f32(280 + 16 * r + 12, origin[r]);
    }
  }
  std::memcpy(&h.b[344], "n+1", 4);
  const std::string file = h.b + std::string(4, '\0') + voxel_bytes(v, o.big_endian);
  write_bytes(path, o.gzip ? deflate_bytes(file, true) : file);
}

} // namespace imgmesh::test
