#include "tools/command_line.h"

#include "tools/commands.h"

namespace oitref::tools {

int runCommandLine(int argc, char** argv, AddCommandFn extra) {
  CLI::App app{"oitref: a bit-exact CPU reference of the GPU pipeline for order-independent transparency"};
  app.require_subcommand(1);
  int exitCode = 0;
  addBlendCommand(app, exitCode);
  addDemoCommand(app, exitCode);
  addRenderCommand(app, exitCode);
  addMethodsCommand(app, exitCode);
  addSuiteCommand(app, exitCode);
  addStudyCommand(app, exitCode);
  addStressCommand(app, exitCode);
  addTrainCommand(app, exitCode);
  addCompareCommand(app, exitCode);
  if (extra) extra(app, exitCode);
  CLI11_PARSE(app, argc, argv);
  return exitCode;
}

}  // namespace oitref::tools
