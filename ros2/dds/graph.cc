#include "graph.h"

#include <cstring>

#include "rmw_dds_common.h"

namespace lrd_ros2 {

namespace {

constexpr const char* kTopic = "ros_discovery_info";
constexpr const char* kTypeName = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

// Humble's 24-byte Gid and later distros' 16-byte one, filled alike: the GUID, zeros after it.
template <typename GidType>
void fill(GidType& out, const Gid& gid) {
  std::memset(out.data, 0, sizeof out.data);
  std::memcpy(out.data, gid.data(), gid.size());
}

template <typename Info, typename NodeInfo, typename GidType>
Info entities_info(const Gid& participant, const std::string& ns, const std::string& name,
                   std::vector<GidType>& readers, std::vector<GidType>& writers, NodeInfo& node) {
  Info info{};
  fill(info.gid, participant);
  // string<256>: a char[257] in the generated type (names are checked to fit where they are made).
  std::strncpy(node.node_namespace, ns.c_str(), sizeof node.node_namespace - 1);
  std::strncpy(node.node_name, name.c_str(), sizeof node.node_name - 1);
  node.reader_gid_seq._length = node.reader_gid_seq._maximum = static_cast<std::uint32_t>(readers.size());
  node.reader_gid_seq._buffer = readers.data();
  node.writer_gid_seq._length = node.writer_gid_seq._maximum = static_cast<std::uint32_t>(writers.size());
  node.writer_gid_seq._buffer = writers.data();
  info.node_entities_info_seq._length = info.node_entities_info_seq._maximum = 1;
  info.node_entities_info_seq._buffer = &node;
  return info;
}

template <typename Info, typename NodeInfo, typename GidType>
void write_info(WriterBase& writer, const Gid& participant, const std::string& ns, const std::string& name,
                const std::vector<Gid>& readers, const std::vector<Gid>& writers) {
  std::vector<GidType> r(readers.size()), w(writers.size());
  for (std::size_t i = 0; i < readers.size(); ++i) fill(r[i], readers[i]);
  for (std::size_t i = 0; i < writers.size(); ++i) fill(w[i], writers[i]);
  NodeInfo node{};
  const Info info = entities_info<Info>(participant, ns, name, r, w, node);
  static_cast<Writer<Info>&>(writer).write(info);
}

}  // namespace

Graph::Graph(Participant& participant, Distro distro, std::string node_namespace, std::string node_name)
    : participant_(participant),
      distro_(distro),
      namespace_(std::move(node_namespace)),
      name_(std::move(node_name)) {
  if (distro_ == Distro::Humble)
    writer_ = std::make_unique<Writer<rmw_dds_common_msg_dds__ParticipantEntitiesInfo_>>(
        participant, kTopic, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, latched_qos(1));
  else
    writer_ = std::make_unique<Writer<rmw_dds_common_msg_jazzy__ParticipantEntitiesInfo_>>(
        participant, kTopic, &rmw_dds_common_msg_jazzy__ParticipantEntitiesInfo__desc, latched_qos(1), "",
        kTypeName);
  std::lock_guard lock(mutex_);
  publish();
}

Graph::~Graph() = default;

void Graph::add_reader(dds_entity_t reader) {
  std::lock_guard lock(mutex_);
  readers_.push_back(Participant::gid(reader));
  publish();
}

void Graph::add_writer(dds_entity_t writer) {
  std::lock_guard lock(mutex_);
  writers_.push_back(Participant::gid(writer));
  publish();
}

void Graph::publish() {
  const Gid participant = Participant::gid(participant_.handle());
  if (distro_ == Distro::Humble)
    write_info<rmw_dds_common_msg_dds__ParticipantEntitiesInfo_, rmw_dds_common_msg_dds__NodeEntitiesInfo_,
               rmw_dds_common_msg_dds__Gid_>(*writer_, participant, namespace_, name_, readers_, writers_);
  else
    write_info<rmw_dds_common_msg_jazzy__ParticipantEntitiesInfo_,
               rmw_dds_common_msg_jazzy__NodeEntitiesInfo_, rmw_dds_common_msg_jazzy__Gid_>(
        *writer_, participant, namespace_, name_, readers_, writers_);
}

}  // namespace lrd_ros2
