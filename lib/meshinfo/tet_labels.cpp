#include "meshinfo/tet_labels.hpp"

#include <algorithm>
#include <set>

namespace imgmesh {

const char* TetLabelCertificate::name(int check) {
  static const char* const names[kChecks] = {"orientation", "conformity", "regions", "voxel centres", "interfaces"};
  return check >= 0 && check < kChecks ? names[check] : "none";
}

int TetLabelCertificate::first_failed() const {
  for (int c = 0; c < kChecks; ++c)
    if (state[std::size_t(c)] != 1) return c;
  return kChecks;
}

std::string TetLabelCertificate::failure() const {
  const int c = first_failed();
  if (c == kChecks) return "";
  return std::string(name(c)) + ": " + (why[std::size_t(c)].empty() ? "not run" : why[std::size_t(c)]);
}

namespace {

template <class T> std::string list(const std::vector<T>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size() && i < 10; ++i) s += (i ? ", " : "") + std::to_string(v[i]);
  return v.size() > 10 ? s + ", ..." : s;
}

} // namespace

TetLabelCertificate certify_tet_labels(const TetMesh& mesh, const LabelImage& x, const InterfaceCertificateOptions& options) {
  TetLabelCertificate c;
  auto set = [&c](int check, bool held, const std::string& why) {
    c.state[std::size_t(check)] = held ? 1 : 0;
    if (!held) c.why[std::size_t(check)] = why;
  };
  c.conformity = tet_conformity(mesh);
  const TetConformity& f = c.conformity;
  set(TetLabelCertificate::kOrientation, f.nonpositive == 0,
      std::to_string(f.nonpositive) + " of " + std::to_string(mesh.tets.size()) + " tetrahedra not positively oriented");
  set(TetLabelCertificate::kConformity, f.duplicates + f.overfull_faces + f.inconsistent_faces + f.bad_ids == 0,
      std::to_string(f.duplicates) + " duplicated, " + std::to_string(f.overfull_faces) + " faces in three tetrahedra or more, " +
          std::to_string(f.inconsistent_faces) + " faces traversed alike by their two, " + std::to_string(f.bad_ids) +
          " with a bad vertex id");

  const std::set<std::int32_t> labels(x.data.begin(), x.data.end());
  std::set<long long> regions;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) regions.insert(t < mesh.tet_region.size() ? mesh.tet_region[t] : 1);
  for (std::int32_t l : labels)
    if (l != 0) c.labels.push_back(l);
  for (long long r : regions)
    if (r != 0) c.regions.push_back(r);
  for (std::int32_t l : c.labels)
    if (!regions.count(l)) c.labels_without_region.push_back(l);
  for (long long r : c.regions)
    if (r < INT32_MIN || r > INT32_MAX || !labels.count(std::int32_t(r))) c.regions_without_label.push_back(r);
  std::string why;
  if (!c.labels_without_region.empty()) why = "label(s) " + list(c.labels_without_region) + " with no region";
  if (!c.regions_without_label.empty())
    why += (why.empty() ? "" : "; ") + std::string("region(s) ") + list(c.regions_without_label) + " not a label of the map";
  set(TetLabelCertificate::kRegions, why.empty(), why);

  c.centres = locate_voxel_centres(mesh, x);
  set(TetLabelCertificate::kVoxelCentres, c.centres.wrong() == 0, c.centres.failure());

  c.state[TetLabelCertificate::kInterfaces] = -1;
  if (f.ok()) {
    region_interfaces(mesh, c.triangles, c.pairs);
    if (c.triangles.empty()) set(TetLabelCertificate::kInterfaces, false, "the regions have no boundary");
    else {
      c.interfaces = certify_interface_mesh(mesh.points, c.triangles, c.pairs, x, options);
      set(TetLabelCertificate::kInterfaces, c.interfaces.ok(), c.interfaces.failure());
    }
  }
  return c;
}

Json TetLabelCertificate::to_json() const {
  Json j = Json::object();
  j["verdict"] = ok() ? "ok" : name(first_failed());
  if (!ok()) j["failure"] = failure();
  Json checks = Json::object();
  for (int k = 0; k < kChecks; ++k) {
    const int s = state[std::size_t(k)];
    checks[name(k)] = s < 0 ? Json() : Json(s == 1);
  }
  j["checks"] = checks;
  j["labels"] = labels;
  j["regions"] = regions;
  j["labels_without_region"] = labels_without_region;
  j["regions_without_label"] = regions_without_label;
  j["voxel_centres"] = centres.to_json();
  j["interface_triangles"] = triangles.size();
  return j;
}

} // namespace imgmesh
