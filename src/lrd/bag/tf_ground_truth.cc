#include "lrd/bag/tf_ground_truth.h"

#include <fmt/format.h>

#include <set>
#include <vector>

#include "lrd/util/error.h"

namespace lrd::bag {

namespace {

std::string without_slash(const std::string& frame) {
  return !frame.empty() && frame.front() == '/' ? frame.substr(1) : frame;
}

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double ratio) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = a.translation() + (b.translation() - a.translation()) * ratio;
  T.linear() = Eigen::Quaterniond(a.linear()).slerp(ratio, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  return T;
}

}  // namespace

void TfGroundTruth::add(const std::string& parent, const std::string& child, const Stamp& stamp,
                        const Eigen::Isometry3d& parent_from_child, bool is_static) {
  Link& link = links_[without_slash(child)];
  link.parent = without_slash(parent);
  if (is_static)
    link.fixed = parent_from_child;
  else
    link.by_stamp_ns[to_nanoseconds(stamp)] = parent_from_child;
  ++transforms_;
}

std::optional<Eigen::Isometry3d> TfGroundTruth::link_at(const Link& link, std::int64_t t_ns) {
  if (link.fixed) return link.fixed;
  const auto& samples = link.by_stamp_ns;
  const auto after = samples.lower_bound(t_ns);
  if (after != samples.end() && after->first == t_ns) return after->second;
  if (after == samples.end() || after == samples.begin()) return std::nullopt;  // no extrapolation
  const auto before = std::prev(after);
  const double ratio =
      static_cast<double>(t_ns - before->first) / static_cast<double>(after->first - before->first);
  return interpolate(before->second, after->second, ratio);
}

std::optional<Eigen::Isometry3d> TfGroundTruth::pose_in(const std::string& ancestor, const std::string& frame,
                                                        std::int64_t t_ns) const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  std::set<std::string> seen;
  for (std::string f = frame; f != ancestor;) {
    const auto link = links_.find(f);
    if (link == links_.end() || !seen.insert(f).second) return std::nullopt;
    const auto step = link_at(link->second, t_ns);
    if (!step) return std::nullopt;
    pose = *step * pose;
    f = link->second.parent;
  }
  return pose;
}

std::optional<Eigen::Isometry3d> TfGroundTruth::lookup(const std::string& parent, const std::string& child,
                                                       std::int64_t t_ns) const {
  // Through the nearest frame above both (the parent itself in the usual world -> camera case).
  std::set<std::string> seen;
  for (std::string above = parent; seen.insert(above).second;) {
    const auto child_pose = pose_in(above, child, t_ns);
    if (child_pose) {
      const auto parent_pose = pose_in(above, parent, t_ns);
      if (!parent_pose) return std::nullopt;
      return parent_pose->inverse() * *child_pose;
    }
    const auto link = links_.find(above);
    if (link == links_.end()) return std::nullopt;
    above = link->second.parent;
  }
  return std::nullopt;
}

io::Trajectory TfGroundTruth::trajectory(const std::filesystem::path& file, const BagTopics& t) const {
  if (transforms_ == 0) throw file_error(file, "--gt-from-tf: the bag has no /tf messages");
  const std::string parent = without_slash(t.gt_parent), child = without_slash(t.gt_child);
  std::set<std::int64_t> stamps;  // of the dynamic links on the chain above the child
  std::set<std::string> chain;
  for (std::string f = child; f != parent && chain.insert(f).second;) {
    const auto link = links_.find(f);
    if (link == links_.end()) break;
    for (const auto& [stamp, pose] : link->second.by_stamp_ns) stamps.insert(stamp);
    f = link->second.parent;
  }
  io::Trajectory gt;
  for (const std::int64_t stamp : stamps) {
    const auto pose = lookup(parent, child, stamp);
    // Outside the span of another transform of the chain: no sample there.
    if (pose)
      gt.push_back({to_seconds({stamp / 1000000000, static_cast<std::uint32_t>(stamp % 1000000000)}), *pose});
  }
  if (gt.empty()) {
    std::set<std::string> frames;
    for (const auto& [c, link] : links_) frames.insert({c, link.parent});
    std::string known;
    for (const std::string& f : frames) known += " " + f;
    throw file_error(file, fmt::format("--gt-from-tf {}:{}: no transform from {} to {} on /tf (frames:{})",
                                       t.gt_parent, t.gt_child, t.gt_parent, t.gt_child, known));
  }
  return gt;
}

}  // namespace lrd::bag
