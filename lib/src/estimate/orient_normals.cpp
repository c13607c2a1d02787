#include "orient_normals.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pnf::detail {

namespace {

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void flip(Vec3& v) {
  v[0] = -v[0];
  v[1] = -v[1];
  v[2] = -v[2];
}

// Flips normals[i] where normals[i] · direction(i) < 0, in parallel; each iteration touches only
// its own point, so the result does not depend on the thread count.
template <class Direction>
void flip_against(const Direction& direction, std::vector<Vec3>& normals) {
  const auto count = static_cast<std::int64_t>(normals.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i) {
    if (dot(normals[i], direction(i)) < 0.0) flip(normals[i]);
  }
}

// An edge of the symmetric neighbour graph with Hoppe's weight 1 − |n_a · n_b|, a < b. The weight
// is stored as float (12 bytes per edge instead of 16, for N k edges): rounding it can only
// reorder edges whose weights agree to about 1e-7 relative, which are equally good tree edges.
struct Edge {
  float weight;
  int a;
  int b;
};

// Lightest first; equal weights by endpoint ids, so that the order is total and the tree (and
// every flip that follows from it) is the same on every run and platform.
bool lighter(const Edge& x, const Edge& y) {
  if (x.weight != y.weight) return x.weight < y.weight;
  if (x.a != y.a) return x.a < y.a;
  return x.b < y.b;
}

bool row_contains(const NeighbourTable& neighbours, std::size_t point, int other) {
  const int* row = neighbours.row(point);
  return std::find(row, row + neighbours.k, other) != row + neighbours.k;
}

// Each undirected edge once: i–j is listed from i's row, and from j's row too when the
// relation is mutual, so the copy with i > j is skipped in that case. Rows are processed in
// parallel in two passes (count, then fill at a prefix-sum offset), so the list comes out in the
// same order for any thread count.
std::vector<Edge> weighted_edges(const NeighbourTable& neighbours, const std::vector<Vec3>& normals) {
  const std::size_t count = neighbours.point_count;
  const auto rows = static_cast<std::int64_t>(count);
  const auto listed_here = [&](std::size_t i, int j) {
    const auto other = static_cast<std::size_t>(j);
    return !(other < i && row_contains(neighbours, other, static_cast<int>(i)));
  };

  std::vector<std::size_t> offsets(count + 1, 0);
#pragma omp parallel for schedule(static)
  for (std::int64_t r = 0; r < rows; ++r) {
    const auto i = static_cast<std::size_t>(r);
    const int* row = neighbours.row(i);
    std::size_t kept = 0;
    for (int slot = 0; slot < neighbours.k; ++slot) kept += listed_here(i, row[slot]) ? 1 : 0;
    offsets[i + 1] = kept;
  }
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());

  std::vector<Edge> edges(offsets[count]);
#pragma omp parallel for schedule(static)
  for (std::int64_t r = 0; r < rows; ++r) {
    const auto i = static_cast<std::size_t>(r);
    const int* row = neighbours.row(i);
    std::size_t next = offsets[i];
    for (int slot = 0; slot < neighbours.k; ++slot) {
      if (!listed_here(i, row[slot])) continue;
      const auto other = static_cast<std::size_t>(row[slot]);
      const double weight = 1.0 - std::abs(dot(normals[i], normals[other]));
      edges[next++] =
          Edge{static_cast<float>(weight), static_cast<int>(std::min(i, other)), static_cast<int>(std::max(i, other))};
    }
  }
  return edges;
}

// Sorts by `lighter`: one slice per thread sorted in parallel, then merged pairwise. `lighter`
// is a strict total order on distinct edges, so the result is the same for any slicing.
void sort_edges(std::vector<Edge>& edges) {
#ifdef _OPENMP
  const auto parts = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
#else
  const std::size_t parts = 1;
#endif
  std::vector<std::size_t> bounds(parts + 1);
  for (std::size_t p = 0; p <= parts; ++p) bounds[p] = edges.size() * p / parts;
  const auto begin = edges.begin();
#pragma omp parallel for schedule(static, 1)
  for (std::int64_t p = 0; p < static_cast<std::int64_t>(parts); ++p) {
    const auto part = static_cast<std::size_t>(p);
    std::sort(begin + static_cast<std::ptrdiff_t>(bounds[part]), begin + static_cast<std::ptrdiff_t>(bounds[part + 1]),
              lighter);
  }
  for (std::size_t width = 1; width < parts; width *= 2) {
    for (std::size_t p = 0; p + width < parts; p += 2 * width) {
      std::inplace_merge(begin + static_cast<std::ptrdiff_t>(bounds[p]),
                         begin + static_cast<std::ptrdiff_t>(bounds[p + width]),
                         begin + static_cast<std::ptrdiff_t>(bounds[std::min(p + 2 * width, parts)]), lighter);
    }
  }
}

// Disjoint sets over point ids with path halving and union by size: near-constant time per
// operation, so Kruskal's cost is the sort.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t count) : parent_(count), size_(count, 1) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }

  int find(int x) {
    while (parent_[static_cast<std::size_t>(x)] != x) {
      int& up = parent_[static_cast<std::size_t>(x)];
      up = parent_[static_cast<std::size_t>(up)];
      x = up;
    }
    return x;
  }

  // Joins the sets of a and b; returns false when they were already one.
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size_[static_cast<std::size_t>(a)] < size_[static_cast<std::size_t>(b)]) std::swap(a, b);
    parent_[static_cast<std::size_t>(b)] = a;
    size_[static_cast<std::size_t>(a)] += size_[static_cast<std::size_t>(b)];
    return true;
  }

 private:
  std::vector<int> parent_;
  std::vector<std::size_t> size_;
};

// Compressed adjacency of the spanning forest: the tree neighbours of point i are
// targets[offsets[i], offsets[i + 1]).
struct Forest {
  std::vector<std::size_t> offsets;  // N + 1
  std::vector<int> targets;          // 2 (N − components)
};

Forest forest_adjacency(std::size_t count, const std::vector<Edge>& tree_edges) {
  Forest forest;
  forest.offsets.assign(count + 1, 0);
  for (const Edge& e : tree_edges) {
    ++forest.offsets[static_cast<std::size_t>(e.a) + 1];
    ++forest.offsets[static_cast<std::size_t>(e.b) + 1];
  }
  std::partial_sum(forest.offsets.begin(), forest.offsets.end(), forest.offsets.begin());
  forest.targets.resize(forest.offsets[count]);
  std::vector<std::size_t> cursor(forest.offsets.begin(), forest.offsets.end() - 1);
  for (const Edge& e : tree_edges) {
    forest.targets[cursor[static_cast<std::size_t>(e.a)]++] = e.b;
    forest.targets[cursor[static_cast<std::size_t>(e.b)]++] = e.a;
  }
  return forest;
}

}  // namespace

void orient_towards_viewpoint(const std::vector<Vec3>& positions, const Vec3& viewpoint, std::vector<Vec3>& normals) {
  flip_against(
      [&](std::int64_t i) {
        const Vec3& p = positions[static_cast<std::size_t>(i)];
        return Vec3{viewpoint[0] - p[0], viewpoint[1] - p[1], viewpoint[2] - p[2]};
      },
      normals);
}

void orient_outward(const std::vector<Vec3>& positions, std::vector<Vec3>& normals) {
  // A sequential sum, so that the centroid (and every sign that depends on it) does not change
  // with the thread count.
  Vec3 centroid = {0.0, 0.0, 0.0};
  for (const Vec3& p : positions) {
    for (int axis = 0; axis < 3; ++axis) centroid[axis] += p[axis];
  }
  for (int axis = 0; axis < 3; ++axis) centroid[axis] /= static_cast<double>(positions.size());
  flip_against(
      [&](std::int64_t i) {
        const Vec3& p = positions[static_cast<std::size_t>(i)];
        return Vec3{p[0] - centroid[0], p[1] - centroid[1], p[2] - centroid[2]};
      },
      normals);
}

void orient_by_mst(const std::vector<Vec3>& positions, const NeighbourTable& neighbours, std::vector<Vec3>& normals) {
  const std::size_t count = positions.size();

  // Kruskal: the lightest edges that join two different trees form the minimum spanning forest.
  std::vector<Edge> edges = weighted_edges(neighbours, normals);
  sort_edges(edges);
  DisjointSets components(count);
  std::vector<Edge> tree_edges;
  tree_edges.reserve(count);
  for (const Edge& e : edges) {
    if (components.unite(e.a, e.b)) tree_edges.push_back(e);
  }
  edges = std::vector<Edge>();  // the largest buffer; free it before the traversal allocates
  const Forest forest = forest_adjacency(count, tree_edges);

  // The seed of each component: its largest-z point, ties by smallest id.
  std::vector<int> seed_of_root(count, -1);
  for (std::size_t i = 0; i < count; ++i) {
    const auto root = static_cast<std::size_t>(components.find(static_cast<int>(i)));
    const int best = seed_of_root[root];
    if (best < 0 || positions[i][2] > positions[static_cast<std::size_t>(best)][2]) {
      seed_of_root[root] = static_cast<int>(i);
    }
  }

  // Breadth-first from each seed; every point is compared with its tree parent, whose sign is
  // already final.
  std::vector<char> reached(count, 0);
  std::vector<int> queue;
  queue.reserve(count);
  for (std::size_t root = 0; root < count; ++root) {
    const int seed = seed_of_root[root];
    if (seed < 0) continue;
    Vec3& seed_normal = normals[static_cast<std::size_t>(seed)];
    if (seed_normal[2] < 0.0) flip(seed_normal);
    reached[static_cast<std::size_t>(seed)] = 1;
    queue.push_back(seed);
    for (std::size_t head = queue.size() - 1; head < queue.size(); ++head) {
      const auto parent = static_cast<std::size_t>(queue[head]);
      for (std::size_t e = forest.offsets[parent]; e < forest.offsets[parent + 1]; ++e) {
        const auto child = static_cast<std::size_t>(forest.targets[e]);
        if (reached[child]) continue;
        reached[child] = 1;
        if (dot(normals[child], normals[parent]) < 0.0) flip(normals[child]);
        queue.push_back(static_cast<int>(child));
      }
    }
  }
}

}  // namespace pnf::detail
