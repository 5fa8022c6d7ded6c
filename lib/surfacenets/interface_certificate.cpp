// certify_interface_mesh: a short driver over the checks
// interface_certificate.hpp lists: the interfaces (interface_patches.cpp),
// the whole mesh's crossings (soup_crossing_pairs), each label's surface
// against a crop of its indicator (certify_surface, voxel_sides).
#include "surfacenets/interface_certificate.hpp"

#include "surfacenets/interface_certificate_detail.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <map>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <cmath>
#include <limits>
#include <numeric>

namespace imgmesh {
namespace {

using Cert = InterfaceCertificate;

void validate(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
              const std::vector<std::array<std::int32_t, 2>>& pairs, const Geometry& image,
              const InterfaceComplex& k) {
  if (image.dimension != 3 || k.dimension != 3) throw Error("certify_interface_mesh: a 3D label image is needed");
  for (int a = 0; a < 3; ++a)
    if (k.lattice[std::size_t(a)] != image.size[std::size_t(a)] + 1)
      throw Error("certify_interface_mesh: the interface complex is not the label image's");
  if (k.critical.total()) throw Error("certify_interface_mesh: " + k.failed_guarantee());
  if (triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw Error("certify_interface_mesh: more than 2^32 triangles");
  if (pairs.size() != triangles.size())
    throw Error("certify_interface_mesh: " + std::to_string(pairs.size()) + " label pairs for " +
                std::to_string(triangles.size()) + " triangles");
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    for (int v : tri) {
      if (v < 0 || std::size_t(v) >= points.size())
        throw Error("triangle " + std::to_string(t) + " has a vertex id out of range: " + std::to_string(v));
      const Vec3& p = points[std::size_t(v)];
      if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
        throw Error("vertex " + std::to_string(v) + " has a coordinate that is not a finite number");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      throw Error("triangle " + std::to_string(t) + " repeats a corner");
  }
}

// The voxel box of each label (label 0: of X != 0) and its voxel count.
struct LabelBox {
  std::array<std::size_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
  std::size_t voxels = 0;
  void add(std::size_t x, std::size_t y, std::size_t z) {
    const std::array<std::size_t, 3> p{x, y, z};
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = voxels ? std::min(lo[a], p[a]) : p[a];
      hi[a] = voxels ? std::max(hi[a], p[a]) : p[a];
    }
    ++voxels;
  }
};
// labels: ascending, 0 among them. T: the image's voxel type (int32, or
// narrower: NarrowLabelImage).
template <class T>
std::vector<LabelBox> label_boxes(const Image<T>& img, const std::vector<std::int32_t>& labels) {
  std::vector<LabelBox> box(labels.size());
  const std::size_t zero = std::size_t(std::lower_bound(labels.begin(), labels.end(), 0) - labels.begin());
  std::size_t at = 0;
  for (std::size_t z = 0; z < img.size[2]; ++z)
    for (std::size_t y = 0; y < img.size[1]; ++y)
      for (std::size_t x = 0; x < img.size[0]; ++x) {
        const std::int32_t v = std::int32_t(img(x, y, z));
        if (labels[at] != v) at = std::size_t(std::lower_bound(labels.begin(), labels.end(), v) - labels.begin());
        if (v != 0) box[at].add(x, y, z), box[zero].add(x, y, z);
      }
  return box;
}

// The first voxel of a label's crop: its box grown by a voxel within the grid.
std::array<std::size_t, 3> crop_lo(const LabelBox& box) {
  return {box.lo[0] ? box.lo[0] - 1 : 0, box.lo[1] ? box.lo[1] - 1 : 0, box.lo[2] ? box.lo[2] - 1 : 0};
}

// {X = label} (label 0: X != 0) on its box grown by a voxel within the
// grid: every voxel with a face on its bdCA, and its neighbours across.
template <class T> BinaryImage crop_indicator(const Image<T>& img, std::int32_t label, const LabelBox& box) {
  Geometry g = img.geometry();
  const std::array<std::size_t, 3> lo = crop_lo(box);
  for (std::size_t a = 0; a < 3; ++a) g.size[a] = std::min(box.hi[a] + 1, img.size[a] - 1) - lo[a] + 1;
  g.origin = img.world(double(lo[0]), double(lo[1]), double(lo[2]));
  BinaryImage b(g, 0);
  for (std::size_t z = 0; z < g.size[2]; ++z)
    for (std::size_t y = 0; y < g.size[1]; ++y)
      for (std::size_t x = 0; x < g.size[0]; ++x) {
        const std::int32_t v = std::int32_t(img(lo[0] + x, lo[1] + y, lo[2] + z));
        b(x, y, z) = label == 0 ? v != 0 : v == label;
      }
  return b;
}

// A label's triangles, oriented out of it (label 0: out of X != 0, into 0),
// on its own vertices (renumbered through `local`, left all -1 again).
// ts .. ts_end: its triangles' ids.
void label_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                   const std::vector<std::array<std::int32_t, 2>>& pairs, const std::uint32_t* ts,
                   const std::uint32_t* ts_end, std::int32_t label, std::vector<int>& local, std::vector<Vec3>& p,
                   std::vector<std::array<int, 3>>& tris) {
  std::vector<int> used;
  tris.clear();  // sized exactly below (the scratch holds its largest label's)
  tris.resize(std::size_t(ts_end - ts));
  for (std::size_t i = 0; i < tris.size(); ++i) {
    auto tri = triangles[ts[i]];
    const auto& pr = pairs[ts[i]];
    if (label == 0 ? pr[1] != 0 : pr[0] != label) std::swap(tri[1], tri[2]);
    for (int c = 0; c < 3; ++c) {
      int& v = local[std::size_t(tri[std::size_t(c)])];
      if (v < 0) v = int(used.size()), used.push_back(tri[std::size_t(c)]);
      tris[i][std::size_t(c)] = v;
    }
  }
  p.clear();
  p.resize(used.size());
  for (std::size_t v = 0; v < used.size(); ++v) {
    p[v] = points[std::size_t(used[v])];
    local[std::size_t(used[v])] = -1;
  }
}

double area_of(const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& tris) {
  double area = 0;
  for (const auto& t : tris) {
    const Vec3 &a = p[std::size_t(t[0])], &b = p[std::size_t(t[1])], &c = p[std::size_t(t[2])];
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    area += std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2;
  }
  return area;
}

// One label: its surface certified against the crop of its indicator, its
// figures, its voxel centres' sides. On a mesh where `cells` holds, the
// nesting and the sides from the lattice (interface_cells.cpp), else by rays.
template <class T>
void certify_label(Cert::Label& l, const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& tris,
                   const Image<T>& image, const LabelBox& box, const CertificateOptions& options,
                   const surfacenets_detail::NetCells& cells, const InterfaceComplex& k) {
  l.triangles = tris.size();
  l.area = area_of(p, tris);
  l.voxels = box.voxels;
  l.voxel_volume = double(box.voxels) * image.spacing[0] * image.spacing[1] * image.spacing[2];
  BinaryImage crop = crop_indicator(image, l.label, box);
  const VoxelBoundary vb = voxel_boundary(crop);
  const MeshTopology bt = mesh_topology(vb);
  const Geometry grid = crop.geometry();
  // On the lattice the crop's last use is its voxel centres' count: freed
  // before the surface's certificate (a label's peak).
  const std::size_t centres = cells.holds ? centres_next_to_boundary(crop) : 0;
  if (cells.holds) decltype(crop.data)().swap(crop.data);
  CertificateOptions o = options;
  if (cells.holds)
    o.nesting = [&](const MeshTopology& t) {
      return surfacenets_detail::net_depths(t, p, image, k.lattice, cells.slack, crop_lo(box), vb, bt);
    };
  l.surface = certify_surface(p, tris, grid, vb, bt, o);
  for (double v : l.surface.volume) l.volume += v;
  if (l.surface.state[SurfaceCertificate::kIntersections] < 0) return;  // not closed, manifold, oriented
  l.sides_checked = true;
  if (cells.holds) {
    l.sides.checked = centres;  // every one on its side
    return;
  }
  std::vector<int> component(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) component[t] = l.surface.topology.component_of[std::size_t(tris[t][0])];
  l.sides = voxel_sides(p, tris, component, l.surface.topology.components.size(), crop);
}

// A thread's scratch for one label after another.
struct Scratch {
  std::vector<int> local;  // per mesh vertex its label-surface id, -1 between labels
  std::vector<Vec3> p;
  std::vector<std::array<int, 3>> tris;
};

// Every label of K(X) with faces and every label of the mesh, ascending.
// Labels are independent: `threads` threads take them in turn, each result
// in its label's slot, so the certificate is the same whatever their number.
template <class T>
std::vector<Cert::Label> certify_labels(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                        const std::vector<std::array<std::int32_t, 2>>& pairs, const Image<T>& image,
                                        const InterfaceComplex& k, const CertificateOptions& options, unsigned threads,
                                        const surfacenets_detail::NetCells& cells) {
  std::vector<std::int32_t> in_image, labels;
  for (const auto& lb : k.labels) in_image.push_back(lb.label);  // ascending, 0 among them
  for (const auto& lb : k.labels)
    if (lb.faces) labels.push_back(lb.label);
  // The mesh's labels added as found (a few, against two a triangle kept).
  for (const auto& pr : pairs)
    for (std::int32_t v : pr)
      if (const auto at = std::lower_bound(labels.begin(), labels.end(), v); at == labels.end() || *at != v) labels.insert(at, v);
  // Per label, its triangles (CSR, ascending ids; 4 bytes each: validate
  // allows no more than 2^32 triangles).
  auto index = [&](std::int32_t v) { return std::size_t(std::lower_bound(labels.begin(), labels.end(), v) - labels.begin()); };
  std::vector<std::size_t> start(labels.size() + 1, 0);
  for (const auto& pr : pairs) {
    ++start[index(pr[0]) + 1];
    if (pr[1] != pr[0]) ++start[index(pr[1]) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::uint32_t> of(start.back());
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < pairs.size(); ++t) {
    of[next[index(pairs[t][0])]++] = std::uint32_t(t);
    if (pairs[t][1] != pairs[t][0]) of[next[index(pairs[t][1])]++] = std::uint32_t(t);
  }
  const std::vector<LabelBox> boxes = label_boxes(image, in_image);
  std::vector<Cert::Label> out(labels.size());
  auto certify_one = [&](std::size_t i, std::vector<int>& local, std::vector<Vec3>& p, std::vector<std::array<int, 3>>& tris) {
    Cert::Label& l = out[i];
    l.label = labels[i];
    label_surface(points, triangles, pairs, of.data() + start[i], of.data() + start[i + 1], l.label, local, p, tris);
    const auto b = std::lower_bound(in_image.begin(), in_image.end(), l.label);
    l.in_image = b != in_image.end() && *b == l.label;
    if (!l.in_image) {
      l.triangles = tris.size();
      l.area = area_of(p, tris);
      return;
    }
    certify_label(l, p, tris, image, boxes[std::size_t(b - in_image.begin())], options, cells, k);
  };
  // The labels of more than an eighth of the triangles (a body's skin and
  // soft tissue: 3 labels of body.mha, each 40 to 75% of them) one after
  // another on one worker, the others beside them: two of those at once
  // held both their voxel boundaries and topologies at the certificate's
  // peak.
  std::vector<std::size_t> big, rest;
  for (std::size_t i = 0; i < labels.size(); ++i) (start[i + 1] - start[i] > triangles.size() / 8 ? big : rest).push_back(i);
  std::vector<Scratch> scratch(std::max(1u, threads));
  std::atomic<std::size_t> next_rest{0};
  surfacenets_detail::for_each_index(std::max(1u, threads), threads, [&](std::size_t job, unsigned w) {
    Scratch& s = scratch[w];
    if (s.local.empty()) s.local.assign(points.size(), -1);
    if (job == 0)
      for (std::size_t i : big) certify_one(i, s.local, s.p, s.tris);
    for (std::size_t r; (r = next_rest++) < rest.size();) certify_one(rest[r], s.local, s.p, s.tris);
  });
  return out;
}

void set(Cert& c, int check, bool held, const std::string& why = "") {
  c.state[std::size_t(check)] = held ? 1 : 0;
  if (!held) c.why[std::size_t(check)] = why;
}

std::string pair_text(const std::array<std::int32_t, 2>& p) { return std::to_string(p[0]) + "|" + std::to_string(p[1]); }

void check_intersections(Cert& c, const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                         const std::vector<std::array<std::int32_t, 2>>& pairs, const InterfaceCertificateOptions& o) {
  const std::size_t cap = o.intersections_cap;
  std::vector<std::array<std::size_t, 2>> found = o.crossings ? o.crossings() : soup_crossing_pairs(points, triangles, cap);
  if (found.size() > cap) found.resize(cap);
  const SelfIntersections& s = c.intersections = summarize_intersections(found, cap);
  if (s.pairs == 0) return set(c, Cert::kIntersections, true);
  auto tri = [&](std::size_t t) { return "triangle " + std::to_string(t) + " (" + pair_text(pairs[t]) + ")"; };
  std::string why = "intersections: ";
  if (s.first[0] == s.first[1]) why += std::to_string(s.degenerate) + " degenerate triangle(s) (collinear corners), the first " + tri(s.first[0]);
  else
    why += std::string(s.capped ? "at least " : "") + std::to_string(s.pairs - s.degenerate) +
           " pair(s) of triangles meet other than in a shared edge or vertex, the first " + tri(s.first[0]) + " and " +
           tri(s.first[1]);
  set(c, Cert::kIntersections, false, why);
}

// labels and voxel sides from the labels' certificates.
void check_labels(Cert& c) {
  c.state[Cert::kSides] = 1;
  for (const auto& l : c.labels) {
    const std::string name = "label " + std::to_string(l.label) + ": ";
    if (c.state[Cert::kLabels] != 0 && (!l.in_image || !l.surface.ok()))
      set(c, Cert::kLabels, false,
          name + (l.in_image ? l.surface.failure() : "not a label of the image (" + std::to_string(l.triangles) + " triangles)"));
    if (c.state[Cert::kSides] == 0) continue;
    if (!l.sides_checked) c.state[Cert::kSides] = -1;
    else if (l.sides.wrong())
      set(c, Cert::kSides, false,
          name + "voxel sides: " + std::to_string(l.sides.wrong()) + " of " + std::to_string(l.sides.checked) +
              " voxel centres on the wrong side (" + std::to_string(l.sides.foreground_outside) + " of the label outside its surface, " +
              std::to_string(l.sides.background_inside) + " others inside, " + std::to_string(l.sides.on_surface) + " on it)");
  }
  if (c.state[Cert::kLabels] != 0) c.state[Cert::kLabels] = 1;
}

} // namespace

void surfacenets_detail::for_each_index(std::size_t n, unsigned threads,
                                        const std::function<void(std::size_t, unsigned)>& work) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto run = [&](unsigned w) {
    try {
      for (std::size_t i; (i = next++) < n;) work(i, w);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = n;
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < std::min<std::size_t>(std::max(1u, threads), n); ++t) pool.emplace_back(run, t);
  run(0);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

std::string InterfaceCertificate::Interface::name() const { return pair_text({behind, front}); }

const char* InterfaceCertificate::name(int check) {
  static const char* const names[kChecks] = {"interfaces", "intersections", "labels", "voxel sides"};
  return check >= 0 && check < kChecks ? names[check] : "none";
}

int InterfaceCertificate::first_failed() const {
  for (int k = 0; k < kChecks; ++k)
    if (state[std::size_t(k)] != 1) return k;
  return kChecks;
}

std::string InterfaceCertificate::failure() const {
  const int k = first_failed();
  if (k == kChecks) return "";
  return state[std::size_t(k)] < 0 ? std::string(name(k)) + ": not checked" : why[std::size_t(k)];
}

namespace {
constexpr std::size_t kWholePatchFaces = 256;
constexpr std::size_t kStrayPieceTriangles = 4096;

// A large mesh patch whose Euler characteristic or loops differ from its
// K(X) patch's: where? Each of the K(X) patch's boundary loops goes with
// the mesh patch's boundary loop nearest most of its curve edges; the
// curve edges of K(X) loops that share a mesh loop (a strip of the patch
// between two holes cut) or have none near are the places. piece: the mesh
// patch's triangles.
void merged_loop_places(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                        const std::vector<std::uint32_t>& piece, std::size_t patch, const InterfaceComplex& k,
                        const Geometry& grid, std::vector<Vec3>& out) {
  // The mesh patch's boundary edges, joined into loops at their vertices.
  std::map<std::pair<int, int>, int> uses;
  for (std::uint32_t t : piece)
    for (int e = 0; e < 3; ++e) {
      const int a = triangles[t][std::size_t(e)], b = triangles[t][std::size_t((e + 1) % 3)];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::map<int, int> parent;
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<std::pair<int, int>> border;
  for (const auto& [e, n] : uses)
    if (n == 1) {
      border.push_back(e);
      parent.try_emplace(e.first, e.first);
      parent.try_emplace(e.second, e.second);
      parent[find(e.first)] = find(e.second);
    }
  // Their midpoints by lattice cell.
  auto cell = [&](const Vec3& w) {
    const Vec3 q = grid.continuous_index(w);
    return std::array<long, 3>{long(std::floor(q[0])), long(std::floor(q[1])), long(std::floor(q[2]))};
  };
  std::map<std::array<long, 3>, std::vector<std::pair<Vec3, int>>> near;
  for (const auto& [a, b] : border) {
    const Vec3& p = points[std::size_t(a)];
    const Vec3& q = points[std::size_t(b)];
    const Vec3 m{(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
    near[cell(m)].push_back({m, find(a)});
  }
  // K(X)'s loops of the patch: their curve edges' midpoints, and the mesh
  // loop nearest each.
  std::map<std::uint32_t, std::vector<Vec3>> kloop;
  std::map<std::uint32_t, std::map<int, std::size_t>> votes;
  for (std::size_t e = 0; e < k.curve_edges.size(); ++e)
    for (int s = 0; s < 4; ++s) {
      const std::uint32_t l = k.curve_edge_loop[4 * e + std::size_t(s)];
      if (l == InterfaceComplex::kNoLoop || k.loops[l].patch != patch) continue;
      const auto q = k.corner(k.curve_edges[e] / 3);
      const int a = int(k.curve_edges[e] % 3);
      // Corner q is where voxels q - 1 and q meet.
      Vec3 c{double(q[0]) - 0.5, double(q[1]) - 0.5, double(q[2]) - 0.5};
      c[std::size_t(a)] += 0.5;
      const Vec3 w = grid.world(c[0], c[1], c[2]);
      kloop[l].push_back(w);
      const auto at = cell(w);
      double best = INFINITY;
      int loop = -1;
      for (long dz = -1; dz <= 1; ++dz)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dx = -1; dx <= 1; ++dx) {
            const auto it = near.find({at[0] + dx, at[1] + dy, at[2] + dz});
            if (it == near.end()) continue;
            for (const auto& [m, id] : it->second) {
              const double d = (m[0] - w[0]) * (m[0] - w[0]) + (m[1] - w[1]) * (m[1] - w[1]) + (m[2] - w[2]) * (m[2] - w[2]);
              if (d < best) best = d, loop = id;
            }
          }
      ++votes[l][loop];
    }
  std::map<int, std::vector<std::uint32_t>> of_mesh_loop;
  for (const auto& [l, v] : votes) {
    const auto top = std::max_element(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    of_mesh_loop[top->first].push_back(l);
  }
  for (const auto& [m, ls] : of_mesh_loop)
    if (m < 0 || ls.size() > 1)
      for (std::uint32_t l : ls) out.insert(out.end(), kloop[l].begin(), kloop[l].end());
}
} // namespace

std::vector<Vec3> InterfaceCertificate::failing_places(const std::vector<Vec3>& points,
                                                       const std::vector<std::array<int, 3>>& triangles,
                                                       const std::vector<std::array<std::int32_t, 2>>& pairs,
                                                       const InterfaceComplex& k, const Geometry& grid) const {
  std::vector<std::int32_t> bad;
  for (const Label& l : labels)
    if (!l.surface.ok() || (l.sides_checked && l.sides.wrong() > 0)) bad.push_back(l.label);
  auto is_bad = [&](std::int32_t l) { return std::find(bad.begin(), bad.end(), l) != bad.end(); };
  auto centroid = [&](std::size_t t) {
    Vec3 c{0, 0, 0};
    for (int v : triangles[t])
      for (int a = 0; a < 3; ++a) c[a] += points[std::size_t(v)][a] / 3;
    return c;
  };
  std::vector<Vec3> out;
  std::vector<std::size_t> whole;
  for (const Interface& i : interfaces) {
    const bool all = is_bad(i.behind) || is_bad(i.front);
    if (!all && i.why.empty()) continue;
    // Its mesh patches' triangles, when a place finder needs them: once.
    std::vector<std::vector<std::uint32_t>> members;
    auto piece = [&](std::size_t p) -> const std::vector<std::uint32_t>& {
      if (members.empty()) members = surfacenets_detail::interface_patch_triangles(triangles, pairs, i.behind, i.front);
      return members.at(p);
    };
    std::map<long long, std::size_t> largest;  // per K(X) patch, its largest mesh patch
    for (std::size_t p = 0; p < i.patches.size(); ++p) {
      const long long c = i.patches[p].complex_patch;
      if (c < 0) continue;
      auto it = largest.try_emplace(c, p).first;
      if (i.patches[p].triangles > i.patches[it->second].triangles) it->second = p;
    }
    for (std::size_t p = 0; p < i.patches.size(); ++p) {
      const Patch& q = i.patches[p];
      if (!all && q.verdict == "ok") continue;
      if (q.verdict == "matched twice" && largest[q.complex_patch] != p) {
        // A stray piece: where it parted from the rest (a neck one voxel
        // wide) lies along its border, so all of it when not large.
        if (q.triangles > kStrayPieceTriangles) out.push_back(centroid(q.first_triangle));
        else
          for (std::uint32_t t : piece(p)) out.push_back(centroid(t));
        continue;
      }
      out.push_back(centroid(q.first_triangle));
      if (q.complex_patch < 0) continue;
      if (k.patches[std::size_t(q.complex_patch)].faces <= kWholePatchFaces) whole.push_back(std::size_t(q.complex_patch));
      else if (q.verdict == "euler differs" || q.verdict == "loops differ")
        merged_loop_places(points, triangles, piece(p), std::size_t(q.complex_patch), k, grid, out);
    }
    for (std::size_t c : i.complex_patches)
      if (!largest.count((long long)c)) whole.push_back(c);  // no mesh patch on it
  }
  // Every face of the K(X) patches wrong as a whole (Euler characteristic,
  // loops, pinches, missing): where, the certificate does not say. Not of
  // a large patch: refining all over it grades the mesh around it for a
  // difference somewhere (the noisy brain map's first round quintupled its
  // points so).
  whole.erase(std::remove_if(whole.begin(), whole.end(), [&](std::size_t c) { return k.patches[c].faces > kWholePatchFaces; }),
              whole.end());
  std::sort(whole.begin(), whole.end());
  whole.erase(std::unique(whole.begin(), whole.end()), whole.end());
  if (!whole.empty())
    for (std::size_t f = 0; f < k.faces.size(); ++f) {
      if (!std::binary_search(whole.begin(), whole.end(), std::size_t(k.face_patch[f]))) continue;
      const auto q = k.corner(InterfaceComplex::face_corner(k.faces[f]));
      const int a = InterfaceComplex::face_axis(k.faces[f]);
      // Corner q is where voxels q - 1 and q meet; the face's centre.
      Vec3 c{double(q[0]) - 0.5, double(q[1]) - 0.5, double(q[2]) - 0.5};
      for (int b = 0; b < 3; ++b)
        if (b != a) c[b] += 0.5;
      out.push_back(grid.world(c[0], c[1], c[2]));
    }
  return out;
}

std::string InterfaceCertificate::summary() const {
  if (!ok()) return "interface certificate fails: " + failure();
  std::size_t patches = 0, centres = 0;
  for (const auto& in : interfaces) patches += in.patches.size();
  for (const auto& l : labels) centres += l.sides.checked;
  return "interface certificate holds: " + std::to_string(labels.size()) + " labels, " + std::to_string(interfaces.size()) +
         " interfaces (" + std::to_string(patches) + " patches), no crossing, " + std::to_string(centres) +
         " voxel centres on their side";
}

Json InterfaceCertificate::to_json() const {
  Json j = Json::object();
  j["verdict"] = ok() ? "ok" : name(first_failed());
  if (!ok()) j["failure"] = failure();
  j["place_tolerance"] = place_tolerance;
  Json checks = Json::object();
  for (int k = 0; k < kChecks; ++k) checks[name(k)] = state[std::size_t(k)] < 0 ? Json() : Json(state[std::size_t(k)] == 1);
  j["checks"] = checks;
  j["intersecting_pairs"] = intersections.pairs - intersections.degenerate;
  j["degenerate_triangles"] = intersections.degenerate;
  Json ls = Json::array();
  for (const auto& l : labels) {
    Json o = Json::object();
    o["label"] = l.label;
    if (l.label == 0) o["surface_of"] = "X != 0";
    o["triangles"] = l.triangles;
    o["area"] = l.area;
    o["volume"] = l.volume;
    o["voxels"] = l.voxels;
    o["voxel_volume"] = l.voxel_volume;
    o["components"] = l.surface.topology.components.size();
    o["euler"] = l.surface.topology.euler_list();
    o["verdict"] = !l.in_image ? "not in the image" : l.surface.ok() ? "ok" : SurfaceCertificate::name(l.surface.first_failed());
    if (l.in_image && !l.surface.ok()) o["failure"] = l.surface.failure();
    if (l.sides_checked) o["voxel_sides"] = l.sides.to_json();
    ls.push_back(o);
  }
  j["labels"] = ls;
  Json is = Json::array();
  for (const auto& in : interfaces) {
    Json o = Json::object();
    o["pair"] = in.name();
    o["triangles"] = in.triangles;
    o["reversed"] = in.reversed;
    o["complex_patches"] = in.complex_patches.size();
    Json ps = Json::array();
    for (const auto& p : in.patches) {
      Json q = Json::object();
      q["first_triangle"] = p.first_triangle;
      q["triangles"] = p.triangles;
      q["euler"] = p.euler;
      q["boundary_loops"] = p.boundary_loops;
      q["pinched_vertices"] = p.pinched_vertices;
      q["placed"] = p.placed;
      q["complex_patch"] = p.complex_patch;
      q["verdict"] = p.verdict;
      ps.push_back(q);
    }
    o["patches"] = ps;
    if (!in.why.empty()) o["failure"] = in.why;
    is.push_back(o);
  }
  j["interfaces"] = is;
  return j;
}

namespace {
template <class T>
InterfaceCertificate certify(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                             const std::vector<std::array<std::int32_t, 2>>& pairs, const Image<T>& image,
                             const InterfaceComplex& k, const InterfaceCertificateOptions& options) {
  validate(points, triangles, pairs, image, k);
  if (options.intersections_cap == 0) throw Error("certify_interface_mesh: the intersections cap must be positive");
  InterfaceCertificate c;
  c.state.fill(-1);
  c.place_tolerance = options.place_tolerance > 0 ? options.place_tolerance : default_place_tolerance(image);
  c.interfaces = surfacenets_detail::certify_interfaces(points, triangles, pairs, image, k, c.place_tolerance, options.threads);
  set(c, Cert::kInterfaces, true);
  for (const auto& in : c.interfaces)
    if (!in.why.empty()) {
      set(c, Cert::kInterfaces, false, in.why);
      break;
    }
  CertificateOptions co;
  co.place_tolerance = c.place_tolerance;
  co.intersections_cap = options.intersections_cap;
  co.intersections = false;  // each label's triangles are among the whole mesh's, tested here
  if (options.check_crossings) check_intersections(c, points, triangles, pairs, options);
  const surfacenets_detail::NetCells cells =
      options.lattice ? surfacenets_detail::net_cells(points, triangles, pairs, image, k) : surfacenets_detail::NetCells();
  c.on_lattice = cells.holds;
  // The pages the interfaces freed given back: the labels' threads take
  // memory from arenas of their own, which would not reuse them.
  release_free_memory();
  c.labels = certify_labels(points, triangles, pairs, image, k, co, options.threads, cells);
  check_labels(c);
  return c;
}
} // namespace

InterfaceCertificate certify_interface_mesh(const std::vector<Vec3>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<std::array<std::int32_t, 2>>& pairs,
                                            const LabelImage& image, const InterfaceComplex& k,
                                            const InterfaceCertificateOptions& options) {
  return certify(points, triangles, pairs, image, k, options);
}

void add_crossings(InterfaceCertificate& c, const std::vector<Vec3>& points,
                   const std::vector<std::array<int, 3>>& triangles,
                   const std::vector<std::array<std::int32_t, 2>>& pairs, const InterfaceCertificateOptions& options) {
  check_intersections(c, points, triangles, pairs, options);
}

InterfaceCertificate certify_interface_mesh(const std::vector<Vec3>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<std::array<std::int32_t, 2>>& pairs,
                                            const NarrowLabelImage& image, const InterfaceComplex& k,
                                            const InterfaceCertificateOptions& options) {
  return image.visit([&](const auto& im) { return certify(points, triangles, pairs, im, k, options); });
}

InterfaceCertificate certify_interface_mesh(const std::vector<Vec3>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<std::array<std::int32_t, 2>>& pairs,
                                            const LabelImage& image, const InterfaceCertificateOptions& options) {
  if (image.dimension != 3) throw Error("certify_interface_mesh: a 3D label image is needed");
  return certify_interface_mesh(points, triangles, pairs, image, interface_complex(image), options);
}

} // namespace imgmesh
