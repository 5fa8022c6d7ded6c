// meshinfo: what a mesh is (topology and quality), as text or one JSON object.
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "mesh/meshinfo.hpp"
#include "mesh/volume_io.hpp"
#include "util/atomic_file.hpp"

#include <iostream>
#include <optional>

int main(int argc, char** argv) {
  imgmesh::cli::Tool tool("meshinfo", "Report the topology and quality of a mesh (surface or planar)");
  std::string in, image;
  bool json = false;
  tool.app.add_option("MESH", in, "mesh: .off .ply .obj .stl (surface), .ele/.node, .off (planar) or .msh .mesh .vtu (tetrahedra); - = OFF on stdin")
      ->required();
  tool.data_output(imgmesh::cli::Tool::kStdout, imgmesh::cli::Stream::Text, [&] { return !json; });  // --json: one object
  tool.app.add_flag("--json", json, "print one JSON object (keys 'components' and 'euler' first) instead of text");
  tool.app.add_option("--image", image,
                      "well-composed image: match each mesh component by place to a bdCA(X) component, one to one, same euler (exit 3 if not)")
      ->type_name("FILE");
  return tool.run(argc, argv, [&] {
    const std::string ext = imgmesh::extension_of(in);
    const bool tets = ext == ".msh" || ext == ".mesh" || ext == ".vtu";
    std::optional<imgmesh::TetMesh> tm;
    std::optional<imgmesh::PolyMesh> pm;
    if (tets) tm = imgmesh::read_tet_mesh(in);
    else pm = imgmesh::read_poly_mesh(in);
    std::optional<imgmesh::BinaryImage> img;
    if (!image.empty()) img = imgmesh::read_foreground(image, {});
    const imgmesh::MeshInfo info = tets ? imgmesh::tet_mesh_info(*tm, in, img ? &*img : nullptr, image)
                                        : imgmesh::mesh_info(*pm, in, img ? &*img : nullptr, image);
    if (json) tool.print_json(info.report);
    else std::cout << imgmesh::format_report(info.report);
    return tool.finish(info);
  });
}
