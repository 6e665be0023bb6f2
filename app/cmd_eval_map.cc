// `lrdslam eval-map`: judges the dense map of a finished run against the synthetic benchmark's
// scene.ply (issue 7): ghosts (map points far from every static surface) and completeness (scene
// samples the camera saw with a map point near).
#include <cstdio>
#include <memory>
#include <string>

#include "app/commands.h"
#include "lrd/dense/dense_params.h"
#include "lrd/dense/ply_io.h"
#include "lrd/io/trajectory.h"
#include "lrd/runner/dense_evaluation.h"
#include "lrd/runner/sequence_runner.h"

namespace lrd::app {

namespace {
struct EvalMapCli {
  std::string run, sequence;
  double threshold = 0.05;
  double max_depth = dense::DenseParams{}.max_depth;
};
}  // namespace

void register_eval_map_command(CLI::App& app) {
  auto cli = std::make_shared<EvalMapCli>();
  CLI::App* cmd =
      app.add_subcommand("eval-map", "Judge a run's dense_map.ply against the sequence's scene.ply");
  cmd->add_option("--run", cli->run,
                  "Output folder of `lrdslam run --dense` (dense_map.ply, CameraTrajectory.txt)")
      ->required();
  cmd->add_option("--sequence", cli->sequence, "The synthetic sequence folder (scene.ply, groundtruth.txt)")
      ->required();
  cmd->add_option("--threshold", cli->threshold,
                  "Distance (m) beyond which a point is a ghost / a sample missing")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-depth", cli->max_depth,
                  "Scene samples farther than this from the camera count as unseen")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([cli] {
    const std::filesystem::path run = cli->run;
    runner::RunOptions o;
    o.sequence = cli->sequence;
    const config::Config cfg = runner::resolve_config(o);
    const dense::PointCloud map = dense::read_ply(run / "dense_map.ply");
    const eval::MapAccuracy accuracy =
        runner::evaluate_dense_map(map, io::read_trajectory_tum(run / "CameraTrajectory.txt"), cli->sequence,
                                   cfg.camera, cli->max_depth, cli->threshold);
    std::printf("dense map vs scene: %s\n", eval::describe(accuracy).c_str());
  });
}

}  // namespace lrd::app
