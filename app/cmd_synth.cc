#include "app/commands.h"
namespace lrd::app {
void register_synth_command(CLI::App& app) { app.add_subcommand("synth", "Render a synthetic dynamic RGB-D sequence"); }
}  // namespace lrd::app
