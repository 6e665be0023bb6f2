#pragma once
// The map outputs of a run with the dense stage: dense_map.ply/.png, occupancy.bt and
// occupancy_2d.pgm/.yaml/.png, each judged against the synthetic benchmark's scene where the
// sequence has one (the truth is loaded once for both).
#include "lrd/runner/dense_evaluation.h"
#include "lrd/runner/sequence_runner.h"

namespace lrd::runner {

// Fills report.dense and (unless occupancy.enabled is false) report.occupancy.
void finish_maps(RunReport& report, const System& slam, const RepairRecorder& repairs, const RunOptions& o,
                 const io::Trajectory& trajectory, const camera::PinholeCamera& camera,
                 const SystemParams& params);

}  // namespace lrd::runner
