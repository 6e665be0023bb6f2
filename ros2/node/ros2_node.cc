#include "ros2_node.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cstdio>
#include <vector>

#include "lrd/util/error.h"
#include "messages.h"

namespace lrd_ros2 {

namespace {

constexpr const char* kImageType = "sensor_msgs/msg/Image";
constexpr const char* kCameraInfoType = "sensor_msgs/msg/CameraInfo";

// The DDS type name of a publication back as the ROS type it maps (for the warning's words).
std::string ros_type_of(const std::string& dds_type) {
  std::vector<std::string> parts;
  for (std::size_t from = 0;;) {
    const std::size_t at = dds_type.find("::", from);
    const std::string part = dds_type.substr(from, at == std::string::npos ? std::string::npos : at - from);
    if (part != "dds_") parts.push_back(part);
    if (at == std::string::npos) break;
    from = at + 2;
  }
  if (!parts.empty() && !parts.back().empty() && parts.back().back() == '_') parts.back().pop_back();
  return fmt::format("{}", fmt::join(parts, "/"));
}

}  // namespace

void log_line(const char* level, const std::string& node, const std::string& message) {
  const double now =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  std::fprintf(stderr, "[%s] [%.9f] [%s]: %s\n", level, now, node.c_str(), message.c_str());
  std::fflush(stderr);
}

Ros2Node::Ros2Node(const RosArgs& args, std::function<void()> on_fatal) {
  if (!args.node_name.empty()) id_.name = args.node_name;
  if (!args.node_namespace.empty()) id_.ns = args.node_namespace;
  const ParamStore store(args, id_.fqn());
  params_ = lrd::node::NodeParams::from(store);
  std::string distro = "humble";
  store.get("distro", distro);
  distro_ = parse_distro(distro);
  for (const std::string& unused : store.unused()) warn(fmt::format("no such parameter: {}", unused));
  const auto remapped = [&](const std::string& topic) {
    const std::string resolved = resolve_name(topic, id_.ns, id_.name);
    const auto it = args.remaps.find(topic);
    return it == args.remaps.end() ? resolved : resolve_name(it->second, id_.ns, id_.name);
  };
  params_.rgb_topic = remapped(params_.rgb_topic);
  params_.depth_topic = remapped(params_.depth_topic);
  params_.camera_info_topic = remapped(params_.camera_info_topic);

  participant_ = std::make_unique<Participant>(domain_from_environment());
  graph_ = std::make_unique<Graph>(*participant_, distro_, id_.ns, id_.name);
  publisher_ = std::make_shared<Ros2Publisher>(*participant_, *graph_, id_.fqn(), params_.publish);
  lrd::node::NodeLog log{[this](const std::string& m) { info(m); }, [this](const std::string& m) { warn(m); },
                         [this](const std::string& m) { log_line("FATAL", id_.name, m); }};
  driver_ = std::make_unique<lrd::node::SlamDriver>(params_, publisher_, std::move(log), std::move(on_fatal));
  pairer_ = std::make_unique<lrd::node::FramePairer<Incoming>>(
      params_.max_pair_dt, static_cast<std::size_t>(params_.queue_size) * 5);

  using ImageReader = Reader<sensor_msgs_msg_dds__Image_>;
  colour_ = std::make_unique<ImageReader>(
      *participant_, dds_topic_name(params_.rgb_topic), &sensor_msgs_msg_dds__Image__desc, sensor_data_qos(),
      [this](const sensor_msgs_msg_dds__Image_& m, const dds_sample_info_t&) { on_colour(m); });
  depth_ = std::make_unique<ImageReader>(
      *participant_, dds_topic_name(params_.depth_topic), &sensor_msgs_msg_dds__Image__desc,
      sensor_data_qos(),
      [this](const sensor_msgs_msg_dds__Image_& m, const dds_sample_info_t&) { on_depth(m); });
  camera_info_ = std::make_unique<Reader<sensor_msgs_msg_dds__CameraInfo_>>(
      *participant_, dds_topic_name(params_.camera_info_topic), &sensor_msgs_msg_dds__CameraInfo__desc,
      sensor_data_qos(),
      [this](const sensor_msgs_msg_dds__CameraInfo_& m, const dds_sample_info_t&) { on_camera_info(m); });
  for (const ReaderBase* r :
       {static_cast<const ReaderBase*>(colour_.get()), static_cast<const ReaderBase*>(depth_.get()),
        static_cast<const ReaderBase*>(camera_info_.get())})
    graph_->add_reader(r->handle());

  // A publisher of another type on an input topic matches nothing and is never heard: say so.
  dds_listener_t* listener = dds_create_listener(this);
  dds_lset_data_available(listener, [](dds_entity_t reader, void* self) {
    void* samples[8] = {nullptr};
    dds_sample_info_t infos[8];
    const dds_return_t n = dds_take(reader, samples, infos, 8, 8);
    for (dds_return_t i = 0; i < n; ++i)
      if (infos[i].valid_data)
        static_cast<Ros2Node*>(self)->on_publication(
            *static_cast<const dds_builtintopic_endpoint_t*>(samples[i]));
    if (n > 0) dds_return_loan(reader, samples, n);
  });
  publications_ =
      dds_create_reader(participant_->handle(), DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, listener);
  dds_delete_listener(listener);

  info(fmt::format("node {} in domain {} ({}): colour {}, depth {}, camera {}; output to {}", id_.fqn(),
                   participant_->domain_id(), distro, params_.rgb_topic, params_.depth_topic,
                   params_.system.settings.empty() ? params_.camera_info_topic : params_.system.settings,
                   params_.output_dir.string()));
}

Ros2Node::~Ros2Node() {
  if (publications_ > 0) dds_delete(publications_);
  colour_.reset();
  depth_.reset();
  camera_info_.reset();
  try {
    driver_->stop();
  } catch (const std::exception& e) {
    log_line("ERROR", id_.name, e.what());
  }
}

void Ros2Node::on_publication(const dds_builtintopic_endpoint_t& e) {
  if (e.topic_name == nullptr || e.type_name == nullptr) return;
  const std::string topic = e.topic_name, type = e.type_name;
  for (const auto& [ros_topic, expected] :
       {std::pair{params_.rgb_topic, kImageType}, std::pair{params_.depth_topic, kImageType},
        std::pair{params_.camera_info_topic, kCameraInfoType}}) {
    if (topic != dds_topic_name(ros_topic) || type == dds_type_name(expected)) continue;
    std::lock_guard lock(warned_mutex_);
    if (!warned_types_.insert({topic, type}).second) continue;
    warn(fmt::format("{}: a publisher sends {}, expected {}: its messages are not received", ros_topic,
                     ros_type_of(type), expected));
  }
}

void Ros2Node::on_colour(const sensor_msgs_msg_dds__Image_& m) {
  Incoming in;
  try {
    in.image = colour_from_message(m);
  } catch (const std::exception& e) {
    return driver_->drop(&lrd::node::NodeCounts::malformed,
                         fmt::format("{}: {}", params_.rgb_topic, e.what()));
  }
  in.frame_id = m.header.frame_id == nullptr ? "" : m.header.frame_id;
  if (auto pair = pairer_->add_colour(to_seconds(m.header.stamp), std::move(in))) on_pair(std::move(*pair));
}

void Ros2Node::on_depth(const sensor_msgs_msg_dds__Image_& m) {
  Incoming in;
  try {
    in.image = depth_from_message(m);
  } catch (const std::exception& e) {
    return driver_->drop(&lrd::node::NodeCounts::malformed,
                         fmt::format("{}: {}", params_.depth_topic, e.what()));
  }
  if (auto pair = pairer_->add_depth(to_seconds(m.header.stamp), std::move(in))) on_pair(std::move(*pair));
}

void Ros2Node::on_pair(lrd::node::FramePairer<Incoming>::Pair pair) {
  // A pair, not a colour image: over best-effort transport an image can come without its depth.
  driver_->count_received();
  lrd::node::NodeFrame f;
  f.rgb = std::move(pair.colour.image.image);
  f.depth = std::move(pair.depth.image.image);
  if (f.rgb.size() != f.depth.size())
    return driver_->drop(&lrd::node::NodeCounts::malformed,
                         fmt::format("{} is {}x{} but {} is {}x{}", params_.rgb_topic, f.rgb.cols, f.rgb.rows,
                                     params_.depth_topic, f.depth.cols, f.depth.rows));
  f.timestamp = pair.colour.stamp;
  f.frame_id = std::move(pair.colour.image.frame_id);
  f.arrival = std::chrono::steady_clock::now();
  driver_->push(std::move(f));
}

void Ros2Node::on_camera_info(const sensor_msgs_msg_dds__CameraInfo_& m) {
  try {
    lrd::io::SourceCamera c = camera_from_message(m);
    c.origin = fmt::format("camera_info {}", params_.camera_info_topic);
    driver_->set_camera_info(c);
  } catch (const lrd::Error& e) {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard lock(warned_mutex_);
    if (now - last_camera_warning_ < std::chrono::duration<double>(params_.warn_period_s)) return;
    last_camera_warning_ = now;
    warn(fmt::format("ignored a camera_info on {}: {}", params_.camera_info_topic, e.what()));
  }
}

}  // namespace lrd_ros2
