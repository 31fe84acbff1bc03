#include "shell_fit/core/shell_mesh.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace yarnfit::shell {

double ShellMesh::rest_area(int t) const {
  const auto& tri = triangles.row(t);
  const Eigen::Vector2d e1 = rest.row(tri(1)) - rest.row(tri(0));
  const Eigen::Vector2d e2 = rest.row(tri(2)) - rest.row(tri(0));
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

void build_interior_edges(ShellMesh& mesh) {
  // edge (min, max) -> (triangle, opposite vertex) of its first triangle
  std::map<std::pair<int, int>, std::pair<int, int>> first;
  mesh.interior_edges.clear();
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v0 = mesh.triangles(t, k);
      const int v1 = mesh.triangles(t, (k + 1) % 3);
      const int opposite = mesh.triangles(t, (k + 2) % 3);
      const auto key = std::minmax(v0, v1);
      const auto it = first.find(key);
      if (it == first.end()) {
        first.emplace(key, std::make_pair(t, opposite));
        continue;
      }
      InteriorEdge e;
      e.v0 = key.first;
      e.v1 = key.second;
      e.t0 = it->second.first;
      e.a = it->second.second;
      e.t1 = t;
      e.b = opposite;
      mesh.interior_edges.push_back(e);
      first.erase(it);  // a third triangle on the edge would be non-manifold: it starts anew
    }
  }
}

}  // namespace yarnfit::shell
