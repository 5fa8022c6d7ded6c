// meshinfo: what a mesh is (topology and quality), as text or one JSON object.
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "mesh/meshinfo.hpp"
#include "util/error.hpp"

#include <iostream>

int main(int argc, char** argv) {
  imgmesh::cli::Tool tool("meshinfo", "Report the topology and quality of a mesh (surface or planar)");
  std::string in, image;
  bool json = false;
  tool.app.add_option("MESH", in, "mesh: .off .ply .obj .stl (surface) or .ele/.node, .off (planar); - = OFF on stdin")
      ->required();
  tool.app.add_flag("--json", json, "print one JSON object (keys 'components' and 'euler' first) instead of text");
  tool.app.add_option("--image", image,
                      "well-composed image: compare the mesh with bdCA(X) component by component (exit 3 if different)");
  return tool.run(argc, argv, [&] {
    const imgmesh::PolyMesh mesh = imgmesh::read_poly_mesh(in);
    if (mesh.faces.empty()) throw imgmesh::Error("mesh has no faces", in);
    imgmesh::Json report;
    try {
      report = imgmesh::mesh_report(mesh);
    } catch (const imgmesh::Error& e) {
      throw imgmesh::Error(e.what(), in);  // name the file
    }
    bool matches = true;
    if (!image.empty()) {
      const imgmesh::BinaryImage img = imgmesh::read_foreground(image, {});
      imgmesh::MeshTopology it;
      try {
        it = imgmesh::voxel_boundary_topology(img);
      } catch (const imgmesh::Error& e) {
        throw imgmesh::Error(e.what(), image);
      }
      if (!it.manifold)
        throw imgmesh::Error("bdCA(X) is not a manifold: the image is not well-composed (run img2wc first)", image);
      const imgmesh::MeshTopology mt = imgmesh::mesh_topology(mesh.points.size(), mesh.faces);
      report["image"] = imgmesh::image_comparison(mt, it);
      matches = report.at("image").at("matches").boolean();
    }
    if (json) std::cout << report.dump(2) << "\n";
    else std::cout << imgmesh::format_report(report);
    tool.stats["vertices"] = report.at("vertices");
    tool.stats["faces"] = report.at("faces");
    tool.stats["components"] = report.at("components");
    tool.stats["euler"] = report.at("euler");
    if (!image.empty()) tool.stats["matches_image"] = matches;
    if (!matches) {
      tool.info("the mesh does not match bdCA(X) of " + image + " component by component");
      return imgmesh::cli::kGuarantee;
    }
    return imgmesh::cli::kOk;
  });
}
