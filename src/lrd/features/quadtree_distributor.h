#pragma once
// Picks a requested number of keypoints spread evenly over an image region, the strongest one in
// each cell of a quadtree (the idea of ORB-SLAM2's DistributeOctTree, Mur-Artal & Tardos 2017):
// an image with texture in one corner must not spend its whole budget there.
#include <opencv2/core.hpp>
#include <vector>

namespace lrd::features {

class QuadtreeDistributor {
 public:
  // Indices (ascending) of at most `count` of `points` inside `area`: cells split breadth-first,
  // the most populated cell first within a depth, until there are `count` non-empty cells or no
  // cell holds two points; each cell then keeps its highest-response point, and when splitting
  // overshoots, the surplus goes from the smallest cells. Ties break on index: deterministic.
  // Points outside `area` are never chosen. Reuses its buffers between calls (not thread-safe).
  std::vector<int> select(const std::vector<cv::KeyPoint>& points, const cv::Rect2f& area, int count);

 private:
  struct Node {
    float x0, y0, x1, y1;
    int begin, end;  // range in order_
    int depth;
  };
  void split(const Node& node, std::vector<Node>& children);

  std::vector<int> order_;  // point indices, each node's points contiguous
  const std::vector<cv::KeyPoint>* points_ = nullptr;
};

}  // namespace lrd::features
