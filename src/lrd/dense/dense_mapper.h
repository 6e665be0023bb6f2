#pragma once
// The dense-mapping thread (paper Fig. 1, §2.7; Fig. 18): every new keyframe's RGB-D image is
// repaired from the previous keyframes (BackgroundRepairer), turned into a coloured point cloud
// in the keyframe's own camera frame (dynamic pixels, depth edges and far depth left out,
// voxel-downsampled) and kept with the keyframe. The map is assembled on request with the
// keyframes' current poses, so when local BA or loop closing moves a keyframe, its points move
// with it. The thread runs at a lower OS priority than tracking, which never waits for it.
#include <Eigen/Geometry>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "lrd/camera/image_undistorter.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/background_repairer.h"
#include "lrd/dense/dense_params.h"
#include "lrd/dense/point_cloud.h"
#include "lrd/util/thread_errors.h"

namespace lrd::map {
class KeyFrame;
class Map;
}  // namespace lrd::map

namespace lrd::dense {

struct RepairTotals {
  std::size_t keyframes = 0;       // keyframes repaired (with a dynamic region)
  std::size_t dynamic_pixels = 0;  // pixels inside their dynamic regions
  std::size_t filled_pixels = 0;   // of those, filled from earlier keyframes
  [[nodiscard]] double fill_ratio() const {
    return dynamic_pixels == 0 ? 1.0
                               : static_cast<double>(filled_pixels) / static_cast<double>(dynamic_pixels);
  }
};

// What the stored keyframe clouds hold (dense.max_memory_mb caps `bytes`).
struct DenseStorage {
  std::size_t keyframes = 0;          // clouds stored
  std::size_t points = 0;             // their points
  std::size_t bytes = 0;              // points, colours and free-space votes
  std::size_t evicted_keyframes = 0;  // clouds dropped to stay under the cap
  std::size_t evicted_active = 0;     // of those, keyframes still in the map (not culled)
  double max_memory_mb = 0.0;         // the cap (dense.max_memory_mb; 0: none)
};

class DenseMapper {
 public:
  // Called in the dense thread after each keyframe's repair (for --save-repaired and evaluation).
  using RepairCallback =
      std::function<void(double timestamp, const RgbdView& keyframe, const RepairResult& repair)>;

  // threaded = false: nothing runs until process_queued() (deterministic mode, tests).
  DenseMapper(map::Map& map, const camera::PinholeCamera& camera, const DenseParams& params, bool threaded);
  ~DenseMapper();
  DenseMapper(const DenseMapper&) = delete;
  DenseMapper& operator=(const DenseMapper&) = delete;

  void set_repair_callback(RepairCallback cb) { on_repair_ = std::move(cb); }
  // Called in the dense thread after each keyframe is in the map: its timestamp, the keyframes so
  // far, its view (original images) and its repair (null when it had nothing dynamic). The images
  // are shared, not copied: read them only.
  using UpdateCallback = std::function<void(double timestamp, std::size_t keyframes, const RgbdView& keyframe,
                                            const RepairResult* repair)>;
  void set_update_callback(UpdateCallback cb) { on_update_ = std::move(cb); }
  // The dense thread's error also goes here (besides shutdown()'s rethrow). Set before use.
  void set_error_sink(util::ThreadErrors* errors) { errors_ = errors; }

  // Queues a new keyframe. bgr: CV_8UC3 BGR; depth: CV_32F metres; dynamic: CV_8UC1 or empty.
  // The images must not be written to afterwards (the caller hands over its copies).
  // mask_carried: the segmentation part of `dynamic` was made for an earlier frame and carried
  // over (async schedule), or no mask came for it though a network runs: none of the keyframe's
  // own depth is trusted at once (see process()).
  void add_keyframe(const map::KeyFrame* kf, cv::Mat bgr, cv::Mat depth, cv::Mat dynamic,
                    bool mask_carried = false);
  // Processes every queued keyframe in the caller's thread.
  void process_queued();
  // Finishes the queue and stops the thread. Idempotent. Rethrows the first error the dense
  // thread met (e.g. a repaired image that could not be written); the thread stops at it.
  void shutdown();

  // The map: every keyframe's points at its current pose, merged into voxel_size voxels. Takes the
  // map mutex briefly to read poses.
  [[nodiscard]] PointCloud cloud() const;
  [[nodiscard]] RepairTotals repair_totals() const;
  [[nodiscard]] DenseStorage storage() const;

  // One keyframe's cloud as the dense stage keeps it: in the camera frame (z = the measured
  // depth), with the keyframe's current pose and which points are in the map (the rest other
  // keyframes saw through). The occupancy map casts its rays from these (occupancy/).
  struct KeyframeCloud {
    std::uint64_t keyframe_id = 0;
    double timestamp = 0.0;
    Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
    std::shared_ptr<const PointCloud> local;  // shared: the mapper may drop it meanwhile (memory cap)
    std::vector<char> kept;
    // Points [0, trusted) are the keyframe's own depth away from its dynamic pixels, [trusted,
    // measured) its own depth within dense.mask_margin_px of them (where a mask misses a hand),
    // the rest what the background repair filled in from earlier keyframes (not new measurements).
    std::size_t trusted = static_cast<std::size_t>(-1);  // all, unless set
    std::size_t measured = static_cast<std::size_t>(-1);
  };
  // Every keyframe's, in the order they were added. Takes the map mutex briefly to read poses.
  [[nodiscard]] std::vector<KeyframeCloud> keyframe_clouds() const;

 private:
  // Keyframes by id: they may be culled and freed meanwhile (the map still resolves their poses).
  struct Pending {
    std::uint64_t keyframe_id;
    double timestamp;
    RgbdView view;
    RgbdView coarse;  // for the free-space check (free_space_check.h), made when processed
    bool mask_carried = false;
  };
  struct Stored {
    std::uint64_t keyframe_id;
    std::shared_ptr<const PointCloud> local;  // camera frame
    std::vector<std::uint8_t> votes;          // per point: keyframes that saw through it
    double timestamp;
    std::size_t trusted = 0;   // points [0, trusted): own depth, beyond dense.mask_margin_px of the mask
    std::size_t measured = 0;  // [trusted, measured): own depth near the mask; the rest repaired
  };
  static constexpr std::size_t kBytesPerPoint = sizeof(Eigen::Vector3f) + sizeof(cv::Vec3b) + 1;

  void run();
  void process(Pending p);
  [[nodiscard]] PointCloud keyframe_cloud(const RgbdView& view, const cv::Mat& exclude) const;
  // Drops stored clouds older than recent_'s until they fit in dense.max_memory_mb.
  void enforce_memory_cap();

  map::Map& map_;
  camera::PinholeCamera camera_;
  camera::PinholeCamera coarse_camera_;
  camera::ImageUndistorter undistorter_;
  DenseParams params_;
  BackgroundRepairer repairer_;
  UpdateCallback on_update_;
  bool failed_ = false;  // lock-step: process_queued() threw (guarded by queue_mutex_)
  util::ThreadErrors* errors_ = nullptr;
  RepairCallback on_repair_;

  // Lock order: mutex_ is never held while taking the map mutex, so neither waits on the other.
  std::mutex queue_mutex_;  // queue_, stop_, error_: all tracking ever waits for
  std::condition_variable wake_;
  std::deque<Pending> queue_;
  bool stop_ = false;
  std::exception_ptr error_;
  mutable std::mutex mutex_;  // stored_ (a deque: elements stay put as it grows), totals_
  std::deque<Stored> stored_;
  RepairTotals totals_;
  DenseStorage storage_;
  // Recent keyframes' images, the repair sources (dense thread only).
  std::deque<Pending> recent_;
  std::thread thread_;
};

}  // namespace lrd::dense
