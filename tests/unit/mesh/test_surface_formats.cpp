#include "mesh/surface_formats.hpp"
#include "mesh/surface_io.hpp"
#include "util/binary_io.hpp"

#include "util/error.hpp"

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

using namespace imgmesh;

namespace {
// Two disjoint tetrahedra, the second (vertices 4..7) first in the face
// list and smaller (3 faces of its 4, so it is not the largest).
SurfaceMesh two_pieces() {
  SurfaceMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {5, 0, 1}};
  m.triangles = {{4, 6, 5}, {0, 2, 1}, {4, 5, 7}, {0, 1, 3}, {1, 2, 3}, {5, 6, 7}, {0, 3, 2}};
  return m;
}
} // namespace

TEST_CASE("face_components: connected by shared vertices, largest first") {
  const SurfaceMesh m = two_pieces();
  CHECK(face_components(m) == std::vector<int>{1, 0, 1, 0, 0, 1, 0});
  SurfaceMesh joined = m;
  joined.triangles.push_back({3, 7, 2});  // a face joining them: one component
  CHECK(face_components(joined) == std::vector<int>(8, 0));
}

TEST_CASE("PLY face properties: component and label per face, in order") {
  SurfaceMesh m = two_pieces();
  m.labels = {7, 3, 7, 3, 3, 7, 3};
  std::ostringstream out;
  write_ply(out, m, face_components(m), true);
  const std::string b = out.str();
  CHECK(b.find("property int component\nproperty int label\nend_header\n") != std::string::npos);
  const std::size_t faces = b.find("end_header\n") + 11 + 8 * 12;
  REQUIRE(b.size() == faces + 7 * 21);
  for (std::size_t i = 0; i < 7; ++i) {
    std::int32_t v[5];
    std::memcpy(v, b.data() + faces + 21 * i + 1, 20);
    CHECK(v[0] == m.triangles[i][0]);
    CHECK(v[3] == (m.triangles[i][0] >= 4 ? 1 : 0));
    CHECK(v[4] == m.labels[i]);
  }
}

TEST_CASE("msh: one entity per component, physical group per label") {
  SurfaceMesh m = two_pieces();
  m.labels = {7, 3, 7, 3, 3, 7, 3};
  for (const std::string version : {"4.1", "2.2"}) {
    std::ostringstream out;
    write_msh(out, m, face_components(m), version, false);
    const std::string s = out.str();
    CHECK(s.find("$MeshFormat\n" + version + " 0 8\n") == 0);
    CHECK(s.find("$PhysicalNames\n2\n2 3 \"label 3\"\n2 7 \"label 7\"\n") != std::string::npos);
    if (version == "2.2") {
      CHECK(s.find("\n1 2 2 7 2 5 7 6\n") != std::string::npos);  // face 0: label 7, entity 2, 1-based ids
    } else {
      CHECK(s.find("$Entities\n0 0 2 0\n") != std::string::npos);
      CHECK(s.find(" 1 3 0\n2 ") != std::string::npos);  // entity 1 (the larger piece) in group 3
    }
  }
}

TEST_CASE("label names: .msh physical names, PLY comments, VTK field data; labels without a face left out") {
  SurfaceMesh m = two_pieces();
  m.labels = {7, 3, 7, 3, 3, 7, 3};
  m.label_names = {{3, "left \"kidney\" 5%\n\xc3\xa9"}, {7, ""}, {9, "absent"}};
  const std::vector<int> comp = face_components(m);
  std::ostringstream msh, ply, vtp, vtk;
  write_msh(msh, m, comp, "4.1", false);
  CHECK(msh.str().find("$PhysicalNames\n2\n2 3 \"left 'kidney' 5% \xc3\xa9\"\n2 7 \"label 7\"\n") != std::string::npos);
  write_ply(ply, m, comp, true);
  CHECK(ply.str().find("(as ITK)\ncomment label_name 3 left \"kidney\" 5% \xc3\xa9\nelement vertex") != std::string::npos);
  write_vtp(vtp, m, comp, false);
  CHECK(vtp.str().find("  <PolyData>\n    <FieldData>\n"
                       "      <DataArray type=\"Int32\" Name=\"label_values\" NumberOfTuples=\"1\" format=\"ascii\">\n"
                       "        3 \n      </DataArray>\n"
                       "      <DataArray type=\"String\" Name=\"label_names\" NumberOfTuples=\"1\" format=\"ascii\">\n"
                       "        108 101 102 116 32 34 107 105 100 110 101 121 34 32 53 37 10 -61 -87 0\n"
                       "      </DataArray>\n    </FieldData>\n    <Piece ") != std::string::npos);
  write_vtk_legacy(vtk, m, comp, false);
  CHECK(vtk.str().find("DATASET POLYDATA\nFIELD FieldData 2\nlabel_values 1 1 int\n3 \nlabel_names 1 1 string\n"
                       "left%20%22kidney%22%205%25%0A%C3%A9\nPOINTS 8 double\n") != std::string::npos);
  // A long name is cut at 127 bytes in .msh, never inside a UTF-8 character.
  m.label_names = {{3, std::string(126, 'a') + "\xc3\xa9"}};
  std::ostringstream cut;
  write_msh(cut, m, comp, "2.2", false);
  CHECK(cut.str().find("2 3 \"" + std::string(126, 'a') + "\"\n") != std::string::npos);
  // Without names every format is as before.
  m.label_names.clear();
  std::ostringstream plain;
  write_vtp(plain, m, comp, false);
  CHECK(plain.str().find("FieldData") == std::string::npos);
}

TEST_CASE("binary .vtp: appended zlib arrays holding the exact doubles and ids; field data as in ASCII") {
  SurfaceMesh m = two_pieces();
  m.points[1] = {1.0 / 3, -2e-9, 123456.789012345};
  m.labels = {7, 3, 7, 3, 3, 7, 3};
  m.label_names = {{3, "liver"}};
  const std::vector<int> comp = face_components(m);
  std::ostringstream text, bin;
  write_vtp(text, m, comp, false);
  write_vtp(bin, m, comp, true);
  const std::string b = bin.str();
  CHECK(b.find("header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"") != std::string::npos);
  CHECK(b.find("Name=\"label_names\" NumberOfTuples=\"1\" format=\"ascii\">\n        108 105 118 101 114 0\n") !=
        std::string::npos);
  const std::size_t data = b.find("<AppendedData encoding=\"raw\">\n   _") + 34;
  VtkBinaryLayout zlib64;
  zlib64.zlib = zlib64.uint64_header = true;
  REQUIRE(data > 34);
  // Each array by the offset its DataArray gives.
  auto array = [&](const std::string& name) {
    const std::size_t tag = b.find("Name=\"" + name + "\"");
    const std::size_t at = b.find("offset=\"", tag) + 8;
    return vtk_array_decode(b, data + std::stoull(b.substr(at)), zlib64, name, "t.vtp");
  };
  const std::string points = array("Points"), ids = array("connectivity"), labels = array("label");
  REQUIRE(points.size() == 8 * 24);
  for (std::size_t i = 0; i < 24; ++i) CHECK(get_bytes<double>(points.data() + 8 * i) == m.points[i / 3][i % 3]);
  REQUIRE(ids.size() == 7 * 24);
  for (std::size_t i = 0; i < 21; ++i) CHECK(get_bytes<std::int64_t>(ids.data() + 8 * i) == m.triangles[i / 3][i % 3]);
  REQUIRE(labels.size() == 7 * 4);
  for (std::size_t i = 0; i < 7; ++i) CHECK(get_bytes<std::int32_t>(labels.data() + 4 * i) == m.labels[i]);
  // The text form is what it was: 17 digits, version 0.1, no appended data.
  CHECK(text.str().find("version=\"0.1\" byte_order=\"LittleEndian\">") != std::string::npos);
  CHECK(text.str().find("AppendedData") == std::string::npos);
  CHECK(text.str().find("         0.33333333333333331 -2.0000000000000001e-09 123456.78901234501\n") != std::string::npos);
}

TEST_CASE("vtk_zlib: arrays over several 32 KiB blocks decode to their bytes; a cut array is an Error") {
  std::string raw;
  for (int i = 0; i < 20000; ++i) append_bytes(raw, double(i) / 7);
  const std::string z = vtk_zlib_encode(raw);
  CHECK(get_bytes<std::uint64_t>(z.data()) == 5);  // 160000 bytes: 4 full blocks and one of 28928
  CHECK(get_bytes<std::uint64_t>(z.data() + 16) == 160000 % 32768);
  VtkBinaryLayout zlib64;
  zlib64.zlib = zlib64.uint64_header = true;
  CHECK(vtk_array_decode("xy" + z, 2, zlib64, "a", "t") == raw);
  CHECK_THROWS_AS(vtk_array_decode(z.substr(0, z.size() - 1), 0, zlib64, "a", "t"), Error);
  CHECK(vtk_array_decode(vtk_zlib_encode(""), 0, zlib64, "a", "t").empty());
}

TEST_CASE("VtkZlibEncoder: the bytes given in any pieces encode as all at once, and decode back to them") {
  for (const std::size_t n : {std::size_t(3 * 32768 + 100), std::size_t(2 * 32768)}) {
    std::string raw;
    for (std::size_t i = 0; raw.size() < n; ++i) raw += char((i * 7919) % 251);
    std::string once;
    for (const std::string& piece : [&] {
           VtkZlibEncoder e;
           e.add(raw.data(), raw.size());
           return e.finish();
         }())
      once += piece;
    CHECK(get_bytes<std::uint64_t>(once.data()) == (n + 32767) / 32768);
    CHECK(get_bytes<std::uint64_t>(once.data() + 16) == n % 32768);
    // Uneven pieces across the block boundaries, and single values.
    VtkZlibEncoder e;
    std::size_t at = 0;
    for (const std::size_t size : {std::size_t(1), std::size_t(7), std::size_t(40000), std::size_t(20000)}) {
      e.add(raw.data() + at, size);
      at += size;
    }
    for (; at < raw.size(); ++at) e.add_value(raw[at]);
    std::string pieces;
    for (const std::string& piece : e.finish()) pieces += piece;
    CHECK(pieces == once);
    VtkBinaryLayout zlib64;
    zlib64.zlib = zlib64.uint64_header = true;
    CHECK(vtk_array_decode(pieces, 0, zlib64, "a", "t") == raw);
    // Emptied by finish: the next array starts afresh.
    std::string empty;
    for (const std::string& piece : e.finish()) empty += piece;
    CHECK(empty == vtk_zlib_encode(""));
  }
}

// Arrays as vtkXMLWriter writes them in base64, made by hand: the bytes
// packed little- or big-endian, zlib-compressed and base64-encoded by
// Python's struct, zlib and base64 modules (not by our encoder); the values
// are the numbers packed.
TEST_CASE("vtk_array_decode: base64 arrays (uncompressed one run; zlib header and blocks two) to their values") {
  const auto int32s = [](const std::string& raw) {
    std::vector<std::int32_t> v;
    for (std::size_t i = 0; i + 4 <= raw.size(); i += 4) v.push_back(get_bytes<std::int32_t>(raw.data() + i));
    return v;
  };
  const std::vector<std::int32_t> want{1, -2, 258};
  VtkBinaryLayout b64;
  b64.base64 = true;
  // UInt32 byte count 12, then Int32 1, -2, 258: one run, padded.
  CHECK(int32s(vtk_array_decode("_DAAAAAEAAAD+////AgEAAA==", 1, b64, "a", "t")) == want);
  // zlib: header (1 block of 32768, the last 12, compressed 20) one run,
  // the block the next.
  VtkBinaryLayout z = b64;
  z.zlib = true;
  CHECK(int32s(vtk_array_decode("AQAAAACAAAAMAAAAFAAAAA==eJxjZGBg+Pf//38mRgYGABoBBAA=", 0, z, "a", "t")) == want);
  // Two blocks (8 bytes each, the last 4; compressed 16 and 12): the blocks
  // together are one run.
  CHECK(int32s(vtk_array_decode("AgAAAAgAAAAEAAAAEAAAAAwAAAA=eJxjZGBg+Pf//38ACgID/XicY2JkYAAAAA8ABA==", 0, z, "a", "t")) ==
        want);
  // Big-endian, UInt64 header: byte count 16, then Float64 0.5 and -3.25.
  VtkBinaryLayout be = b64;
  be.uint64_header = true;
  be.order = ByteOrder::Big;
  const std::string raw = vtk_array_decode("AAAAAAAAABA/4AAAAAAAAMAKAAAAAAAA", 0, be, "a", "t");
  REQUIRE(raw.size() == 16);
  CHECK(get_bytes<double>(raw.data(), ByteOrder::Big) == 0.5);
  CHECK(get_bytes<double>(raw.data() + 8, ByteOrder::Big) == -3.25);
  // Not base64, padding inside a run, cut short: an Error naming the array.
  CHECK_THROWS_WITH(vtk_array_decode("DAAAAAEAAAD+//*/AgEAAA==", 0, b64, "DataArray x", "t"),
                    Catch::Contains("DataArray x: its data is not base64"));
  CHECK_THROWS_WITH(vtk_array_decode("DAAAAA==AAD+////AgEAAA==", 0, b64, "a", "t"), Catch::Contains("not base64"));
  CHECK_THROWS_WITH(vtk_array_decode("DAAAAAEAAAD+////AgEA", 0, b64, "a", "t"), Catch::Contains("runs past the end"));
  CHECK_THROWS_WITH(vtk_array_decode("AQAAAACAAAAMAAAAFAAAAA==eJxjZGBg+Pf//38mRgYGABo", 0, z, "a", "t"),
                    Catch::Contains("runs past the end"));
}
