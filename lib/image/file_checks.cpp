// Checks of image files before ITK reads them: what a header declares
// against what the file holds and the machine has, and the headers whose
// mistakes ITK's readers (MetaIO, niftilib, libpng) crash on, hang on or
// read as zeros. No ITK here: the files are read as bytes.
#include "image/file_checks.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <png.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

namespace imgmesh {
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

namespace {
// MetaIO reads a boolean field as true when its value starts with T, t or 1.
bool metaio_true(const std::string& v) { return !v.empty() && (v[0] == 'T' || v[0] == 't' || v[0] == '1'); }

}  // namespace

// Limits before allocation: the voxel block a header declares must fit in
// this machine's memory and, when it is stored in the file read, in what
// that file can hold. The most bytes of voxels `file` (of file_size bytes)
// can hold, or 0 when that is not known here (data in another file, bzip2).
// Deflate (gzip, zlib, PNG) expands at most 1032:1; a PNG of 1-bit palette
// indices reads as 8-bit RGB (24 times its bits).
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
    // MetaIO allocates CompressedDataSize bytes as the header says: a
    // negative or NaN size is refused here, one beyond its data file by
    // metaimage_data_error, which knows the data files.
    if (line.compare(0, 18, "CompressedDataSize") == 0 && eq != std::string::npos) {
      const double declared = std::strtod(line.c_str() + eq + 1, nullptr);
      if (!(declared >= 0)) return "the MetaImage's CompressedDataSize is not a size";
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
// file it names is a regular file, holds what the header declares (raw
// voxels, or CompressedDataSize bytes, which MetaIO allocates for each
// file), and compressed data inflates to the image's `bytes` (the
// inflated bytes are counted, not kept).
namespace {
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

// What metaimage_data_error reads of a header: its fields up to
// ElementDataFile (the last), and the lines after it (a LIST's names).
struct MetaDataFields {
  std::string data, ndims, dimsize;
  bool compressed = false, binary = true;
  double compressed_size = 0;
  std::uintmax_t offset = 0;  // where LOCAL data starts
  std::vector<std::string> after;
};

MetaDataFields read_data_fields(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  MetaDataFields f;
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
  for (std::string line; std::getline(in, line);) {
    if (line.find('=') == std::string::npos) continue;
    if (key(line, "CompressedData")) f.compressed = metaio_true(value(line));
    if (key(line, "CompressedDataSize")) f.compressed_size = std::strtod(value(line).c_str(), nullptr);
    if (key(line, "BinaryData")) f.binary = metaio_true(value(line));
    if (key(line, "NDims")) f.ndims = value(line);
    if (key(line, "DimSize")) f.dimsize = value(line);
    if (key(line, "ElementDataFile")) {
      f.data = value(line);
      f.offset = std::uintmax_t(in.tellg());
      break;
    }
  }
  if (f.data.substr(0, f.data.find_first_of(" \t")) == "LIST")
    for (std::string name; std::getline(in, name);) {
      while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
      if (!name.empty()) f.after.push_back(name);
    }
  return f;
}

struct DataFile {
  std::string name;  // as the header gives it
  std::filesystem::path path;
};

// The data files of a header whose ElementDataFile is not LOCAL: one file,
// a LIST or a %d pattern; files of a LIST or a pattern hold slices, as many
// as the last axes (of the file's own dimension, NDims - 1 unless "LIST 2D"
// and such say). Names relative to the header's folder, as MetaIO takes them.
std::string data_files(const std::string& file, const MetaDataFields& f, std::vector<DataFile>& files) {
  std::vector<std::string> names;
  std::istringstream words(f.data);
  std::string first;
  words >> first;
  std::vector<long> dims;
  {
    std::istringstream d(f.dimsize);
    for (long x; d >> x;) dims.push_back(x);
  }
  const long n = std::atol(f.ndims.c_str());
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
    names = f.after;
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
    names.push_back(f.data);
  }
  if (long(names.size()) < needed)
    return "the MetaImage's ElementDataFile names " + std::to_string(names.size()) + " files, " +
           std::to_string(needed) + " needed";
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  for (const std::string& name : names) {
    const std::filesystem::path p = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : dir / name;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      return "the MetaImage's data file '" + name + "' is missing or not a regular file";
    files.push_back({name, p});
  }
  return "";
}

// The sizes the data files hold against what the header declares.
std::string data_size_error(const std::string& file, const MetaDataFields& f,
                            const std::vector<DataFile>& files, std::uintmax_t bytes) {
  std::uintmax_t largest = 0, total = 0;
  for (const DataFile& d : files) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(d.path, ec);
    largest = std::max(largest, ec ? 0 : size);
    total += ec ? 0 : size;
  }
  const std::string where = files.empty() ? std::string("the file")
                            : files.size() == 1 ? "its data file '" + files[0].name + "'"
                                                : "the largest of its data files";
  if (files.empty()) {
    std::error_code ec;
    largest = std::filesystem::file_size(file, ec);
    if (ec) return "";
  }
  if (f.compressed && f.compressed_size > double(largest))
    return "the MetaImage's CompressedDataSize (" + std::to_string((unsigned long long)std::min(f.compressed_size, 1e19)) +
           " bytes) is more than " + where + " holds (" + std::to_string(largest) + " bytes)";
  if (!f.compressed && f.binary && !files.empty() && total < bytes)
    return "the MetaImage's data file" + std::string(files.size() == 1 ? " '" + files[0].name + "' holds " : "s hold ") +
           std::to_string(total) + " bytes, the header declares " + std::to_string(bytes);
  return "";
}
}  // namespace

std::string metaimage_data_error(const std::string& file, std::uintmax_t bytes) {
  const MetaDataFields f = read_data_fields(file);
  if (f.data.empty()) return "";  // MetaIO itself refuses a header without one
  std::vector<DataFile> files;  // none: LOCAL
  if (f.data != "LOCAL") {
    const std::string e = data_files(file, f, files);
    if (!e.empty()) return e;
  }
  if (const std::string e = data_size_error(file, f, files, bytes); !e.empty()) return e;
  if (!f.compressed) return "";
  const std::string fewer = "the MetaImage's compressed data holds fewer bytes than its size declares";
  if (files.empty()) {
    const std::string e = inflate_error(file, f.offset, bytes);
    return !e.empty() ? "the MetaImage's " + e : bytes ? fewer : "";
  }
  for (const DataFile& d : files) {
    const std::string e = inflate_error(d.path.string(), 0, bytes);
    if (!e.empty()) return "the MetaImage's data file '" + d.name + "': " + e;
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

}  // namespace imgmesh
