#include "core/dmtree/single_tree.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

Polygon2 withoutShortEdges(const Polygon2& polygon, double eps) {
  Polygon2 out;
  for (const Vec2& p : polygon)
    if (out.empty() || glm::length(p - out.back()) > eps) out.push_back(p);
  while (out.size() > 1 && glm::length(out.front() - out.back()) <= eps) out.pop_back();
  if (out.size() < 3 || !(signedArea(out) > 0)) return {};
  return out;
}

namespace {

using Region = SingleTreeNode::Region;

int addLeaf(SingleTree& tree, Region region) {
  SingleTreeNode leaf;
  leaf.region = region;
  tree.nodes.push_back(leaf);
  return static_cast<int>(tree.nodes.size() - 1);
}

// A polygon edge p→q as a node, taking its generator from a collinear overlapping
// segment of the expected kind (generators, not coordinates, identify it downstream).
SingleTreeNode edgeNode(const Vec2& p, const Vec2& q, SegmentKind kind, const SingleShadow& shadow,
                        double eps) {
  SingleTreeNode node;
  node.line = Line2::rightOf(p, q);
  node.a = p;
  node.b = q;
  node.kind = kind;
  const Vec2 dir = (q - p) / glm::length(q - p);
  for (const CriticalSegment& s : shadow.segments) {
    if (s.kind != kind) continue;
    if (std::abs(node.line.distance(s.a)) > eps || std::abs(node.line.distance(s.b)) > eps) continue;
    const double ta = glm::dot(s.a - p, dir), tb = glm::dot(s.b - p, dir);
    const double overlap = std::min(std::max(ta, tb), glm::length(q - p)) - std::max(std::min(ta, tb), 0.0);
    if (overlap <= eps) continue;
    node.lightElement = s.lightElement;
    node.occluderElement = s.occluderElement;
    node.generated = true;
    break;
  }
  return node;
}

// Filters the segment a→b down from node `at`, splitting it where it crosses a node's
// line, and hangs each piece at the leaf it reaches.
void filterDown(SingleTree& tree, int at, const Vec2& a, const Vec2& b, const CriticalSegment& s,
                double eps) {
  if (!(glm::length(b - a) > eps)) return;
  if (tree.nodes[at].region != Region::None) {
    const Region region = tree.nodes[at].region;
    const int front = addLeaf(tree, region), back = addLeaf(tree, region);
    SingleTreeNode& node = tree.nodes[at];
    node.region = Region::None;
    node.line = Line2::rightOf(a, b);
    node.a = a;
    node.b = b;
    node.kind = s.kind;
    node.lightElement = s.lightElement;
    node.occluderElement = s.occluderElement;
    node.generated = true;
    node.front = front;
    node.back = back;
    return;
  }
  const SingleTreeNode node = tree.nodes[at];
  const double da = node.line.distance(a), db = node.line.distance(b);
  if (da >= -eps && db >= -eps) return filterDown(tree, node.front, a, b, s, eps);  // collinear too
  if (da <= eps && db <= eps) return filterDown(tree, node.back, a, b, s, eps);
  const Vec2 cut = a + (da / (da - db)) * (b - a);
  filterDown(tree, da > 0 ? node.front : node.back, a, cut, s, eps);
  filterDown(tree, db > 0 ? node.front : node.back, cut, b, s, eps);
}

}  // namespace

std::vector<KeptSegment> SingleTree::segments() const {
  // Exact size: every inserted shadow keeps its segments as long as it stays in the tree.
  std::vector<KeptSegment> out;
  out.reserve(size_t(std::count_if(nodes.begin(), nodes.end(),
                                   [](const SingleTreeNode& n) { return n.region == Region::None; })));
  for (const SingleTreeNode& n : nodes)
    if (n.region == Region::None) out.push_back({n.a, n.b, n.kind});
  return out;
}

SingleTree buildSingleTree(const SingleShadow& shadow, const Tolerance& tolerance,
                           const std::function<void()>& beat) {
  const double eps = tolerance.length();
  SingleTree tree;
  tree.penumbra = withoutShortEdges(shadow.penumbra, eps);
  if (tree.penumbra.empty()) return tree;
  tree.umbra = withoutShortEdges(shadow.umbra, eps);

  // Penumbra chain: front of each edge is lit, the back continues inside.
  int hook = -1;  // the node whose back receives the next node; -1: the root
  auto attach = [&](int id) { (hook < 0 ? tree.root : tree.nodes[hook].back) = id; };
  const size_t np = tree.penumbra.size();
  for (size_t i = 0; i < np; ++i) {
    tree.nodes.push_back(edgeNode(tree.penumbra[i], tree.penumbra[(i + 1) % np], SegmentKind::Penumbra,
                                  shadow, eps));
    const int id = static_cast<int>(tree.nodes.size() - 1);
    attach(id);
    const int out = addLeaf(tree, Region::Out);
    tree.nodes[id].front = out;
    hook = id;
  }
  // Umbra chain behind it: front of each umbra edge is penumbra, the final back is umbra.
  int firstUmbra = -1;
  const size_t nu = tree.umbra.size();
  for (size_t i = 0; i < nu; ++i) {
    tree.nodes.push_back(edgeNode(tree.umbra[i], tree.umbra[(i + 1) % nu], SegmentKind::Umbra, shadow, eps));
    const int id = static_cast<int>(tree.nodes.size() - 1);
    if (firstUmbra < 0) firstUmbra = id;
    attach(id);
    const int pen = addLeaf(tree, Region::Penumbra);
    tree.nodes[id].front = pen;
    hook = id;
  }
  const int last = addLeaf(tree, nu > 0 ? Region::Umbra : Region::Penumbra);
  attach(last);
  // Internal (EV/VE) and contact segments lie behind every penumbra node.
  const int start = firstUmbra >= 0 ? firstUmbra : last;
  for (size_t i = 0; i < shadow.segments.size(); ++i) {
    const CriticalSegment& s = shadow.segments[i];
    if (s.kind == SegmentKind::Internal || s.kind == SegmentKind::Contact)
      filterDown(tree, start, s.a, s.b, s, eps);
    if (beat && i % kSegmentsPerBeat == kSegmentsPerBeat - 1) beat();
  }
  return tree;
}

}  // namespace penumbra
