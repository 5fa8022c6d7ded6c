// meshinfo: what a mesh is (topology and quality), as text or one JSON object.
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "mesh/volume_io.hpp"
#include "meshinfo/meshinfo.hpp"
#include "planar/image_pslg.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <iostream>
#include <optional>
#include <set>

namespace {

// The label map holds two nonzero values or more (after --label): held a
// byte a voxel where its values fit, as read_foreground holds a mask, so a
// large binary image costs a second read, not four bytes a voxel.
bool several_labels(const std::string& image, const imgmesh::Selection& sel) {
  if (!sel.labels.empty()) return std::set<long long>(sel.labels.begin(), sel.labels.end()).size() > 1;
  return imgmesh::read_labels_narrow(image).visit([](const auto& x) {
    long long first = 0;
    for (const auto v : x.data)
      if (v != 0) {
        if (first == 0) first = v;
        else if (v != first) return true;
      }
    return false;
  });
}

} // namespace

int main(int argc, char** argv) {
  imgmesh::cli::Tool tool("meshinfo", "Report the topology and quality of a mesh (surface or planar)");
  std::string in, image;
  bool json = false;
  tool.app.add_option("MESH", in, "mesh: .off .ply .obj .stl .vtp .vtk (surface), .ele/.node, .off (planar), .mesh .vtu .inp (tetrahedra) or .msh (tetrahedra, else its triangles); - = OFF on stdin")
      ->required();
  tool.data_output(imgmesh::cli::Tool::kStdout, imgmesh::cli::Stream::Text, [&] { return !json; });  // --json: one object
  tool.app.add_flag("--json", json, "print one JSON object (keys 'components' and 'euler' first) instead of text");
  tool.app.add_option("--image", image,
                      "3D: well-composed image; certify the mesh against its voxel boundary bdCA(X): closed, "
                      "manifold, oriented outward, no self-intersection, each component within --place-tolerance of "
                      "one bdCA(X) component and it of the mesh component, one to one, same euler. 2D: the image "
                      "img2poly read (repaired as img2poly does); match each region of the planar mesh to a pixel "
                      "region (exit 3 if not). A surface with a label pair per face (seg2mesh's fast mode): the label "
                      "image, repaired as that mode does; the interface certificate (every pair's patches, no "
                      "crossing, each label's surface, voxel sides). Tetrahedra with a region per label against a "
                      "label image of two labels or more: repaired as seg2tet does; orientation, conformity, a region "
                      "per label, every voxel centre in a tetrahedron of its label, the regions' interfaces through "
                      "the interface certificate")
      ->type_name("FILE");
  imgmesh::CertificateOptions cert;
  auto* place = tool.app.add_option("--place-tolerance", cert.place_tolerance,
                      "with a 3D --image: how far (world units) a vertex may lie from its bdCA(X) component, and a "
                      "corner of bdCA(X) from its mesh component (default: one voxel diagonal)")
      ->type_name("D")
      ->check(CLI::Range(1e-300, 1e300).description(""));
  imgmesh::Selection sel;
  auto* label = tool.app.add_option("--label", sel.labels,
                                    "with --image: keep this label (repeatable), other values become 0, as in img2poly and img2wc")
                    ->type_name("L")
                    ->allow_extra_args(false);
  auto* thr = tool.app.add_option("--threshold", sel.threshold, "with --image: foreground is value >= T")
                  ->type_name("T")
                  ->excludes(label);
  double tolerance = 1.0;
  tool.app.add_option("--tolerance", tolerance,
                      "with a 2D --image: img2poly's --tolerance E in pixels; a face may lie up to E + 1 pixels "
                      "from its pixel region")
      ->capture_default_str()
      ->type_name("E")
      ->check(CLI::Range(0.0, 1e6).description(""));
  tool.add_seed();  // img2poly's --seed: the same repair of a 2D image

  return tool.run(argc, argv, [&] {
    const std::string ext = imgmesh::extension_of(in);
    std::optional<imgmesh::TetMesh> tm;
    std::optional<imgmesh::PolyMesh> pm;
    if (ext == ".msh" || ext == ".vtk") {  // tetrahedra, or a surface (seg2mesh's, with its label pairs)
      imgmesh::TetsOrSurface m = imgmesh::read_tets_or_surface(in);
      if (m.tets) tm = std::move(*m.tets);
      else pm = imgmesh::poly_mesh(*m.surface, ext.substr(1));
    } else if (ext == ".mesh" || ext == ".vtu" || ext == ".inp") {
      tm = imgmesh::read_tet_mesh(in);
    } else {
      pm = imgmesh::read_poly_mesh(in);
    }
    const bool tets = tm.has_value();
    sel.has_threshold = thr->count() > 0;
    if (image.empty() && (sel.has_threshold || !sel.labels.empty()))
      throw imgmesh::UsageError("--label and --threshold select the foreground of --image: give --image");
    if (image.empty() && place->count()) throw imgmesh::UsageError("--place-tolerance is the certificate's, against --image: give --image");
    // A 2D image: the labels img2poly traced (same selection, same repair).
    bool planar_image = false;
    if (!image.empty() && !tets && image != "-") {
      const auto g = imgmesh::read_image_info(image).geometry;
      planar_image = g.dimension == 2 || g.size[2] == 1;
    }
    if (pm && !pm->interfaces.empty() && !image.empty() && !planar_image) {
      imgmesh::InterfaceCertificateOptions icert;
      icert.place_tolerance = cert.place_tolerance;
      const imgmesh::MeshInfo info = imgmesh::interface_mesh_info(*pm, in, imgmesh::read_labels(image, sel), image, icert);
      if (json) tool.print_json(info.report);
      else std::cout << imgmesh::format_report(info.report);
      return tool.finish(info);
    }
    // Tetrahedra against a 3D label map of several labels: a region per
    // label, certified as seg2tet certifies its own.
    if (tets && !image.empty() && image != "-" && !sel.has_threshold) {
      const imgmesh::ImageInfo ii = imgmesh::read_image_info(image);
      if (ii.integer && ii.geometry.dimension == 3 && ii.geometry.size[2] > 1 && several_labels(image, sel)) {
        imgmesh::InterfaceCertificateOptions icert;
        icert.place_tolerance = cert.place_tolerance;
        const imgmesh::MeshInfo info = imgmesh::label_tet_mesh_info(*tm, in, imgmesh::read_labels(image, sel), image, icert);
        if (json) tool.print_json(info.report);
        else std::cout << imgmesh::format_report(info.report);
        return tool.finish(info);
      }
    }
    std::optional<imgmesh::BinaryImage> img;
    std::optional<imgmesh::LabelImage> labels;
    if (planar_image) labels = imgmesh::well_composed_labels(imgmesh::read_labels(image, sel), tool.seed());
    else if (!image.empty()) img = imgmesh::read_foreground(image, sel);
    const imgmesh::MeshInfo info = tets     ? imgmesh::tet_mesh_info(*tm, in, img ? &*img : nullptr, image, cert)
                                   : labels ? imgmesh::planar_mesh_info(*pm, in, *labels, image, tolerance + 1)
                                            : imgmesh::mesh_info(*pm, in, img ? &*img : nullptr, image, cert);
    if (json) tool.print_json(info.report);
    else std::cout << imgmesh::format_report(info.report);
    return tool.finish(info);
  });
}
