#pragma once
// PNG plots of an ATE evaluation, drawn with OpenCV (no plotting library in the dependencies):
//   trajectory_top.png  top view of the ground truth and the aligned estimate, red segments joining
//                       associated pairs (like Fig. 13 of the LRD-SLAM paper and evaluate_ate.py --plot);
//   ape_over_time.png   absolute position error of each associated pair over time.
#include <filesystem>

#include "lrd/eval/ate.h"
#include "lrd/io/trajectory.h"

namespace lrd::eval {

// Creates `dir` if needed; throws lrd::Error naming the file that could not be written.
void write_ate_plots(const std::filesystem::path& dir, const io::Trajectory& ground_truth,
                     const io::Trajectory& estimate, const AteResult& ate);

}  // namespace lrd::eval
