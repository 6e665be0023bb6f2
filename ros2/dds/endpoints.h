#pragma once
// Typed DDS writers and readers for idlc-generated ROS 2 message types. A Reader hands each valid
// sample to its callback on Cyclone's receive thread (a data-available listener taking loaned
// samples), so callbacks must not block; deleting it waits for a callback in progress.
#include <dds/dds.h>

#include <functional>
#include <string>

#include "participant.h"

namespace lrd_ros2 {

class WriterBase {
 public:
  WriterBase(Participant& participant, const std::string& dds_topic, const dds_topic_descriptor_t* type,
             const Qos& qos, const std::string& user_data = {}, const char* type_name = nullptr);
  ~WriterBase();
  WriterBase(const WriterBase&) = delete;
  WriterBase& operator=(const WriterBase&) = delete;

  [[nodiscard]] dds_entity_t handle() const { return writer_; }
  // Readers matched now.
  [[nodiscard]] int matched() const;
  // Waits up to timeout_s for a matched reader (a player's first frames); false when none came.
  bool wait_for_reader(double timeout_s) const;

 protected:
  // False when DDS refused the sample (a reliable reader kept the history full for longer than
  // max_blocking_s): the sample is dropped.
  bool write_sample(const void* sample);

 private:
  dds_entity_t writer_ = 0;
};

template <typename T>
class Writer final : public WriterBase {
 public:
  using WriterBase::WriterBase;
  bool write(const T& sample) { return write_sample(&sample); }
};

class ReaderBase {
 public:
  using Callback = std::function<void(const void* sample, const dds_sample_info_t& info)>;
  ReaderBase(Participant& participant, const std::string& dds_topic, const dds_topic_descriptor_t* type,
             const Qos& qos, Callback callback, const std::string& user_data = {});
  ~ReaderBase();
  ReaderBase(const ReaderBase&) = delete;
  ReaderBase& operator=(const ReaderBase&) = delete;
  [[nodiscard]] dds_entity_t handle() const { return reader_; }

 private:
  static void on_data(dds_entity_t reader, void* self);
  Callback callback_;
  dds_entity_t reader_ = 0;
};

template <typename T>
class Reader final : public ReaderBase {
 public:
  Reader(Participant& participant, const std::string& dds_topic, const dds_topic_descriptor_t* type,
         const Qos& qos, std::function<void(const T&, const dds_sample_info_t&)> callback)
      : ReaderBase(participant, dds_topic, type, qos,
                   [cb = std::move(callback)](const void* s, const dds_sample_info_t& i) {
                     cb(*static_cast<const T*>(s), i);
                   }) {}
};

}  // namespace lrd_ros2
