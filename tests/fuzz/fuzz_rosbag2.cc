// ROS 2 bags: the input as an MCAP file (first byte even) or a sqlite3 .db3 (odd), opened with
// the TUM topics and /tf ground truth, and every frame loaded.
#include "fuzz_input.h"
#include "lrd/rosbag2/rosbag2_sequence.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  if (size == 0) return 0;
  const bool mcap = (data[0] & 1) == 0;
  const auto file =
      write_input(mcap ? "bag.mcap" : "bag.db3", {reinterpret_cast<const char*>(data) + 1, size - 1});
  lrd::bag::BagTopics topics;
  topics.gt_parent = "/world";
  topics.gt_child = "/kinect";
  return guarded([&] {
    const auto bag = lrd::rosbag2::Rosbag2Sequence::open(file, topics);
    for (std::size_t i = 0; i < bag->size(); ++i) (void)bag->load_rgbd(i, 5000.0);
  });
}
