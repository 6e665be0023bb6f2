#include "endpoints.h"

#include <fmt/format.h>

#include <chrono>
#include <thread>

#include "lrd/util/error.h"

namespace lrd_ros2 {

namespace {

dds_qos_t* endpoint_qos(const Qos& qos, const std::string& user_data) {
  dds_qos_t* q = make_qos(qos);
  if (!user_data.empty()) dds_qset_userdata(q, user_data.data(), user_data.size());
  return q;
}

}  // namespace

WriterBase::WriterBase(Participant& participant, const std::string& dds_topic,
                       const dds_topic_descriptor_t* type, const Qos& qos, const std::string& user_data,
                       const char* type_name) {
  const dds_entity_t topic = participant.topic(dds_topic, type, type_name);
  dds_qos_t* q = endpoint_qos(qos, user_data);
  writer_ = dds_create_writer(participant.handle(), topic, q, nullptr);
  dds_delete_qos(q);
  if (writer_ < 0) throw lrd::Error(fmt::format("DDS: writer on {}: {}", dds_topic, dds_strretcode(writer_)));
}

WriterBase::~WriterBase() {
  dds_delete(writer_);
}

int WriterBase::matched() const {
  dds_publication_matched_status_t status;
  if (dds_get_publication_matched_status(writer_, &status) < 0) return 0;
  return static_cast<int>(status.current_count);
}

bool WriterBase::wait_for_reader(double timeout_s) const {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (matched() == 0) {
    if (std::chrono::steady_clock::now() >= end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

bool WriterBase::write_sample(const void* sample) {
  return dds_write(writer_, sample) >= 0;
}

ReaderBase::ReaderBase(Participant& participant, const std::string& dds_topic,
                       const dds_topic_descriptor_t* type, const Qos& qos, Callback callback,
                       const std::string& user_data)
    : callback_(std::move(callback)) {
  const dds_entity_t topic = participant.topic(dds_topic, type);
  dds_qos_t* q = endpoint_qos(qos, user_data);
  dds_listener_t* listener = dds_create_listener(this);
  dds_lset_data_available(listener, &ReaderBase::on_data);
  reader_ = dds_create_reader(participant.handle(), topic, q, listener);
  dds_delete_listener(listener);
  dds_delete_qos(q);
  if (reader_ < 0) throw lrd::Error(fmt::format("DDS: reader on {}: {}", dds_topic, dds_strretcode(reader_)));
}

ReaderBase::~ReaderBase() {
  dds_delete(reader_);
}

void ReaderBase::on_data(dds_entity_t reader, void* self) {
  auto* r = static_cast<ReaderBase*>(self);
  constexpr int kBatch = 8;
  for (;;) {
    void* samples[kBatch] = {nullptr};  // null: Cyclone lends its own samples
    dds_sample_info_t infos[kBatch];
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) return;
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      try {
        r->callback_(samples[i], infos[i]);
      } catch (...) {  // callbacks handle their own errors; nothing may unwind into Cyclone's thread
      }
    }
    dds_return_loan(reader, samples, n);
    if (n < kBatch) return;
  }
}

}  // namespace lrd_ros2
