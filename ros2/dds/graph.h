#pragma once
// The node in the ROS graph: rmw_dds_common's ParticipantEntitiesInfo on the DDS topic
// ros_discovery_info (reliable, transient_local, keep last 1), the participant's whole state
// again at each change, as rmw_cyclonedds publishes it. `ros2 node list` and `ros2 topic info
// -v` read it to put our endpoints under /lrdslam.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "endpoints.h"
#include "participant.h"

namespace lrd_ros2 {

class Graph {
 public:
  Graph(Participant& participant, Distro distro, std::string node_namespace, std::string node_name);
  ~Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;

  // The node's readers and writers (their DDS entities); each publishes the new state.
  void add_reader(dds_entity_t reader);
  void add_writer(dds_entity_t writer);

 private:
  void publish();
  Participant& participant_;
  const Distro distro_;
  const std::string namespace_, name_;
  std::mutex mutex_;
  std::vector<Gid> readers_, writers_;
  std::unique_ptr<WriterBase> writer_;
};

}  // namespace lrd_ros2
