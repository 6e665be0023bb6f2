#include "participant.h"

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>

#include "lrd/util/error.h"

namespace lrd_ros2 {

namespace {

void check(dds_return_t rc, const std::string& what) {
  if (rc < 0) throw lrd::Error(fmt::format("DDS: {}: {}", what, dds_strretcode(rc)));
}

}  // namespace

Distro parse_distro(const std::string& name) {
  if (name == "humble") return Distro::Humble;
  if (name == "iron" || name == "jazzy" || name == "kilted" || name == "rolling") return Distro::Jazzy;
  throw lrd::Error(fmt::format("distro '{}' is not one of humble, iron, jazzy, kilted, rolling", name));
}

DomainSettings domain_from_environment() {
  DomainSettings d;
  if (const char* id = std::getenv("ROS_DOMAIN_ID"); id != nullptr && *id != '\0') {
    char* end = nullptr;
    const long v = std::strtol(id, &end, 10);
    // 232: the last domain whose RTPS ports (7400 + 250 * id + ...) fit below 65536.
    if (*end != '\0' || v < 0 || v > 232)
      throw lrd::Error(fmt::format("ROS_DOMAIN_ID '{}' is not a domain id 0..232", id));
    d.domain_id = static_cast<std::uint32_t>(v);
  }
  if (const char* local = std::getenv("ROS_LOCALHOST_ONLY")) d.localhost_only = std::string(local) == "1";
  return d;
}

std::string localhost_config() {
  return "<CycloneDDS><Domain><General><Interfaces><NetworkInterface address=\"127.0.0.1\" "
         "multicast=\"true\"/>"
         "</Interfaces><AllowMulticast>spdp</AllowMulticast></General><Discovery>"
         "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>"
         "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>";
}

std::string receive_buffer_config() {
  return "<CycloneDDS><Domain><Internal><SocketReceiveBufferSize min=\"default\" max=\"8MB\"/></Internal>"
         "</Domain></CycloneDDS>";
}

Qos sensor_data_qos() {
  Qos q;
  q.reliable = false;
  q.depth = 5;
  return q;
}

Qos default_qos(int depth) {
  Qos q;
  q.depth = depth;
  return q;
}

Qos latched_qos(int depth) {
  Qos q;
  q.transient_local = true;
  q.depth = depth;
  return q;
}

dds_qos_t* make_qos(const Qos& q) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, q.reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
                       static_cast<dds_duration_t>(q.max_blocking_s * 1e9));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, q.depth);
  dds_qset_durability(qos, q.transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  // Cyclone keeps one sample for late joiners unless told otherwise; rmw keeps the history's depth.
  if (q.transient_local)
    dds_qset_durability_service(qos, 0, DDS_HISTORY_KEEP_LAST, q.depth, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  // ROS 2 serialises plain CDR (XCDR1): an XCDR2 endpoint would not match rmw's.
  dds_data_representation_id_t xcdr1[] = {DDS_DATA_REPRESENTATION_XCDR1};
  dds_qset_data_representation(qos, 1, xcdr1);
  return qos;
}

std::string dds_topic_name(const std::string& ros_topic) {
  return fmt::format("rt{}", ros_topic);
}

std::string dds_type_name(const std::string& ros_type) {
  const std::size_t a = ros_type.find('/'), b = ros_type.rfind('/');
  if (a == std::string::npos || a == b)
    throw lrd::Error(fmt::format("'{}' is not a pkg/msg/Type name", ros_type));
  return fmt::format("{}::{}::dds_::{}_", ros_type.substr(0, a), ros_type.substr(a + 1, b - a - 1),
                     ros_type.substr(b + 1));
}

std::string resolve_name(const std::string& name, const std::string& node_namespace,
                         const std::string& node_name) {
  const std::string ns = node_namespace == "/" ? "" : node_namespace;
  if (!name.empty() && name[0] == '/') return name;
  if (name.rfind("~/", 0) == 0) return fmt::format("{}/{}{}", ns, node_name, name.substr(1));
  return fmt::format("{}/{}", ns, name);
}

Participant::Participant(const DomainSettings& d) : domain_id_(d.domain_id) {
  std::string config = receive_buffer_config();
  if (d.localhost_only) config += fmt::format(",{}", localhost_config());
  if (const char* user = std::getenv("CYCLONEDDS_URI"); user != nullptr && *user != '\0')
    config += fmt::format(",{}", user);
  domain_ = dds_create_domain(d.domain_id, config.c_str());
  // A second participant of this process in the domain shares the first's configuration.
  if (domain_ == DDS_RETCODE_PRECONDITION_NOT_MET) domain_ = 0;
  check(domain_, fmt::format("domain {}{}", d.domain_id, d.localhost_only ? " (localhost only)" : ""));
  dds_qos_t* qos = dds_create_qos();
  const char enclave[] = "enclave=/;";
  dds_qset_userdata(qos, enclave, std::strlen(enclave));
  participant_ = dds_create_participant(d.domain_id, qos, nullptr);
  dds_delete_qos(qos);
  if (participant_ < 0) {
    if (domain_ > 0) dds_delete(domain_);
    check(participant_, fmt::format("participant in domain {}", d.domain_id));
  }
}

Participant::~Participant() {
  dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
}

dds_entity_t Participant::topic(const std::string& name, const dds_topic_descriptor_t* type,
                                const char* type_name) {
  std::lock_guard lock(mutex_);
  if (auto it = topics_.find(name); it != topics_.end()) return it->second;
  if (type_name != nullptr) {
    auto* renamed = static_cast<dds_topic_descriptor_t*>(std::malloc(sizeof(dds_topic_descriptor_t)));
    if (renamed == nullptr) throw std::bad_alloc();
    std::memcpy(static_cast<void*>(renamed), type, sizeof(dds_topic_descriptor_t));
    renamed->m_typename = type_name;
    renamed_types_.emplace_back(renamed);
    type = renamed;
  }
  const dds_entity_t t = dds_create_topic(participant_, type, name.c_str(), nullptr, nullptr);
  check(t, fmt::format("topic {}", name));
  topics_.emplace(name, t);
  return t;
}

Gid Participant::gid(dds_entity_t entity) {
  dds_guid_t guid;
  check(dds_get_guid(entity, &guid), "GUID");
  Gid g;
  std::memcpy(g.data(), guid.v, g.size());
  return g;
}

}  // namespace lrd_ros2
