// ROS 1 bags (`lrdslam run --bag FILE.bag`): the input as a .bag file, opened with the TUM topics
// and /tf ground truth through rosbag_storage (no roscore), and every frame loaded. rosbag_storage
// itself is Debian's build, not instrumented: the search is guided by our reader's code around it,
// and a crash inside it still stops the run.
#include "fuzz_input.h"
#include "lrd_ros/bag_sequence.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  const auto file = write_input("bag.bag", {reinterpret_cast<const char*>(data), size});
  lrd_ros::BagTopics topics;
  topics.gt_parent = "/world";
  topics.gt_child = "/kinect";
  return guarded([&] {
    const auto bag = lrd_ros::BagSequence::open(file, topics);
    for (std::size_t i = 0; i < bag->size(); ++i) (void)bag->load_rgbd(i, 5000.0);
  });
}
