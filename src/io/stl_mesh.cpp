#include "io/stl_mesh.hpp"

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <vector>

#ifdef ISPH_HAVE_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#endif

namespace isph {

namespace {
std::string quoted(const std::string& path) { return "\"" + path + "\""; }
}  // namespace

#ifdef ISPH_HAVE_CGAL

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
}  // namespace

struct StlMesh::Impl {
  Mesh mesh;
  std::size_t border_edges = 0;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, Kernel>> side;  // closed meshes only (its precondition)
};

bool stl_available() { return true; }

std::shared_ptr<const StlMesh> StlMesh::load(const std::string& path, double scale,
                                             const std::array<double, 3>& translate) {
  if (!std::ifstream(path)) throw std::runtime_error("cannot open " + quoted(path));
  // An STL file is a soup of triangles, each with its own copies of its corners: the reader merges equal
  // points, and the soup is repaired (degenerate and repeated triangles dropped) and oriented consistently
  // before it becomes a mesh, as CGAL's read_polygon_mesh does, whatever the file's extension.
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> faces;
  if (!CGAL::IO::read_STL(path, points, faces))
    throw std::runtime_error("cannot read " + quoted(path) + " as an STL file (ASCII or binary) of triangles");
  for (Point& p : points) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw std::runtime_error(quoted(path) + " has a vertex whose coordinates are not finite numbers");
    p = Point(scale * p.x() + translate[0], scale * p.y() + translate[1], scale * p.z() + translate[2]);
  }
  PMP::repair_polygon_soup(points, faces);
  if (faces.empty()) throw std::runtime_error(quoted(path) + " holds no triangle with three distinct corners");
  // Orienting splits the soup where more than two triangles share an edge; a soup it cannot mend is no
  // surface (and would break the conversion's precondition).
  PMP::orient_polygon_soup(points, faces);
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
    throw std::runtime_error(quoted(path) + "'s triangles do not form a surface");
  auto impl = std::make_unique<Impl>();
  PMP::polygon_soup_to_polygon_mesh(points, faces, impl->mesh);
  for (const auto h : impl->mesh.halfedges()) impl->border_edges += impl->mesh.is_border(h);
  if (impl->border_edges == 0) impl->side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, Kernel>>(impl->mesh);
  return std::shared_ptr<const StlMesh>(new StlMesh(std::move(impl)));
}

StlMesh::StlMesh(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {
  const CGAL::Bbox_3 box = PMP::bbox(impl_->mesh);
  lo_ = {box.xmin(), box.ymin(), box.zmin()};
  hi_ = {box.xmax(), box.ymax(), box.zmax()};
}

std::size_t StlMesh::border_edges() const { return impl_->border_edges; }

bool StlMesh::inside(const std::array<double, 3>& p) const {
  return impl_->side && (*impl_->side)(Point(p[0], p[1], p[2])) != CGAL::ON_UNBOUNDED_SIDE;
}

#else

struct StlMesh::Impl {};

bool stl_available() { return false; }

std::shared_ptr<const StlMesh> StlMesh::load(const std::string& path, double, const std::array<double, 3>&) {
  throw std::runtime_error("cannot read " + quoted(path) +
                           ": this build has no CGAL; apt-get install libcgal-dev, then configure and build again");
}

StlMesh::StlMesh(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
std::size_t StlMesh::border_edges() const { return 0; }
bool StlMesh::inside(const std::array<double, 3>&) const { return false; }

#endif

StlMesh::~StlMesh() = default;

}  // namespace isph
