#include "lrd/features/quadtree_distributor.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>
#include <utility>

namespace lrd::features {

void QuadtreeDistributor::split(const Node& node, std::vector<Node>& children) {
  const float mx = 0.5f * (node.x0 + node.x1);
  const float my = 0.5f * (node.y0 + node.y1);
  const auto& pts = *points_;
  auto* first = order_.data() + node.begin;
  auto* last = order_.data() + node.end;
  // Top half then bottom half, each split into left then right: four contiguous ranges.
  auto* mid_y = std::partition(first, last, [&](int i) { return pts[i].pt.y < my; });
  auto* mid_top = std::partition(first, mid_y, [&](int i) { return pts[i].pt.x < mx; });
  auto* mid_bottom = std::partition(mid_y, last, [&](int i) { return pts[i].pt.x < mx; });
  const int base = static_cast<int>(first - order_.data());
  auto add = [&](float x0, float y0, float x1, float y1, const int* b, const int* e) {
    if (b != e) {
      children.push_back({x0, y0, x1, y1, base + static_cast<int>(b - first),
                          base + static_cast<int>(e - first), node.depth + 1});
    }
  };
  add(node.x0, node.y0, mx, my, first, mid_top);
  add(mx, node.y0, node.x1, my, mid_top, mid_y);
  add(node.x0, my, mx, node.y1, mid_y, mid_bottom);
  add(mx, my, node.x1, node.y1, mid_bottom, last);
}

std::vector<int> QuadtreeDistributor::select(const std::vector<cv::KeyPoint>& points, const cv::Rect2f& area,
                                             int count) {
  points_ = &points;
  order_.clear();
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const cv::Point2f& p = points[i].pt;
    if (p.x >= area.x && p.y >= area.y && p.x < area.x + area.width && p.y < area.y + area.height) {
      order_.push_back(i);
    }
  }
  if (count <= 0 || order_.empty()) return {};

  // Roots: a row of near-square cells, so that splitting keeps cells near square.
  std::vector<Node> nodes;
  const int n_roots = std::max(1, static_cast<int>(std::lround(area.width / std::max(area.height, 1.0f))));
  {
    const float w = area.width / static_cast<float>(n_roots);
    std::vector<int>::iterator begin = order_.begin();
    for (int r = 0; r < n_roots; ++r) {
      const float x1 = r + 1 == n_roots ? area.x + area.width : area.x + w * static_cast<float>(r + 1);
      auto end = r + 1 == n_roots
                     ? order_.end()
                     : std::partition(begin, order_.end(), [&](int i) { return points[i].pt.x < x1; });
      if (begin != end) {
        nodes.push_back({area.x + w * static_cast<float>(r), area.y, x1, area.y + area.height,
                         static_cast<int>(begin - order_.begin()), static_cast<int>(end - order_.begin()),
                         0});
      }
      begin = end;
    }
  }

  // Splittable cells by (shallowest, most points, oldest): breadth-first refinement keeps the
  // cells of one depth equal in size, so the density of the kept points follows the texture only
  // through the last, partial round.
  auto size_of = [&](int n) { return nodes[n].end - nodes[n].begin; };
  auto later = [&](int a, int b) {
    return std::make_tuple(nodes[a].depth, -size_of(a), a) > std::make_tuple(nodes[b].depth, -size_of(b), b);
  };
  std::priority_queue<int, std::vector<int>, decltype(later)> open(later);
  auto splittable = [&](int n) { return size_of(n) > 1 && nodes[n].x1 - nodes[n].x0 > 1.0f; };
  std::vector<char> is_leaf(nodes.size(), 1);
  for (int n = 0; n < static_cast<int>(nodes.size()); ++n) {
    if (splittable(n)) open.push(n);
  }
  int leaves = static_cast<int>(nodes.size());
  std::vector<Node> children;
  while (leaves < count && !open.empty()) {
    const int n = open.top();
    open.pop();
    children.clear();
    split(nodes[n], children);
    is_leaf[n] = 0;
    leaves += static_cast<int>(children.size()) - 1;
    for (const Node& c : children) {
      nodes.push_back(c);
      is_leaf.push_back(1);
      if (splittable(static_cast<int>(nodes.size()) - 1)) open.push(static_cast<int>(nodes.size()) - 1);
    }
  }

  // The strongest point of each leaf (ties to the lower index). The last split may overshoot by two
  // cells; the surplus comes out of the smallest cells, the weakest first, so isolated corners in
  // sparse regions survive.
  auto stronger = [&](int a, int b) {
    return points[a].response > points[b].response || (points[a].response == points[b].response && a < b);
  };
  std::vector<std::pair<int, int>> winners;  // (depth, point index)
  winners.reserve(leaves);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!is_leaf[n]) continue;
    winners.emplace_back(nodes[n].depth, *std::min_element(order_.begin() + nodes[n].begin,
                                                           order_.begin() + nodes[n].end, stronger));
  }
  if (static_cast<int>(winners.size()) > count) {
    std::sort(winners.begin(), winners.end(), [&](const auto& a, const auto& b) {
      return a.first < b.first || (a.first == b.first && stronger(a.second, b.second));
    });
    winners.resize(count);
  }
  std::vector<int> kept;
  kept.reserve(winners.size());
  for (const auto& w : winners) kept.push_back(w.second);
  std::sort(kept.begin(), kept.end());
  return kept;
}

}  // namespace lrd::features
