#include "core/order/offending_sort.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <optional>

#include "core/geom/clip.h"
#include "core/overlap/penumbra_volume.h"

namespace penumbra {

namespace {

bool anyVertexBehind(const Polygon3& polygon, const Plane& plane, double eps) {
  return std::any_of(polygon.begin(), polygon.end(),
                     [&](const Vec3& p) { return plane.signedDistance(p) < -eps; });
}

bool spans(const Polygon3& polygon, const Plane& plane, double eps) {
  bool front = false, back = false;
  for (const Vec3& p : polygon) {
    const double d = plane.signedDistance(p);
    front |= d > eps;
    back |= d < -eps;
  }
  return front && back;
}

// Per-fragment data reused by every pair test.
struct Prepared {
  Polygon3 litFrom;  // the light's part strictly in front of the fragment
  std::optional<PenumbraVolume> volume;  // from all of litFrom (a superset region)
};

Prepared prepare(const PlanarFragment& f, const Polygon3& light, const Tolerance& tolerance) {
  Prepared p;
  p.litFrom = clipFront(light, f.plane, tolerance.length());
  if (!p.litFrom.empty()) p.volume = penumbraVolume(f.polygon, f.plane, p.litFrom, tolerance, VolumeMargin::Tight);
  return p;
}

// The pair test; `pa` speeds up the common rejections with a's own lit part.
bool precedes(const PlanarFragment& a, const Prepared& pa, const PlanarFragment& b,
              const Tolerance& tolerance) {
  const double eps = tolerance.length();
  if (pa.litFrom.empty() || !pa.volume) return false;
  if (!anyVertexBehind(b.polygon, a.plane, eps)) return false;
  // The coarse test below would say so; no allocation: the test runs for every pair of offending
  // fragments (a scanned model's thousands of side faces), and most pairs end here.
  if (pa.volume->outsideABound(b.polygon)) return false;
  // Rays must leave light points in front of b too.
  const Polygon3 lit = clipFront(pa.litFrom, b.plane, eps);
  if (lit.empty()) return false;
  // Coarse: the penumbra volume from all of a's lit part contains the exact one.
  if (pa.volume->clipInside(b.polygon, eps).empty()) return false;
  if (lit.size() == pa.litFrom.size() &&
      std::equal(lit.begin(), lit.end(), pa.litFrom.begin()))
    return true;
  const auto exact = penumbraVolume(a.polygon, a.plane, lit, tolerance, VolumeMargin::Tight);
  return exact && !exact->clipInside(b.polygon, eps).empty();
}

// Tarjan's strongly connected components; returns the component of each vertex.
std::vector<int> components(const std::vector<std::vector<int>>& edges, int* count) {
  const int n = static_cast<int>(edges.size());
  std::vector<int> index(n, -1), low(n, 0), component(n, -1), stack;
  std::vector<bool> onStack(n, false);
  int nextIndex = 0;
  *count = 0;
  // Iterative DFS: (vertex, next edge position).
  std::vector<std::pair<int, size_t>> dfs;
  for (int start = 0; start < n; ++start) {
    if (index[start] >= 0) continue;
    dfs.push_back({start, 0});
    index[start] = low[start] = nextIndex++;
    stack.push_back(start);
    onStack[start] = true;
    while (!dfs.empty()) {
      auto& [v, pos] = dfs.back();
      if (pos < edges[v].size()) {
        const int w = edges[v][pos++];
        if (index[w] < 0) {
          index[w] = low[w] = nextIndex++;
          stack.push_back(w);
          onStack[w] = true;
          dfs.push_back({w, 0});
        } else if (onStack[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      const int done = v;
      dfs.pop_back();
      if (!dfs.empty()) low[dfs.back().first] = std::min(low[dfs.back().first], low[done]);
      if (low[done] == index[done]) {
        int w;
        do {
          w = stack.back();
          stack.pop_back();
          onStack[w] = false;
          component[w] = *count;
        } while (w != done);
        ++*count;
      }
    }
  }
  return component;
}

}  // namespace

bool mayPrecede(const PlanarFragment& a, const PlanarFragment& b, const Polygon3& light,
                const Tolerance& tolerance) {
  return precedes(a, prepare(a, light, tolerance), b, tolerance);
}

OffendingOrder sortOffending(std::vector<PlanarFragment> fragments, const Polygon3& light,
                             const Tolerance& tolerance) {
  const double eps = tolerance.length();
  OffendingOrder result;
  // Splitting stops at full mutual splitting; the budget only guards pathological input.
  const size_t splitBudget = 8 * fragments.size() + 64;
  std::vector<std::vector<int>> edges;
  std::vector<int> component;
  int componentCount = 0;
  for (;;) {
    const int n = static_cast<int>(fragments.size());
    std::vector<Prepared> prepared;
    prepared.reserve(n);
    for (const auto& f : fragments) prepared.push_back(prepare(f, light, tolerance));
    edges.assign(n, {});
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j && fragments[i].face != fragments[j].face &&
            precedes(fragments[i], prepared[i], fragments[j], tolerance))
          edges[i].push_back(j);
    component = components(edges, &componentCount);
    if (componentCount == n || result.splits >= splitBudget) break;

    // Open each cycle group with the member whose plane cuts fewest other members.
    std::vector<std::vector<int>> members(componentCount);
    for (int i = 0; i < n; ++i) members[component[i]].push_back(i);
    std::vector<bool> splitBy(n, false);  // splitBy[j]: split j by pivot[component[j]]
    std::vector<int> pivot(componentCount, -1);
    bool anySplit = false;
    for (int c = 0; c < componentCount; ++c) {
      if (members[c].size() < 2) continue;
      size_t best = SIZE_MAX;
      for (int p : members[c]) {
        size_t cuts = 0;
        for (int q : members[c])
          if (q != p && spans(fragments[q].polygon, fragments[p].plane, eps)) ++cuts;
        if (cuts > 0 && cuts < best) {
          best = cuts;
          pivot[c] = p;
        }
      }
      if (pivot[c] < 0) continue;
      for (int q : members[c])
        if (q != pivot[c] && spans(fragments[q].polygon, fragments[pivot[c]].plane, eps)) {
          splitBy[q] = true;
          anySplit = true;
        }
    }
    if (!anySplit) break;
    std::vector<PlanarFragment> next;
    next.reserve(fragments.size() + 8);
    for (int i = 0; i < n; ++i) {
      if (!splitBy[i]) {
        next.push_back(std::move(fragments[i]));
        continue;
      }
      const Split3 split =
          splitByPlane(fragments[i].polygon, fragments[pivot[component[i]]].plane, eps);
      next.push_back({fragments[i].face, split.front, fragments[i].plane});
      next.push_back({fragments[i].face, split.back, fragments[i].plane});
      ++result.splits;
    }
    fragments = std::move(next);
  }

  // Kahn's sort, nearest-to-the-light first among the free; a cycle left over is
  // broken at its nearest member.
  const int n = static_cast<int>(fragments.size());
  Vec3 lightCenter = centroid(light);
  std::vector<double> key(n);
  for (int i = 0; i < n; ++i) key[i] = glm::length(centroid(fragments[i].polygon) - lightCenter);
  std::vector<int> indegree(n, 0);
  for (int i = 0; i < n; ++i)
    for (int j : edges[i]) ++indegree[j];
  std::vector<bool> placed(n, false);
  std::vector<int> order;
  order.reserve(n);
  auto better = [&](int x, int y) { return key[x] < key[y] || (key[x] == key[y] && x < y); };
  std::vector<bool> brokenComponent(componentCount, false);
  while (static_cast<int>(order.size()) < n) {
    int pick = -1;
    for (int i = 0; i < n; ++i)
      if (!placed[i] && indegree[i] == 0 && (pick < 0 || better(i, pick))) pick = i;
    if (pick < 0) {
      for (int i = 0; i < n; ++i)
        if (!placed[i] && (pick < 0 || better(i, pick))) pick = i;
      if (!brokenComponent[component[pick]]) {
        brokenComponent[component[pick]] = true;
        ++result.cyclesBroken;
      }
    }
    placed[pick] = true;
    order.push_back(pick);
    for (int j : edges[pick]) --indegree[j];
  }
  result.fragments.reserve(n);
  for (int i : order) result.fragments.push_back(std::move(fragments[i]));
  return result;
}

}  // namespace penumbra
