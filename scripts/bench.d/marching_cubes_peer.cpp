// Benchmark peer (not installed, not a test): ITK's marching cubes
// (itk::BinaryMask3DMeshSource) on the well-composed image, in world
// coordinates.   marching_cubes_peer IN.nrrd OUT.off
// Prints "seconds triangles".
#include "image/io.hpp"

#include <itkBinaryMask3DMeshSource.h>
#include <itkImage.h>
#include <itkMesh.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: marching_cubes_peer IN.nrrd OUT.off\n";
    return 2;
  }
  try {
    // One background voxel around: a label touching the image's border
    // still gets a closed surface (implicit2mesh's f is closed there too).
    const imgmesh::BinaryImage x = imgmesh::pad(imgmesh::read_foreground(argv[1], {}), {1, 1, 1}, {1, 1, 1});
    using Image = itk::Image<unsigned char, 3>;
    using Mesh = itk::Mesh<double, 3>;
    const auto t0 = std::chrono::steady_clock::now();
    Image::Pointer img = Image::New();
    Image::RegionType region;
    Image::SizeType size;
    for (int i = 0; i < 3; ++i) size[i] = x.size[i];
    region.SetSize(size);
    img->SetRegions(region);
    double spacing[3], origin[3];
    for (int i = 0; i < 3; ++i) { spacing[i] = x.spacing[i]; origin[i] = x.origin[i]; }
    img->SetSpacing(spacing);
    img->SetOrigin(origin);
    Image::DirectionType direction;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) direction(i, j) = x.direction[std::size_t(3 * i + j)];
    img->SetDirection(direction);
    img->Allocate();
    std::copy(x.data.begin(), x.data.end(), img->GetBufferPointer());
    auto mc = itk::BinaryMask3DMeshSource<Image, Mesh>::New();
    mc->SetInput(img);
    mc->SetObjectValue(1);
    mc->Update();
    const Mesh* m = mc->GetOutput();
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ofstream out(argv[2]);
    out.precision(17);
    out << "OFF\n" << m->GetNumberOfPoints() << ' ' << m->GetNumberOfCells() << " 0\n";
    for (auto it = m->GetPoints()->Begin(); it != m->GetPoints()->End(); ++it)
      out << it.Value()[0] << ' ' << it.Value()[1] << ' ' << it.Value()[2] << '\n';
    for (auto it = m->GetCells()->Begin(); it != m->GetCells()->End(); ++it) {
      out << it.Value()->GetNumberOfPoints();
      for (auto p = it.Value()->PointIdsBegin(); p != it.Value()->PointIdsEnd(); ++p) out << ' ' << *p;
      out << '\n';
    }
    std::cout << secs << ' ' << m->GetNumberOfCells() << '\n';
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "marching_cubes_peer: " << e.what() << '\n';
    return 1;
  }
}
