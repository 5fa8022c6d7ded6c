// ITK image I/O. Reading goes through itk::ImageIOBase on a raw buffer, so
// every component type and both 2D and 3D files share one path; writing goes
// through itk::Image + ImageFileWriter.
#include "image/io.hpp"

#include "util/atomic_file.hpp"
#include "util/error.hpp"

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
#include <csetjmp>
#include <png.h>
#include <zlib.h>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
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

// ITK's NIfTI reader returns a zero-padded image for a truncated file (the
// gzip stream or the raw data ends early) instead of failing: check that the
// file holds the whole voxel block before trusting what it read.
void check_nifti_complete(const std::string& path, const std::string& file, std::size_t data_bytes) {
  const std::string ext = extension_of(file);
  if (ext != ".nii" && ext != ".nii.gz") return;
  gzFile gz = gzopen(file.c_str(), "rb");  // reads plain files too
  if (!gz) throw Error("cannot open", path);
  std::vector<char> buf(1 << 20);
  std::size_t total = 0;
  int got = 0;
  while ((got = gzread(gz, buf.data(), unsigned(buf.size()))) > 0) total += std::size_t(got);
  int err = 0;
  gzerror(gz, &err);
  gzclose(gz);
  if (got < 0 || (err != Z_OK && err != Z_STREAM_END))
    throw Error("cannot read the image: corrupt or truncated compressed data", path);
  if (total < 348 + data_bytes)
    throw Error("cannot read the image: truncated (" + std::to_string(total) + " bytes, the header needs " +
                    std::to_string(348 + data_bytes) + ")",
                path);
}

// Limits before allocation: the voxel block a header declares must fit in
// this machine's memory and, when it is stored in the file read, in what
// that file can hold. The most bytes of voxels `file` (of file_size bytes)
// can hold, or 0 when that is not known here (data in another file, bzip2).
// Deflate (gzip, zlib, PNG) expands at most 1032:1; a PNG of 1-bit palette
// indices reads as 8-bit RGB (24 times its bits).
// MetaIO reads a boolean field as true when its value starts with T, t or 1.
bool metaio_true(const std::string& v) { return !v.empty() && (v[0] == 'T' || v[0] == 't' || v[0] == '1'); }

std::uintmax_t max_data_bytes(const std::string& file, std::uintmax_t file_size) {
  constexpr std::uintmax_t deflate = 1032, slack = 4096;
  std::ifstream in(file, std::ios::binary);
  std::string head(1 << 16, '\0');
  in.read(&head[0], std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  auto starts = [&](const char* m) { return head.compare(0, std::strlen(m), m) == 0; };
  // The value of the header line "key<sep>value" (up to the blank line that
  // ends a NRRD header), or "" when absent.
  auto field = [&](const std::string& key, char sep) {
    std::size_t pos = 0;
    while (pos < head.size()) {
      std::size_t end = head.find('\n', pos);
      if (end == std::string::npos) end = head.size();
      std::string line = head.substr(pos, end - pos);
      line = line.substr(0, line.find('\0'));  // the C readers stop there
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
      if (line.empty() && sep == ':') break;
      // teem matches field names whatever their case ("Encoding:").
      auto same = [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); };
      if (line.size() >= key.size() && std::equal(key.begin(), key.end(), line.begin(), same) &&
          line.find(":=") == std::string::npos) {
        std::size_t v = line.find(sep, key.size());
        if (v != std::string::npos && line.find_first_not_of(' ', key.size()) == v) {
          v = line.find_first_not_of(" =:", v);
          return v == std::string::npos ? std::string() : line.substr(v);
        }
      }
      pos = end + 1;
    }
    return std::string();
  };
  if (starts("NRRD")) {
    if (!field("data file", ':').empty() || !field("datafile", ':').empty()) return 0;
    const std::string enc = field("encoding", ':');
    if (enc == "raw" || enc == "hex") return file_size;
    if (enc == "ascii" || enc == "text" || enc == "txt") return 8 * file_size;  // a value: one digit, 8 bytes
    if (enc == "gzip" || enc == "gz") return deflate * file_size + slack;
    return 0;
  }
  if (starts("ObjectType") || starts("NDims")) {
    if (field("ElementDataFile", '=') != "LOCAL") return 0;
    const std::string c = field("CompressedData", '='), b = field("BinaryData", '=');
    // MetaIO's booleans: true when the value starts with T, t or 1.
    if (metaio_true(c)) return deflate * file_size + slack;
    return !b.empty() && !metaio_true(b) ? 8 * file_size : file_size;
  }
  if (starts("\x89PNG")) return 24 * deflate * file_size + slack;
  if (head.size() >= 2 && (unsigned char)head[0] == 0x1f && (unsigned char)head[1] == 0x8b)
    return extension_of(file) == ".nii.gz" ? deflate * file_size + slack : 0;
  // A .nii holds its voxels whatever its magic says (ITK reads it as one file).
  if (extension_of(file) == ".nii" || (head.size() > 348 && head.compare(344, 3, "n+1") == 0)) return file_size;
  return 0;
}

std::uintmax_t physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? std::uintmax_t(pages) * std::uintmax_t(page)
                               : std::numeric_limits<std::uintmax_t>::max();
}

void check_declared_size(const std::string& path, const std::string& file, std::uintmax_t data_bytes) {
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(file, ec);
  const std::uintmax_t most = ec ? 0 : max_data_bytes(file, file_size);
  if (most && data_bytes > most)
    throw Error("the header declares " + std::to_string(data_bytes) + " bytes of voxels, more than the file (" +
                    std::to_string(file_size) + " bytes) can hold",
                path);
  const std::uintmax_t memory = physical_memory();
  if (data_bytes > memory)
    throw Error("the header declares " + std::to_string(data_bytes) + " bytes of voxels, more than this machine's memory (" +
                    std::to_string(memory) + " bytes)",
                path);
}

// ITK's PNG reader sets no libpng error handler before reading the header,
// so a bad IHDR, a bad CRC or an unknown critical chunk aborts the program:
// read the header here first, where libpng's errors come back as a message
// (its warnings are dropped). Empty when libpng reads it.
std::string png_header_error(const std::string& file) {
  struct Messages { std::string error, warning; } msg;
  FILE* fp = std::fopen(file.c_str(), "rb");
  if (!fp) return "cannot open";
  png_structp png = png_create_read_struct(
      PNG_LIBPNG_VER_STRING, &msg,
      [](png_structp p, png_const_charp m) {
        static_cast<Messages*>(png_get_error_ptr(p))->error = m;
        png_longjmp(p, 1);
      },
      [](png_structp p, png_const_charp m) { static_cast<Messages*>(png_get_error_ptr(p))->warning = m; });
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    std::fclose(fp);
    return "out of memory";
  }
  if (setjmp(png_jmpbuf(png)) == 0) {
    png_init_io(png, fp);
    png_read_info(png, info);
  } else if (msg.error.empty()) {
    msg.error = "unreadable PNG header";
  }
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(fp);
  if (!msg.error.empty() && !msg.warning.empty()) msg.error += " (" + msg.warning + ")";
  return msg.error;
}

// stdin is spooled to a temporary file whose extension comes from the content,
// since ITK reads only from paths and picks readers by name and content.
class Spool {
public:
  explicit Spool(const std::string& path) : path_(path) {
    if (path != "-") return;
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
    const char* tmpdir = std::getenv("TMPDIR");
    std::string templ = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/stdin-XXXXXX" + ext;
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
  ~Spool() { if (!tmp_.empty()) std::remove(tmp_.c_str()); }
  const std::string& file() const { return tmp_.empty() ? path_ : tmp_; }

private:
  std::string path_, tmp_;
};

struct Opened {
  itk::ImageIOBase::Pointer io;
  ImageInfo info;
};

// The MetaImage header is checked before MetaIO reads it. Every line up to
// ElementDataFile (the last field) must be "Key = Value": MetaIO takes any
// byte after a key as its '=', so a header it reads differently from this
// check (and from metaimage_data_error) is refused rather than guessed at.
// MetaIO formats a list-of-files ElementDataFile ("slice%03d.raw 1 9 1")
// with printf and an int: any other conversion ("%s", "%n") reads or
// writes through garbage. So a '%' there must start one "%[0][width]d".
std::string metaimage_header_error(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  for (int n = 0; n < 200 && std::getline(in, line); ++n) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
    if (line.empty()) continue;
    {
      std::size_t k = 0;
      while (k < line.size() && (std::isalnum(static_cast<unsigned char>(line[k])) || line[k] == '_')) ++k;
      const std::size_t e = line.find_first_not_of(" \t", k);
      if (k == 0 || e == std::string::npos || line[e] != '=')
        return "MetaImage header line " + std::to_string(n + 1) + " is not 'Key = Value'";
    }
    // MetaIO copies a field's name into 255 bytes and its value into a
    // fixed buffer, unchecked.
    const std::size_t eq = line.find('=');
    if (line.size() > 1000 || (eq != std::string::npos && eq > 200))
      return "a MetaImage header line longer than MetaIO can read";
    // MetaIO reads NDims numbers for each per-axis field: a huge NDims reads
    // on (a hang) and one above 10 overruns its arrays.
    if (line.compare(0, 5, "NDims") == 0 && eq != std::string::npos) {
      char* end = nullptr;
      const long n = std::strtol(line.c_str() + eq + 1, &end, 10);
      if (n < 1 || n > 10 || end == line.c_str() + eq + 1 || end[std::strspn(end, " \t\r")] != '\0')
        return "the MetaImage's NDims must be a whole number from 1 to 10";
    }
    // MetaIO allocates CompressedDataSize bytes as the header says.
    if (line.compare(0, 18, "CompressedDataSize") == 0 && eq != std::string::npos) {
      std::error_code ec;
      const double declared = std::strtod(line.c_str() + eq + 1, nullptr);
      const auto size = std::filesystem::file_size(file, ec);
      if (!(declared >= 0) || (!ec && declared > double(size)))
        return "the MetaImage's CompressedDataSize is more than the file holds";
    }
    if (line.compare(0, 15, "ElementDataFile") != 0 || line.find_first_not_of(" \t", 15) != line.find('=')) continue;
    // An empty value makes MetaIO take its file name from the data after.
    if (line.find_first_not_of(" \t", line.find('=') + 1) == std::string::npos)
      return "the MetaImage's ElementDataFile is empty";
    int conversions = 0;
    for (std::size_t i = line.find('%'); i != std::string::npos; i = line.find('%', i + 1)) {
      std::size_t j = i + 1;
      while (j < line.size() && std::isdigit(static_cast<unsigned char>(line[j]))) ++j;
      if (j >= line.size() || line[j] != 'd' || ++conversions > 1)
        return "the MetaImage's ElementDataFile pattern may hold one %d (and width digits) only";
      i = j;
    }
    return "";
  }
  return "the MetaImage header has no ElementDataFile line (in its first 200 lines)";
}

// MetaIO reads a data file it cannot open, a LIST or a %d pattern naming
// files that are missing, or compressed data that does not inflate, as
// zeros (printing at most "Uncompress failed"), and takes a directory's
// size as 2^63. So the data the header points to is checked here: every
// file it names is a regular file, and compressed data inflates to the
// image's `bytes` (the inflated bytes are counted, not kept).
std::string inflate_error(const std::string& file, std::uintmax_t offset, std::uintmax_t& bytes) {
  std::ifstream in(file, std::ios::binary);
  in.seekg(std::streamoff(offset));
  z_stream z{};
  if (!in || inflateInit2(&z, 47) != Z_OK) return "compressed data cannot be read";  // 47: zlib or gzip
  std::vector<unsigned char> input(1 << 16), output(1 << 16);
  int err = Z_OK;
  while (bytes > 0 && err != Z_STREAM_END) {
    if (z.avail_in == 0) {
      in.read(reinterpret_cast<char*>(input.data()), std::streamsize(input.size()));
      z.next_in = input.data();
      z.avail_in = uInt(in.gcount());
      if (z.avail_in == 0) break;
    }
    z.next_out = output.data();
    z.avail_out = uInt(output.size());
    err = inflate(&z, Z_NO_FLUSH);
    if (err != Z_OK && err != Z_STREAM_END) break;
    const std::uintmax_t got = output.size() - z.avail_out;
    bytes -= std::min(bytes, got);
  }
  inflateEnd(&z);
  if (err != Z_OK && err != Z_STREAM_END) return "compressed data is corrupt (zlib: " + std::string(z.msg ? z.msg : "error") + ")";
  return "";
}

std::string metaimage_data_error(const std::string& file, std::uintmax_t bytes) {
  std::ifstream in(file, std::ios::binary);
  std::string line, data, ndims, dimsize;
  bool compressed = false;
  std::uintmax_t offset = 0;
  auto value = [](const std::string& l) {
    std::size_t v = l.find_first_not_of(" \t", l.find('=') + 1);
    std::string s = v == std::string::npos ? "" : l.substr(v);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    return s;
  };
  auto key = [](const std::string& l, const char* k) {
    const std::size_t n = std::strlen(k);
    return l.compare(0, n, k) == 0 && l.find_first_not_of(" \t", n) == l.find('=');
  };
  while (std::getline(in, line)) {
    if (line.find('=') == std::string::npos) continue;
    if (key(line, "CompressedData")) compressed = metaio_true(value(line));
    if (key(line, "NDims")) ndims = value(line);
    if (key(line, "DimSize")) dimsize = value(line);
    if (key(line, "ElementDataFile")) {
      data = value(line);
      offset = std::uintmax_t(in.tellg());
      break;
    }
  }
  if (data.empty()) return "";  // MetaIO itself refuses a header without one
  const std::string fewer = "the MetaImage's compressed data holds fewer bytes than its size declares";
  if (data == "LOCAL") {
    if (!compressed) return "";
    const std::string e = inflate_error(file, offset, bytes);
    return !e.empty() ? "the MetaImage's " + e : bytes ? fewer : "";
  }
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  std::vector<std::string> names;
  std::istringstream words(data);
  std::string first;
  words >> first;
  // Files of a LIST or a pattern hold slices: as many as the last axes (of
  // the file's own dimension, NDims - 1 unless "LIST 2D" and such say).
  std::vector<long> dims;
  {
    std::istringstream d(dimsize);
    for (long x; d >> x;) dims.push_back(x);
  }
  const long n = std::atol(ndims.c_str());
  auto slices = [&](long file_dims) {
    long count = 1;
    for (long i = std::max(0L, file_dims); i < n && i < long(dims.size()); ++i) count *= std::max(1L, dims[i]);
    return count;
  };
  long needed = 1;
  if (first == "LIST") {
    std::string d;
    words >> d;
    needed = slices(d.empty() ? n - 1 : std::atol(d.c_str()));
    for (std::string name; std::getline(in, name);) {
      while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
      if (!name.empty()) names.push_back(name);
    }
  } else if (first.find('%') != std::string::npos) {
    long lo = 0, hi = -1, step = 1;
    words >> lo >> hi >> step;
    if (step <= 0 || hi < lo || (hi - lo) / step > 100000) return "the MetaImage's ElementDataFile pattern has a bad range";
    needed = slices(n - 1);
    for (long i = lo; i <= hi; i += step) {
      char name[1100];
      std::snprintf(name, sizeof name, first.c_str(), int(i));  // one %d only (metaimage_header_error)
      names.push_back(name);
    }
  } else {
    names.push_back(data);
  }
  if (long(names.size()) < needed)
    return "the MetaImage's ElementDataFile names " + std::to_string(names.size()) + " files, " +
           std::to_string(needed) + " needed";
  for (const std::string& name : names) {
    const std::filesystem::path p = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : dir / name;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      return "the MetaImage's data file '" + name + "' is missing or not a regular file";
  }
  if (!compressed) return "";
  for (const std::string& name : names) {
    const std::filesystem::path p = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : dir / name;
    const std::string e = inflate_error(p.string(), 0, bytes);
    if (!e.empty()) return "the MetaImage's data file '" + name + "': " + e;
  }
  return bytes ? fewer : "";
}

// ITK's NIfTI reader aborts (a vnl assertion) on a header whose spacing or
// orientation is not finite: the header's floats are checked here first.
// Returns what is wrong, or "" (also for a header too short to be NIfTI's).
std::string nifti_header_error(const std::string& file) {
  unsigned char h[348];
  gzFile gz = gzopen(file.c_str(), "rb");  // reads plain files too
  if (!gz) return "";
  const int got = gzread(gz, h, sizeof h);
  gzclose(gz);
  if (got != int(sizeof h)) return "";
  // The byte order as niftilib decides it (need_nhdr_swap): by dim[0] in
  // 1..7 when it is not 0, else by sizeof_hdr = 348.
  const int d0_le = h[40] | (h[41] << 8), d0_be = h[41] | (h[40] << 8);
  bool swap;
  if (d0_le != 0) {
    if (d0_le >= 1 && d0_le <= 7) swap = false;
    else if (d0_be >= 1 && d0_be <= 7) swap = true;
    else return "";  // niftilib refuses it
  } else if (h[0] == 92 && h[1] == 1 && h[2] == 0 && h[3] == 0) {
    swap = false;
  } else if (h[3] == 92 && h[2] == 1 && h[1] == 0 && h[0] == 0) {
    swap = true;
  } else {
    return "";
  }
  auto real = [&](int at) {
    unsigned char b[4];
    for (int i = 0; i < 4; ++i) b[i] = h[at + (swap ? 3 - i : i)];
    float v;
    std::memcpy(&v, b, 4);
    return v;
  };
  for (int at = 76; at < 108; at += 4)  // pixdim
    if (!std::isfinite(real(at))) return "the NIfTI header's voxel size is not finite";
  for (int at = 256; at < 328; at += 4)  // quatern_b..d, qoffset, srow_x..z
    if (!std::isfinite(real(at))) return "the NIfTI header's orientation is not finite";
  return "";
}

Opened open_image_itk(const std::string& path, const std::string& file) {
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
  if (std::strcmp(o.io->GetNameOfClass(), "MetaImageIO") == 0) {
    const std::string e = metaimage_data_error(file, std::uintmax_t(count) * comps * o.io->GetComponentSize());
    if (!e.empty()) throw Error("cannot read the image: " + e, path);
  }
  for (int i = 0; i < 3; ++i)
    if (!(g.spacing[i] > 0) || !std::isfinite(g.spacing[i]))
      throw Error("spacing must be positive and finite", path);
  return o;
}

// ITK throws from its queries too (an unknown component type, ...): those
// come out as Error naming the file, like the reader's own.
Opened open_image(const std::string& path, const std::string& file) {
  try {
    return open_image_itk(path, file);
  } catch (const itk::ExceptionObject& e) {
    throw Error(itk_message(e), path);
  }
}

// Calls f(i, value) for every voxel i, value as double (exact for every
// integer type up to 2^53), straight from ITK's buffer: no per-voxel copy
// wider than the file's own type. Grey images stored as RGB(A) or palette
// PNG (R = G = B) read as their grey value; real colour is refused.
template <class F> void visit_values(const std::string& path, Opened& o, F&& f) {
  const unsigned n = o.io->GetNumberOfDimensions();
  itk::ImageIORegion region(n);
  for (unsigned i = 0; i < n; ++i) {
    region.SetIndex(i, 0);
    region.SetSize(i, o.io->GetDimensions(i));
  }
  o.io->SetIORegion(region);
  const std::size_t count = o.info.geometry.count();
  const std::size_t c = o.io->GetNumberOfComponents();
  check_nifti_complete(path, o.io->GetFileName(), o.io->GetImageSizeInBytes());
  std::vector<char> raw(o.io->GetImageSizeInBytes());
  {
    const CerrCapture said;
    try {
      o.io->Read(raw.data());
    } catch (const itk::ExceptionObject& e) {
      throw said.error(e, path);
    }
    said.check_read(path);
  }
  auto convert = [&](auto tag) {
    using T = decltype(tag);
    const T* p = reinterpret_cast<const T*>(raw.data());
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

template <unsigned D, class T>
void write_itk(const std::string& file, const Image<T>& img, const std::map<std::string, std::string>& fields) {
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
  std::copy(img.data.begin(), img.data.end(), out->GetBufferPointer());
  auto& dict = out->GetMetaDataDictionary();
  for (const auto& [k, v] : fields) itk::EncapsulateMetaData<std::string>(dict, k, v);
  auto writer = itk::ImageFileWriter<ItkImage>::New();
  writer->SetFileName(file);
  writer->SetInput(out);
  writer->SetUseCompression(true);
  writer->Update();
}

template <class T>
void write_any(const std::string& path, const Image<T>& img, const std::map<std::string, std::string>& fields) {
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
    if (img.dimension == 2) write_itk<2>(out.path(), img, fields);
    else write_itk<3>(out.path(), img, fields);
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

BinaryImage read_foreground(const std::string& path, const Selection& sel) {
  Spool spool(path);
  Opened o = open_image(path, spool.file());
  if (!sel.labels.empty() && sel.has_threshold)
    throw UsageError("give either --label or --threshold, not both");
  if (!sel.labels.empty() && !o.info.integer)
    throw UsageError("--label needs an integer image, this one holds " + o.info.component +
                         " values (use --threshold)",
                     path);
  BinaryImage out(o.info.geometry, 0);
  std::size_t count = 0;
  if (!sel.labels.empty()) {
    std::set<double> wanted(sel.labels.begin(), sel.labels.end()), seen;
    visit_values(path, o, [&](std::size_t i, double v) {
      if (wanted.count(v)) { out.data[i] = 1; seen.insert(v); ++count; }
    });
    for (long long l : sel.labels) {
      if (seen.count(double(l))) continue;
      std::set<long long> present;  // a second pass: only on this error
      visit_values(path, o, [&](std::size_t, double v) { present.insert((long long)v); });
      absent_label(l, labels_present(present), path);
    }
  } else if (sel.has_threshold) {
    visit_values(path, o, [&](std::size_t i, double v) {
      if (v >= sel.threshold) { out.data[i] = 1; ++count; }
    });
  } else {
    visit_values(path, o, [&](std::size_t i, double v) {
      if (v != 0) { out.data[i] = 1; ++count; }
    });
  }
  if (count == 0) throw Error("the foreground is empty (check --label/--threshold)", path);
  return out;
}

LabelImage read_labels(const std::string& path) {
  Spool spool(path);
  Opened o = open_image(path, spool.file());
  LabelImage out(o.info.geometry, 0);
  visit_values(path, o, [&](std::size_t i, double v) {
    if (v != std::floor(v) || std::abs(v) > 2147483647.0)
      throw Error("not a label image: value " + std::to_string(v) + " is not a 32-bit integer", path);
    out.data[i] = std::int32_t(v);
  });
  return out;
}

LabelImage read_labels(const std::string& path, const Selection& sel) {
  if (sel.has_threshold) {
    const BinaryImage b = read_foreground(path, sel);
    LabelImage img(b.geometry());
    std::copy(b.data.begin(), b.data.end(), img.data.begin());
    return img;
  }
  LabelImage img = read_labels(path);
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
  if (fields) {
    fields->clear();
    const auto& dict = o.io->GetMetaDataDictionary();
    for (const auto& key : dict.GetKeys()) {
      std::string value;
      if (itk::ExposeMetaData<std::string>(dict, key, value)) (*fields)[key] = value;
    }
  }
  return out;
}

void write_image(const std::string& path, const BinaryImage& img) { write_any(path, img, {}); }

void write_image(const std::string& path, const FloatImage& img, const std::map<std::string, std::string>& fields) {
  write_any(path, img, fields);
}

} // namespace imgmesh
