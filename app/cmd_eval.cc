// Placeholder until the evaluator lands (owned by the eval work).
#include "app/commands.h"
namespace lrd::app {
void register_eval_command(CLI::App& app) { app.add_subcommand("eval", "Evaluate a trajectory (ATE/RPE)"); }
}  // namespace lrd::app
