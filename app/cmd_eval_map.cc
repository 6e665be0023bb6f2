// `lrdslam eval-map`: judges the maps of a finished run against the synthetic benchmark's
// scene.ply: the dense map (ghosts, completeness; docs/dense-map.md) and, when the run wrote them,
// the occupancy map and 2-D grid (precision, recall, people ghosts, the people's path;
// docs/occupancy.md).
#include <cstdio>
#include <memory>
#include <string>

#include "app/commands.h"
#include "lrd/dense/dense_params.h"
#include "lrd/dense/ply_io.h"
#include "lrd/io/trajectory.h"
#include "lrd/occupancy/grid_2d.h"
#include "lrd/runner/map_evaluation.h"
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
  CLI::App* cmd = app.add_subcommand(
      "eval-map",
      "Judge a run's dense_map.ply (and occupancy.bt, occupancy_2d.yaml) against the sequence's scene.ply");
  cmd->add_option(
         "--run", cli->run,
         "Output folder of `lrdslam run --dense` (dense_map.ply, CameraTrajectory.txt; occupancy.bt and "
         "occupancy_2d.yaml when written)")
      ->required();
  cmd->add_option("--sequence", cli->sequence, "The synthetic sequence folder (scene.ply, groundtruth.txt)")
      ->required();
  cmd->add_option("--threshold", cli->threshold,
                  "Distance (m) beyond which a dense-map point is a ghost / a sample missing")
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
    const runner::SceneTruth truth = runner::load_scene_truth(
        io::read_trajectory_tum(run / "CameraTrajectory.txt"), cli->sequence, cfg.camera, cli->max_depth);
    std::printf("dense map vs scene: %s\n",
                eval::describe(runner::evaluate_dense_map(map, truth, cli->threshold)).c_str());
    if (!std::filesystem::exists(run / "occupancy.bt")) return;
    const occupancy::OccupancyMap occupancy = occupancy::OccupancyMap::read_binary(run / "occupancy.bt", {});
    const occupancy::Grid2d grid = occupancy::read_map_server(run / "occupancy_2d.yaml");
    std::printf("occupancy vs scene: %s\n",
                eval::describe(runner::evaluate_occupancy(occupancy, grid, truth)).c_str());
  });
}

}  // namespace lrd::app
