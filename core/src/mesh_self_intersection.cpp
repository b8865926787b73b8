// Does a closed triangulated surface cross or touch itself? (mesh.hpp, docs/equations.md §11)
//
// Faces go into a bounding-volume hierarchy (boxes around their vertices, split at the median
// centroid along the longest side); the hierarchy is traversed against itself, and every pair of
// faces whose boxes overlap is tested exactly as below. Memory is O(F); the number of pair tests
// is bounded (kMaxFacePairTests), so that a pathological file cannot take unbounded time.
//
// Two triangles intersect iff
//   - they share no vertex, and an edge of one meets the other (for triangles that are not
//     coplanar, the ends of their intersection segment lie on edges; for coplanar ones, an edge
//     meets the other or one holds the other's vertices);
//   - they share one vertex v, and the edge of one opposite v meets the other (both cut the line
//     where their planes meet in a segment from v; if the segments overlap, the shorter one's far
//     end lies on the opposite edge of its triangle and inside the other);
//   - they share an edge and lie folded onto each other: the other vertex of one in the plane of
//     the first, on the same side of the shared edge.
// Touching counts: in a valid surface, faces that share no vertex have no point in common.
#include <noether/error.hpp>
#include <noether/mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace noether {

namespace {

struct Box {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  void add(const Box& b) { lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi); }
  bool overlaps(const Box& b) const {
    return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all();
  }
};

struct Node {
  Box box;
  int begin = 0, end = 0;     // faces order[begin, end) when a leaf
  int left = -1, right = -1;  // children, or -1
};

class Search {
 public:
  Search(const Mesh& mesh, double tolerance) : mesh_(mesh), tol_(tolerance) {
    const std::size_t n = mesh.faces.size();
    boxes_.resize(n);
    centroids_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      for (int j : mesh.faces[k]) {
        boxes_[k].lo = boxes_[k].lo.cwiseMin(mesh.vertices.col(j));
        boxes_[k].hi = boxes_[k].hi.cwiseMax(mesh.vertices.col(j));
      }
      boxes_[k].lo.array() -= tol_;
      boxes_[k].hi.array() += tol_;
      centroids_[k] = 0.5 * (boxes_[k].lo + boxes_[k].hi);
    }
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0);
    nodes_.reserve(2 * n / kLeafSize + 2);
    build(0, static_cast<int>(n));
  }

  // The first intersecting pair found, or nullopt; throws SceneError past the pair budget.
  std::optional<std::pair<std::size_t, std::size_t>> run() {
    visit(0, 0);
    return found_;
  }

 private:
  static constexpr int kLeafSize = 4;

  int build(int begin, int end) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Box box;
    for (int i = begin; i < end; ++i) box.add(boxes_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])]);
    nodes_[static_cast<std::size_t>(id)].box = box;
    if (end - begin <= kLeafSize) {
      nodes_[static_cast<std::size_t>(id)].begin = begin;
      nodes_[static_cast<std::size_t>(id)].end = end;
      return id;
    }
    int axis = 0;
    (box.hi - box.lo).maxCoeff(&axis);
    const int mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int a, int b) {
                       return centroids_[static_cast<std::size_t>(a)](axis) <
                              centroids_[static_cast<std::size_t>(b)](axis);
                     });
    const int left = build(begin, mid);
    const int right = build(mid, end);
    nodes_[static_cast<std::size_t>(id)].left = left;
    nodes_[static_cast<std::size_t>(id)].right = right;
    return id;
  }

  void visit(int a, int b) {
    if (found_) return;
    const Node& A = nodes_[static_cast<std::size_t>(a)];
    const Node& B = nodes_[static_cast<std::size_t>(b)];
    if (!A.box.overlaps(B.box)) return;
    const bool leaf_a = A.left < 0, leaf_b = B.left < 0;
    if (leaf_a && leaf_b) {
      for (int i = A.begin; i < A.end && !found_; ++i)
        for (int j = (a == b ? i + 1 : B.begin); j < B.end && !found_; ++j) test(order_[static_cast<std::size_t>(i)], order_[static_cast<std::size_t>(j)]);
      return;
    }
    if (a == b) {
      visit(A.left, A.left);
      visit(A.right, A.right);
      visit(A.left, A.right);
    } else if (leaf_b || (!leaf_a && size(A) >= size(B))) {
      visit(A.left, b);
      visit(A.right, b);
    } else {
      visit(a, B.left);
      visit(a, B.right);
    }
  }

  static double size(const Node& n) { return (n.box.hi - n.box.lo).squaredNorm(); }

  void test(int f, int g) {
    if (!boxes_[static_cast<std::size_t>(f)].overlaps(boxes_[static_cast<std::size_t>(g)])) return;
    if (++tests_ > kMaxFacePairTests)
      throw SceneError(mesh_.source + ": cannot check within bounded time that the surface does not "
                       "intersect itself: more than " + std::to_string(kMaxFacePairTests) +
                       " pairs of faces lie within each other's bounding boxes (long, thin faces "
                       "crossing one region); remesh the shape");
    if (triangles_meet(static_cast<std::size_t>(f), static_cast<std::size_t>(g)))
      found_ = std::make_pair(std::min<std::size_t>(f, g), std::max<std::size_t>(f, g));
  }

  Vec3 vertex(std::size_t face, int k) const {
    return mesh_.vertices.col(mesh_.faces[face][static_cast<std::size_t>(k)]);
  }

  // The signed distance of p from the plane of the triangle (a, b, c), with its unit normal n.
  static double plane_distance(const Vec3& a, const Vec3& n, const Vec3& p) { return n.dot(p - a); }

  // 2-D orientation of (p, q, r) in the plane dropped along axis `drop`.
  static double orient(const Vec3& p, const Vec3& q, const Vec3& r, int drop) {
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    return (q(u) - p(u)) * (r(v) - p(v)) - (q(v) - p(v)) * (r(u) - p(u));
  }

  // p inside or on the triangle (a, b, c) of unit normal n (p in its plane), within tol_.
  bool inside(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, const Vec3& p) const {
    const std::array<Vec3, 3> v{a, b, c};
    for (int e = 0; e < 3; ++e) {
      const Vec3& s = v[static_cast<std::size_t>(e)];
      const Vec3& t = v[static_cast<std::size_t>((e + 1) % 3)];
      const Vec3 edge = t - s;
      // Distance of p to the edge's line, positive towards the triangle's inside.
      const double d = n.cross(edge).dot(p - s) / edge.norm();
      if (d < -tol_) return false;
    }
    return true;
  }

  // 2-D segments (p, q) and (a, b) in the plane dropped along `drop` meet (within tol_ · length).
  bool segments_meet(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, int drop) const {
    const double l1 = (q - p).norm(), l2 = (b - a).norm();
    const double o1 = orient(p, q, a, drop) / l1, o2 = orient(p, q, b, drop) / l1;
    const double o3 = orient(a, b, p, drop) / l2, o4 = orient(a, b, q, drop) / l2;
    auto sign = [&](double o) { return o > tol_ ? 1 : (o < -tol_ ? -1 : 0); };
    const int s1 = sign(o1), s2 = sign(o2), s3 = sign(o3), s4 = sign(o4);
    if (s1 * s2 > 0 || s3 * s4 > 0) return false;
    if (s1 == 0 && s2 == 0) {  // collinear: do the intervals overlap?
      const Vec3 d = (q - p) / l1;
      const double ta = d.dot(a - p), tb = d.dot(b - p);
      return std::max(ta, tb) >= -tol_ && std::min(ta, tb) <= l1 + tol_;
    }
    return true;
  }

  // The segment (p, q) meets the triangle (a, b, c).
  bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                              const Vec3& c) const {
    const Vec3 normal = (b - a).cross(c - a);
    const double area2 = normal.norm();
    if (!(area2 > 0.0)) return false;  // degenerate faces are refused before this search
    const Vec3 n = normal / area2;
    const double dp = plane_distance(a, n, p), dq = plane_distance(a, n, q);
    if ((dp > tol_ && dq > tol_) || (dp < -tol_ && dq < -tol_)) return false;
    if (std::abs(dp) <= tol_ && std::abs(dq) <= tol_) {  // in the plane: a 2-D test
      int drop = 0;
      n.cwiseAbs().maxCoeff(&drop);
      if (inside(a, b, c, n, p) || inside(a, b, c, n, q)) return true;
      return segments_meet(p, q, a, b, drop) || segments_meet(p, q, b, c, drop) ||
             segments_meet(p, q, c, a, drop);
    }
    const double s = dp / (dp - dq);
    const Vec3 x = p + std::clamp(s, 0.0, 1.0) * (q - p);
    return inside(a, b, c, n, x);
  }

  bool triangles_meet(std::size_t f, std::size_t g) const {
    const auto& F = mesh_.faces[f];
    const auto& G = mesh_.faces[g];
    int shared = 0;
    std::array<int, 3> f_in_g{-1, -1, -1};  // for each vertex of f, its place in g
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (F[static_cast<std::size_t>(i)] == G[static_cast<std::size_t>(j)]) f_in_g[static_cast<std::size_t>(i)] = j, ++shared;
    const Vec3 a = vertex(f, 0), b = vertex(f, 1), c = vertex(f, 2);
    const Vec3 p = vertex(g, 0), q = vertex(g, 1), r = vertex(g, 2);
    if (shared == 3) return true;  // the same triangle twice
    if (shared == 2) {             // folded onto each other?
      int i = 0, j = 0;            // the vertex of f and of g off the shared edge
      while (f_in_g[static_cast<std::size_t>(i)] >= 0) ++i;
      std::array<bool, 3> used{false, false, false};
      for (int k : f_in_g)
        if (k >= 0) used[static_cast<std::size_t>(k)] = true;
      while (used[static_cast<std::size_t>(j)]) ++j;
      const Vec3 u = vertex(f, (i + 1) % 3), v = vertex(f, (i + 2) % 3);
      const Vec3 off_f = vertex(f, i), off_g = vertex(g, j);
      const Vec3 normal = (v - u).cross(off_f - u);
      const Vec3 n = normal / normal.norm();
      if (std::abs(plane_distance(u, n, off_g)) > tol_) return false;
      const Vec3 across = n.cross(v - u);  // in the plane, perpendicular to the shared edge
      return across.dot(off_f - u) * across.dot(off_g - u) > 0.0;
    }
    if (shared == 1) {
      int i = 0;
      while (f_in_g[static_cast<std::size_t>(i)] < 0) ++i;
      const int j = f_in_g[static_cast<std::size_t>(i)];
      return segment_meets_triangle(vertex(f, (i + 1) % 3), vertex(f, (i + 2) % 3), p, q, r) ||
             segment_meets_triangle(vertex(g, (j + 1) % 3), vertex(g, (j + 2) % 3), a, b, c);
    }
    return segment_meets_triangle(a, b, p, q, r) || segment_meets_triangle(b, c, p, q, r) ||
           segment_meets_triangle(c, a, p, q, r) || segment_meets_triangle(p, q, a, b, c) ||
           segment_meets_triangle(q, r, a, b, c) || segment_meets_triangle(r, p, a, b, c);
  }

  const Mesh& mesh_;
  double tol_;
  std::vector<Box> boxes_;
  std::vector<Vec3> centroids_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  std::size_t tests_ = 0;
  std::optional<std::pair<std::size_t, std::size_t>> found_;
};

}  // namespace

std::optional<std::pair<std::size_t, std::size_t>> find_self_intersection(const Mesh& mesh) {
  if (mesh.faces.empty()) return std::nullopt;
  const double size = (mesh.vertices.rowwise().maxCoeff() - mesh.vertices.rowwise().minCoeff()).maxCoeff();
  return Search(mesh, kSelfIntersectionTolerance * size).run();
}

}  // namespace noether
