#pragma once
// A triangle mesh read from an STL file (ASCII or binary), for bodies of shape type "stl". The reading
// and the inside test are CGAL's (Polygon_mesh_processing's reader, Side_of_triangle_mesh), kept in
// stl_mesh.cpp so that no other file compiles CGAL's headers; a build without CGAL refuses the files.
#include <array>
#include <memory>
#include <string>

namespace isph {

// Whether this build can read STL files (it was configured with CGAL).
bool stl_available();

class StlMesh {
 public:
  // Reads `path` and maps each vertex v to scale v + translate. Throws std::runtime_error saying why a
  // file cannot be read.
  static std::shared_ptr<const StlMesh> load(const std::string& path, double scale,
                                             const std::array<double, 3>& translate);
  ~StlMesh();

  // The edges that border only one triangle: 0 for a closed (watertight) surface.
  std::size_t border_edges() const;
  bool closed() const { return border_edges() == 0; }
  const std::array<double, 3>& lo() const { return lo_; }  // the bounding box
  const std::array<double, 3>& hi() const { return hi_; }
  // Whether p lies inside the closed surface or on it (exact predicates); false for an open mesh.
  bool inside(const std::array<double, 3>& p) const;

 private:
  struct Impl;
  explicit StlMesh(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
  std::array<double, 3> lo_{}, hi_{};
};

}  // namespace isph
