// ITK image I/O. Reading goes through itk::ImageIOBase on a raw buffer, so
// every component type and both 2D and 3D files share one path; writing goes
// through itk::Image + ImageFileWriter.
#include "image/io.hpp"
#include "image/file_checks.hpp"
#include "image/slicer_segmentation.hpp"
#include "image/voxel_stream.hpp"

#include "util/atomic_file.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <itkImage.h>
#include <itkImageFileWriter.h>
#include <itkImageIOBase.h>
#include <itkImageIOFactory.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIOFactory.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>
#include <itkPNGImageIOFactory.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <png.h>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <unistd.h>

namespace imgmesh {
namespace {

void register_factories() {
  static std::once_flag once;
  std::call_once(once, [] {
    itk::NrrdImageIOFactory::RegisterOneFactory();
    itk::MetaImageIOFactory::RegisterOneFactory();
    itk::NiftiImageIOFactory::RegisterOneFactory();
    itk::PNGImageIOFactory::RegisterOneFactory();
  });
}

// ITK's descriptions carry "ITK ERROR: Class(0x...): " and, for NRRD, a
// chain of "[nrrd] function:" frames: keep the innermost reason only.
std::string itk_message(const itk::ExceptionObject& e) {
  std::string d = e.GetDescription();
  for (char& c : d)
    if (c == '\n' || c == '\r') c = ' ';
  auto frame = d.rfind("[nrrd] ");
  if (frame != std::string::npos) {
    auto colon = d.find(": ", frame);
    d = colon == std::string::npos ? d.substr(frame + 7) : d.substr(colon + 2);
  } else if (d.rfind("ITK ERROR: ", 0) == 0) {
    auto colon = d.find("): ");
    if (colon != std::string::npos) d = d.substr(colon + 3);
  }
  while (!d.empty() && d.back() == ' ') d.pop_back();
  return d.empty() ? "cannot read the image" : "cannot read the image: " + d;
}

// ITK and MetaIO say some reasons on std::cerr only (MetaIO's "Cannot open
// data file", a short LOCAL block read as zeros after "data not read
// completely", itk::OutputWindow warnings), and niftilib on C's stderr
// ("** ERROR: nifti_convert_nhdr2nim: bad dim[0]"). The library never
// prints: while a CerrCapture lives both are kept, to become part of the
// Error (C's stderr goes to a temporary file, descriptor 2 restored after).
class CerrCapture {
public:
  CerrCapture() : old_(std::cerr.rdbuf(text_.rdbuf())) {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = file_ ? dup(2) : -1;
    if (saved_ < 0 || dup2(fileno(file_), 2) < 0) restore_fd();
  }
  ~CerrCapture() {
    restore_fd();
    std::cerr.rdbuf(old_);
  }
  CerrCapture(const CerrCapture&) = delete;
  CerrCapture& operator=(const CerrCapture&) = delete;
  // What was said, on one line.
  std::string text() const {
    std::string all = text_.str();
    if (file_) {
      std::fflush(stderr);
      std::rewind(file_);
      char buf[4096];
      for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, file_)) > 0 && all.size() < 65536;) all.append(buf, got);
      std::fseek(file_, 0, SEEK_END);  // the offset is descriptor 2's too
    }
    std::string t, word;
    std::istringstream in(all);
    while (in >> word) t += (t.empty() ? "" : " ") + word;
    return t;
  }
  // An Error for ITK's exception, with what was said (often the real reason).
  Error error(const itk::ExceptionObject& e, const std::string& path) const {
    const std::string said = text();
    return Error(itk_message(e) + (said.empty() ? "" : " (" + said + ")"), path);
  }
  // A read that ITK let pass though the data was short.
  void check_read(const std::string& path) const {
    const std::string said = text();
    if (said.find("not read completely") != std::string::npos)
      throw Error("cannot read the image: truncated data (" + said + ")", path);
  }

private:
  void restore_fd() {
    if (saved_ >= 0) {
      std::fflush(stderr);
      dup2(saved_, 2);
      close(saved_);
      saved_ = -1;
    }
    if (file_) std::fclose(file_);
    file_ = nullptr;
  }
  std::ostringstream text_;
  std::streambuf* old_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// The file ITK is given for a path. stdin is spooled to a temporary file
// whose extension comes from the content, since ITK reads only from paths
// and picks readers by name and content. niftilib reads the voxels of
// X.nii.gz from X.nii when that file exists beside it (nifti_findimgname
// tries .nii first), so such a file is given through a link of another
// name in a temporary folder.
class Spool {
public:
  explicit Spool(const std::string& path) : path_(path) {
    if (path == "-") {
      spool_stdin();
    } else if (extension_of(path) == ".nii.gz" && std::ifstream(path.substr(0, path.size() - 3))) {
      link_alone();
    }
  }
  ~Spool() {
    if (!tmp_.empty()) std::remove(tmp_.c_str());
    if (!dir_.empty()) rmdir(dir_.c_str());
  }
  Spool(const Spool&) = delete;
  Spool& operator=(const Spool&) = delete;
  const std::string& file() const { return tmp_.empty() ? path_ : tmp_; }

private:
  static std::string tmpdir() {
    const char* t = std::getenv("TMPDIR");
    return t && *t ? t : "/tmp";
  }
  void spool_stdin() {
    std::string data((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    if (data.empty()) throw Error("standard input is empty", "-");
    std::string ext;
    auto starts = [&](const char* m) { return data.compare(0, std::strlen(m), m) == 0; };
    if (starts("NRRD")) ext = ".nrrd";
    else if (starts("\x89PNG")) ext = ".png";
    else if (data.size() >= 2 && (unsigned char)data[0] == 0x1f && (unsigned char)data[1] == 0x8b) ext = ".nii.gz";
    else if (starts("ObjectType") || starts("NDims")) ext = ".mha";
    else if (data.size() > 348 && data.compare(344, 3, "n+1") == 0) ext = ".nii";
    else throw Error("cannot tell the image format of standard input (NRRD, MetaImage, NIfTI or PNG expected)", "-");
    std::string templ = tmpdir() + "/stdin-XXXXXX" + ext;
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    int fd = mkstemps(buf.data(), int(ext.size()));
    if (fd < 0) throw Error("cannot spool standard input", "-");
    close(fd);
    tmp_ = buf.data();
    std::ofstream out(tmp_, std::ios::binary);
    out.write(data.data(), std::streamsize(data.size()));
    if (!out) throw Error("cannot spool standard input", "-");
  }
  void link_alone() {
    std::string templ = tmpdir() + "/nii-XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (!mkdtemp(buf.data())) throw Error("cannot make a temporary folder to read the image alone", path_);
    dir_ = buf.data();
    const std::string link = dir_ + "/image.nii.gz";
    std::error_code ec;
    const std::filesystem::path target = std::filesystem::absolute(path_, ec);
    if (ec || symlink(target.c_str(), link.c_str()) != 0) {
      rmdir(dir_.c_str());
      throw Error("cannot link the image alone into a temporary folder", path_);
    }
    tmp_ = link;
  }
  std::string path_, tmp_, dir_;
};

struct Opened {
  itk::ImageIOBase::Pointer io;
  ImageInfo info;
  LabelNames names;  // 3D Slicer's segment names
};

// The key/value fields of a file that are strings (NRRD's "key:=value").
std::map<std::string, std::string> string_fields(const itk::MetaDataDictionary& dict) {
  std::map<std::string, std::string> fields;
  for (const auto& key : dict.GetKeys()) {
    std::string value;
    if (itk::ExposeMetaData<std::string>(dict, key, value)) fields[key] = value;
  }
  return fields;
}

// MetaIO reads data it cannot read as zeros: what the header points to is
// checked first (metaimage_data_error), compressed data inflated once.
void check_metaimage_data(const std::string& path, const std::string& file, const Opened& o) {
  if (std::strcmp(o.io->GetNameOfClass(), "MetaImageIO") != 0) return;
  const std::string e = metaimage_data_error(file, std::uintmax_t(o.info.geometry.count()) * std::uintmax_t(o.info.components) *
                                                       o.io->GetComponentSize());
  if (!e.empty()) throw Error("cannot read the image: " + e, path);
}

// check_data: false when the caller reads the voxels itself (VoxelStream,
// which checks them as it reads) or calls check_metaimage_data.
Opened open_image_itk(const std::string& path, const std::string& file, bool check_data) {
  register_factories();
  {
    std::ifstream probe(file, std::ios::binary);
    if (!probe) throw Error(std::string("cannot open: ") + std::strerror(errno), path);
  }
  {
    std::ifstream probe(file, std::ios::binary);
    char sig[8] = {};
    probe.read(sig, 8);
    if (probe.gcount() == 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(sig), 0, 8) == 0) {
      const std::string e = png_header_error(file);
      if (!e.empty()) throw Error("cannot read the image: " + e, path);
    }
  }
  Opened o;
  const CerrCapture said;
  o.io = itk::ImageIOFactory::CreateImageIO(file.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  if (!o.io) throw Error("not an image ITK can read (NRRD, MetaImage, NIfTI or PNG expected)", path);
  if (std::strcmp(o.io->GetNameOfClass(), "MetaImageIO") == 0) {
    const std::string e = metaimage_header_error(file);
    if (!e.empty()) throw Error("cannot read the image: " + e, path);
  }
  if (std::strcmp(o.io->GetNameOfClass(), "NiftiImageIO") == 0) {
    const std::string e = nifti_header_error(file);
    if (!e.empty()) throw Error("cannot read the image: " + e, path);
  }
  try {
    o.io->SetFileName(file);
    o.io->ReadImageInformation();
  } catch (const itk::ExceptionObject& e) {
    throw said.error(e, path);
  }
  // A 3D Slicer segmentation's layers are pixel components: checked (and
  // its names kept) before components are taken for colours.
  o.names = naming_input(path, [&] {
    return slicer_label_names(string_fields(o.io->GetMetaDataDictionary()), o.io->GetNumberOfComponents());
  });
  const unsigned n = o.io->GetNumberOfDimensions();
  // Trailing axes of size 1 do not count (a 3D file holding one slice is 2D
  // data, a "4D" file with one time point is 3D).
  unsigned dim = n;
  while (dim > 3 && o.io->GetDimensions(dim - 1) == 1) --dim;
  if (n < 2) throw Error("a 1D image: 2D or 3D expected", path);
  if (dim > 3) throw Error(std::to_string(dim) + "D image: 2D or 3D expected", path);
  const unsigned comps = o.io->GetNumberOfComponents();
  // RGB(A) is accepted for grey images saved as colour (checked per pixel).
  if (comps != 1 && comps != 3 && comps != 4)
    throw Error("pixels have " + std::to_string(comps) + " components (vector image): a scalar image is expected",
                path);
  ImageInfo& info = o.info;
  info.components = int(comps);
  info.component = itk::ImageIOBase::GetComponentTypeAsString(o.io->GetComponentType());
  const auto ct = o.io->GetComponentType();
  info.integer = !(ct == itk::IOComponentEnum::FLOAT || ct == itk::IOComponentEnum::DOUBLE ||
                   ct == itk::IOComponentEnum::LDOUBLE);
  Geometry& g = info.geometry;
  g.dimension = n == 2 ? 2 : 3;  // a 3D file of one slice stays 3D (size[2] == 1)
  for (unsigned i = 0; i < 3; ++i) {
    g.size[i] = i < std::min(n, 3u) ? o.io->GetDimensions(i) : 1;
    g.spacing[i] = i < std::min(n, 3u) ? o.io->GetSpacing(i) : 1.0;
    g.origin[i] = i < std::min(n, 3u) ? o.io->GetOrigin(i) : 0.0;
  }
  g.direction = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const unsigned m = std::min(n, 3u);
  for (unsigned c = 0; c < m; ++c) {
    auto col = o.io->GetDirection(c);
    for (unsigned r = 0; r < m && r < col.size(); ++r) g.direction[r * 3 + c] = col[r];
  }
  std::size_t count = 1;
  for (unsigned i = 0; i < n; ++i) {
    const std::size_t s = o.io->GetDimensions(i);
    if (s == 0) throw Error("image has an empty axis", path);
    if (count > (std::size_t(1) << 40) / s) throw Error("image too large", path);
    count *= s;
  }
  check_declared_size(path, file, std::uintmax_t(count) * comps * o.io->GetComponentSize());
  if (check_data) check_metaimage_data(path, file, o);
  for (int i = 0; i < 3; ++i)
    if (!(g.spacing[i] > 0) || !std::isfinite(g.spacing[i]))
      throw Error("spacing must be positive and finite", path);
  return o;
}

// ITK throws from its queries too (an unknown component type, ...): those
// come out as Error naming the file, like the reader's own.
Opened open_image(const std::string& path, const std::string& file, bool check_data = true) {
  try {
    return open_image_itk(path, file, check_data);
  } catch (const itk::ExceptionObject& e) {
    throw Error(itk_message(e), path);
  }
}

// Calls f(i, value) for every voxel i in order, value as double (exact for every
// integer type up to 2^53), straight from ITK's buffer: no per-voxel copy
// wider than the file's own type. Grey images stored as RGB(A) or palette
// PNG (R = G = B) read as their grey value; real colour is refused.
std::unique_ptr<char[]> read_raw(const std::string& path, Opened& o) {
  const unsigned n = o.io->GetNumberOfDimensions();
  itk::ImageIORegion region(n);
  for (unsigned i = 0; i < n; ++i) {
    region.SetIndex(i, 0);
    region.SetSize(i, o.io->GetDimensions(i));
  }
  o.io->SetIORegion(region);
  check_nifti_complete(path, o.io->GetFileName(), o.io->GetImageSizeInBytes());
  // Not zero-filled first: ITK writes every byte (a whole scan is read for
  // one small label).
  std::unique_ptr<char[]> raw(new char[o.io->GetImageSizeInBytes()]);
  {
    const CerrCapture said;
    try {
      o.io->Read(raw.get());
    } catch (const itk::ExceptionObject& e) {
      throw said.error(e, path);
    }
    said.check_read(path);
  }
  return raw;
}

// visit_values on the file's voxels read_raw gave (raw).
template <class F> void visit_raw(const std::string& path, const Opened& o, const char* raw, F&& f) {
  const std::size_t count = o.info.geometry.count();
  const std::size_t c = o.io->GetNumberOfComponents();
  auto convert = [&](auto tag) {
    using T = decltype(tag);
    const T* p = reinterpret_cast<const T*>(raw);
    for (std::size_t i = 0; i < count; ++i) {
      const T* px = p + i * c;
      if (c > 1 && (px[0] != px[1] || px[0] != px[2]))
        throw Error("a colour image (R, G, B differ): a grey or label image is expected", path);
      const double v = double(px[0]);
      // A label or intensity image holds finite values; thresholding an
      // infinity would hide a broken export.
      if (!std::isfinite(v))
        throw Error(std::isnan(v) ? "image contains NaN values" : "image contains infinite values", path);
      f(i, v);
    }
  };
  switch (o.io->GetComponentType()) {
    case itk::IOComponentEnum::UCHAR: convert(std::uint8_t()); break;
    case itk::IOComponentEnum::CHAR: convert(std::int8_t()); break;
    case itk::IOComponentEnum::USHORT: convert(std::uint16_t()); break;
    case itk::IOComponentEnum::SHORT: convert(std::int16_t()); break;
    case itk::IOComponentEnum::UINT: convert(std::uint32_t()); break;
    case itk::IOComponentEnum::INT: convert(std::int32_t()); break;
    case itk::IOComponentEnum::ULONG: convert((unsigned long)0); break;
    case itk::IOComponentEnum::LONG: convert(long(0)); break;
    case itk::IOComponentEnum::ULONGLONG: convert((unsigned long long)0); break;
    case itk::IOComponentEnum::LONGLONG: convert((long long)0); break;
    case itk::IOComponentEnum::FLOAT: convert(float()); break;
    case itk::IOComponentEnum::DOUBLE: convert(double()); break;
    default: throw Error("unsupported pixel type " + o.info.component, path);
  }
}

template <class F> void visit_values(const std::string& path, Opened& o, F&& f) {
  const std::unique_ptr<char[]> raw = read_raw(path, o);
  visit_raw(path, o, raw.get(), f);
}

// Writes img's voxels as pixel type T (converted straight into ITK's buffer).
template <unsigned D, class T, class Src>
void write_itk(const std::string& file, const Image<Src>& img, const std::map<std::string, std::string>& fields) {
  using ItkImage = itk::Image<T, D>;
  auto out = ItkImage::New();
  typename ItkImage::RegionType region;
  typename ItkImage::SpacingType spacing;
  typename ItkImage::PointType origin;
  typename ItkImage::DirectionType dir;
  for (unsigned i = 0; i < D; ++i) {
    region.SetSize(i, img.size[i]);
    region.SetIndex(i, 0);
    spacing[i] = img.spacing[i];
    origin[i] = img.origin[i];
    for (unsigned j = 0; j < D; ++j) dir(i, j) = img.direction[i * 3 + j];
  }
  out->SetRegions(region);
  out->SetSpacing(spacing);
  out->SetOrigin(origin);
  out->SetDirection(dir);
  out->Allocate();
  std::transform(img.data.begin(), img.data.end(), out->GetBufferPointer(), [](Src v) { return T(v); });
  auto& dict = out->GetMetaDataDictionary();
  for (const auto& [k, v] : fields) itk::EncapsulateMetaData<std::string>(dict, k, v);
  auto writer = itk::ImageFileWriter<ItkImage>::New();
  writer->SetFileName(file);
  writer->SetInput(out);
  writer->SetUseCompression(true);
  writer->Update();
}

template <class T, class Src = T>
void write_any(const std::string& path, const Image<Src>& img, const std::map<std::string, std::string>& fields) {
  register_factories();
  if (img.data.size() != img.count()) throw Error("internal: image data does not match its size", path);
  const std::string ext = path == "-" ? ".nrrd" : extension_of(path);
  static const std::set<std::string> known{".nrrd", ".nhdr", ".mha", ".mhd", ".nii", ".nii.gz", ".png"};
  if (!known.count(ext))
    throw UsageError("unknown image extension '" + ext + "' (use .nrrd, .nhdr, .mha, .mhd, .nii, .nii.gz or .png)", path);
  if (ext == ".png" && (img.dimension != 2 || !std::is_same<T, std::uint8_t>::value))
    throw UsageError("PNG holds only 2D 8-bit images", path);
  if (ext == ".nhdr" || ext == ".mhd")
    throw UsageError("detached-header formats write two files; use .nrrd or .mha", path);
  AtomicOutput out(path, true, ".nrrd");
  const CerrCapture said;
  try {
    if (img.dimension == 2) write_itk<2, T>(out.path(), img, fields);
    else write_itk<3, T>(out.path(), img, fields);
  } catch (const itk::ExceptionObject& e) {
    throw said.error(e, path);
  }
  out.commit();
}

// "labels present: 0-3 7 12" (ranges of consecutive values, the first 20).
template <class Values> std::string labels_present(const Values& values) {
  std::ostringstream out;
  out << "labels present:";
  int shown = 0;
  for (auto it = values.begin(); it != values.end(); ++shown) {
    if (shown == 20) {
      out << " ...";
      break;
    }
    auto last = it;
    while (std::next(last) != values.end() && *std::next(last) == *last + 1) ++last;
    out << ' ' << (long long)*it;
    if (last != it) out << '-' << (long long)*last;
    it = std::next(last);
  }
  return out.str();
}

[[noreturn]] void absent_label(long long label, const std::string& labels, const std::string& path) {
  throw Error("label " + std::to_string(label) + " does not occur in the image (" + labels + ")", path);
}

} // namespace

ImageInfo read_image_info(const std::string& path) {
  Spool spool(path);
  return open_image(path, spool.file()).info;
}

namespace {
BinaryImage read_foreground_opened(const std::string& path, Opened& o, const Selection& sel,
                                   std::map<std::string, std::string>* fields) {
  if (!sel.labels.empty() && sel.has_threshold)
    throw UsageError("give either --label or --threshold, not both");
  if (!sel.labels.empty() && !o.info.integer)
    throw UsageError("--label needs an integer image, this one holds " + o.info.component +
                         " values (use --threshold)",
                     path);
  // Filled in voxel order (visit_values' order), not zero-filled first: a
  // whole scan is read for one small label.
  BinaryImage out;
  static_cast<Geometry&>(out) = o.info.geometry;
  out.data.reserve(out.count());
  std::size_t count = 0;
  auto put = [&](bool in) {
    out.data.push_back(in);
    count += in;
  };
  if (!sel.labels.empty()) {
    // Sorted, and a flag each: a voxel costs a comparison or two, not a
    // set lookup.
    std::vector<double> wanted(sel.labels.begin(), sel.labels.end());
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
    std::vector<char> seen(wanted.size(), 0);
    visit_values(path, o, [&](std::size_t, double v) {
      const auto it = v < wanted.front() || v > wanted.back() ? wanted.end() : std::lower_bound(wanted.begin(), wanted.end(), v);
      const bool in = it != wanted.end() && *it == v;
      if (in) seen[std::size_t(it - wanted.begin())] = 1;
      put(in);
    });
    for (long long l : sel.labels) {
      if (seen[std::size_t(std::lower_bound(wanted.begin(), wanted.end(), double(l)) - wanted.begin())]) continue;
      std::set<long long> present;  // a second pass: only on this error
      visit_values(path, o, [&](std::size_t, double v) { present.insert((long long)v); });
      absent_label(l, labels_present(present), path);
    }
  } else if (sel.has_threshold) {
    visit_values(path, o, [&](std::size_t, double v) { put(v >= sel.threshold); });
  } else {
    visit_values(path, o, [&](std::size_t, double v) { put(v != 0); });
  }
  if (count == 0) throw Error("the foreground is empty (check --label/--threshold)", path);
  if (fields) *fields = string_fields(o.io->GetMetaDataDictionary());
  return out;
}

// The integer types VoxelStream's values are compared in.
std::optional<IntegerType> integer_type(itk::IOComponentEnum t) {
  switch (t) {
    case itk::IOComponentEnum::UCHAR: return IntegerType::u8;
    case itk::IOComponentEnum::CHAR: return IntegerType::i8;
    case itk::IOComponentEnum::USHORT: return IntegerType::u16;
    case itk::IOComponentEnum::SHORT: return IntegerType::i16;
    case itk::IOComponentEnum::UINT: return IntegerType::u32;
    case itk::IOComponentEnum::INT: return IntegerType::i32;
    default: return std::nullopt;
  }
}
} // namespace

BinaryImage read_foreground(const std::string& path, const Selection& sel, std::map<std::string, std::string>* fields) {
  Spool spool(path);
  Opened o = open_image(path, spool.file());
  return read_foreground_opened(path, o, sel, fields);
}

ForegroundRuns read_foreground_runs(const std::string& path, const Selection& sel) {
  if (sel.labels.empty() || sel.has_threshold) throw Error("internal: read_foreground_runs selects labels", path);
  Spool spool(path);
  const std::optional<VoxelLayout> layout = plain_voxel_layout(spool.file());
  Opened o = open_image(path, spool.file(), !layout);
  const std::optional<IntegerType> type = integer_type(o.io->GetComponentType());
  if (layout && type && o.info.components == 1 && std::size_t(layout->bytes) == o.io->GetComponentSize() &&
      layout->values == o.info.geometry.count()) {
    LabelMatch match;
    match.labels = sel.labels;
    std::sort(match.labels.begin(), match.labels.end());
    match.labels.erase(std::unique(match.labels.begin(), match.labels.end()), match.labels.end());
    VoxelStream in(spool.file(), *layout, layout->values, path);
    ForegroundRuns runs = label_runs(o.info.geometry, in, *type, match);
    if (std::find(match.seen.begin(), match.seen.end(), 0) == match.seen.end()) return runs;
    // A label absent: read_foreground's error names the labels present.
  }
  if (layout) check_metaimage_data(path, spool.file(), o);
  return ForegroundRuns(read_foreground_opened(path, o, sel, nullptr));
}

namespace {
// A voxel of a label image: a 32-bit integer.
std::int32_t label_value(double v, const std::string& path) {
  if (v != std::floor(v) || v < -2147483648.0 || v > 2147483647.0)
    throw Error("not a label image: value " + std::to_string(v) + " is not a 32-bit integer", path);
  return std::int32_t(v);
}

LabelImage read_labels_opened(const std::string& path, LabelNames* names, ImageInfo* info) {
  Spool spool(path);
  Opened o = open_image(path, spool.file());
  if (names) *names = o.names;
  if (info) *info = o.info;
  LabelImage out(o.info.geometry, 0);
  visit_values(path, o, [&](std::size_t i, double v) { out.data[i] = label_value(v, path); });
  return out;
}
} // namespace

LabelImage read_labels(const std::string& path, LabelNames* names) { return read_labels_opened(path, names, nullptr); }

NarrowLabelImage read_labels_narrow(const std::string& path, LabelNames* names) {
  Spool spool(path);
  Opened o = open_image(path, spool.file());
  if (names) *names = o.names;
  const std::unique_ptr<char[]> raw = read_raw(path, o);
  std::int32_t lo = 0, hi = 0;
  visit_raw(path, o, raw.get(), [&](std::size_t, double v) {
    const std::int32_t l = label_value(v, path);
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  });
  NarrowLabelImage out;
  auto fill = [&](auto& image) {
    using T = typename std::decay_t<decltype(image.data)>::value_type;
    image = Image<T>(o.info.geometry, 0);
    visit_raw(path, o, raw.get(), [&](std::size_t i, double v) { image.data[i] = T(v); });
  };
  out.bytes = lo >= 0 && hi <= 255 ? 1 : lo >= 0 && hi <= 65535 ? 2 : 4;
  if (out.bytes == 1) fill(out.u8);
  else if (out.bytes == 2) fill(out.u16);
  else fill(out.i32);
  return out;
}

LabelImage read_labels(const std::string& path, const Selection& sel, ImageInfo* info) {
  if (sel.has_threshold) {
    const BinaryImage b = read_foreground(path, sel);
    LabelImage img(b.geometry());
    std::copy(b.data.begin(), b.data.end(), img.data.begin());
    if (info) {
      info->geometry = b.geometry();
      info->component = "unsigned_char";
    }
    return img;
  }
  LabelImage img = read_labels_opened(path, nullptr, info);
  if (!sel.labels.empty()) {
    const std::set<long long> keep(sel.labels.begin(), sel.labels.end());
    for (long long l : keep)
      if (std::find(img.data.begin(), img.data.end(), l) == img.data.end())
        absent_label(l, labels_present(std::set<long long>(img.data.begin(), img.data.end())), path);
    for (auto& v : img.data)
      if (!keep.count(v)) v = 0;
  }
  return img;
}

FloatImage read_float(const std::string& path, std::map<std::string, std::string>* fields) {
  Spool spool(path);
  Opened o = open_image(path, spool.file());
  FloatImage out(o.info.geometry, 0.f);
  visit_values(path, o, [&](std::size_t i, double v) { out.data[i] = float(v); });
  if (fields) *fields = string_fields(o.io->GetMetaDataDictionary());
  return out;
}

void write_image(const std::string& path, const BinaryImage& img, const std::map<std::string, std::string>& fields) {
  write_any<std::uint8_t>(path, img, fields);
}

void write_image(const std::string& path, const FloatImage& img, const std::map<std::string, std::string>& fields) {
  write_any<float>(path, img, fields);
}

void write_image(const std::string& path, const LabelImage& img, const std::string& component,
                 const std::map<std::string, std::string>& fields) {
  auto as = [&](auto tag) { write_any<decltype(tag)>(path, img, fields); };
  switch (component.empty() ? itk::IOComponentEnum::INT : itk::ImageIOBase::GetComponentTypeFromString(component)) {
    case itk::IOComponentEnum::UCHAR: as(std::uint8_t()); break;
    case itk::IOComponentEnum::CHAR: as(std::int8_t()); break;
    case itk::IOComponentEnum::USHORT: as(std::uint16_t()); break;
    case itk::IOComponentEnum::SHORT: as(std::int16_t()); break;
    case itk::IOComponentEnum::UINT: as(std::uint32_t()); break;
    case itk::IOComponentEnum::FLOAT: as(float()); break;
    case itk::IOComponentEnum::DOUBLE: as(double()); break;
    default: write_any<std::int32_t>(path, img, fields); break;  // int and the 64-bit types: the values are 32-bit integers
  }
}

} // namespace imgmesh
