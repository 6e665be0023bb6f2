#pragma once
// A ROS 2 context on Eclipse Cyclone DDS as rmw_cyclonedds_cpp sets one up, so that every ROS 2
// node (and rmw_fastrtps' on the same wire protocol) sees ours as one of its own: the domain from
// ROS_DOMAIN_ID, localhost-only discovery when ROS_LOCALHOST_ONLY=1, the participant's user data
// "enclave=/;" (the ROS graph lists only participants with an enclave), ROS names mapped onto DDS
// topic and type names (rt/ prefix; pkg::msg::dds_::Name_), and the QoS profiles of rmw's
// qos_profiles.h with the data representation ROS 2 uses (XCDR1).
#include <dds/dds.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace lrd_ros2 {

// Which ROS 2 distribution the node talks to: the ROS graph's message (rmw_dds_common's Gid)
// is 24 bytes in Humble and 16 from Iron on, under one type name.
enum class Distro { Humble, Jazzy };
[[nodiscard]] Distro parse_distro(const std::string& name);  // throws lrd::Error naming the choices

struct DomainSettings {
  std::uint32_t domain_id = 0;  // ROS_DOMAIN_ID
  bool localhost_only = false;  // ROS_LOCALHOST_ONLY=1
};
// From the environment; throws lrd::Error for a ROS_DOMAIN_ID that is not 0..232.
[[nodiscard]] DomainSettings domain_from_environment();

// A socket receive buffer of up to 8 MB (as far as the system allows: net.core.rmem_max) instead
// of the system's default (often 208 KiB): a colour and a depth image arrive together as 2 MB of
// fragments, and a best-effort reader loses every sample one of whose fragments overflowed it.
[[nodiscard]] std::string receive_buffer_config();

// Cyclone's configuration for localhost-only discovery: loopback (treated as multicast-capable,
// as Linux does not flag lo so) with SPDP by multicast and the well-known unicast ports of
// participant indices 0..32 as peers, so both ROS 2 nodes run with ROS_LOCALHOST_ONLY=1 (unicast
// discovery on lo) and participants that discover only by multicast find us. The user's
// CYCLONEDDS_URI, when set, follows and overrides it, as rmw_cyclonedds does.
[[nodiscard]] std::string localhost_config();

// QoS as rmw_cyclonedds maps an rmw profile onto DDS.
struct Qos {
  bool reliable = true;
  bool transient_local = false;  // a late subscriber gets the last `depth` samples
  int depth = 10;                // KEEP_LAST depth
  // Reliable writers give up a write after this long when a reader's acknowledgements keep the
  // history full, so a stalled subscriber never stalls tracking for long. Not DDS's default of
  // 0.1 s: Cyclone leaves a QoS equal to the default out of discovery, and some participants
  // (@foxglove/rtps) ignore a writer whose announcement has no reliability.
  double max_blocking_s = 0.25;
};
[[nodiscard]] Qos sensor_data_qos();                // best effort, volatile, keep last 5
[[nodiscard]] Qos default_qos(int depth = 10);      // reliable, volatile
[[nodiscard]] Qos latched_qos(int depth = 1);       // reliable, transient_local
[[nodiscard]] dds_qos_t* make_qos(const Qos& qos);  // caller deletes (dds_delete_qos)

// "/lrdslam/pose" -> "rt/lrdslam/pose".
[[nodiscard]] std::string dds_topic_name(const std::string& ros_topic);
// "sensor_msgs/msg/Image" -> "sensor_msgs::msg::dds_::Image_".
[[nodiscard]] std::string dds_type_name(const std::string& ros_type);
// A ROS name resolved as rcl resolves it: "/x" as is, "~/x" under the node, "x" under its namespace.
[[nodiscard]] std::string resolve_name(const std::string& name, const std::string& node_namespace,
                                       const std::string& node_name);

// rmw_dds_common's Gid of an entity: its 16-byte DDS GUID (Humble pads it with zeros to 24).
using Gid = std::array<std::uint8_t, 16>;

class Participant {
 public:
  explicit Participant(const DomainSettings& domain);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  [[nodiscard]] dds_entity_t handle() const { return participant_; }
  [[nodiscard]] std::uint32_t domain_id() const { return domain_id_; }
  // The topic of this name and type (made once). `type` is its descriptor, the DDS type name
  // overridden by `type_name` when given (a later distro's layout under the same name).
  [[nodiscard]] dds_entity_t topic(const std::string& dds_name, const dds_topic_descriptor_t* type,
                                   const char* type_name = nullptr);
  [[nodiscard]] static Gid gid(dds_entity_t entity);

 private:
  std::uint32_t domain_id_ = 0;
  dds_entity_t domain_ = 0, participant_ = 0;
  std::mutex mutex_;
  std::map<std::string, dds_entity_t> topics_;
  // Descriptors with their type names replaced (the struct has const members: copied as bytes).
  struct FreeDescriptor {
    void operator()(dds_topic_descriptor_t* d) const { std::free(d); }
  };
  std::vector<std::unique_ptr<dds_topic_descriptor_t, FreeDescriptor>> renamed_types_;
};

}  // namespace lrd_ros2
