// The oitref command-line tool.
#include <iostream>

#include "oitref/fp16.h"
#include "oitref/fp_environment.h"
#include "tools/commands.h"
#include "tools/process_setup.h"

int main(int argc, char** argv) {
#if defined(OITREF_HAVE_F16C)
  if (!oitref::cpuHasF16C()) {
    std::cerr << "oitref: this build uses the x86 F16C instructions, which this CPU lacks; "
                 "rebuild with -DOITREF_F16C=OFF (same results, portable code)\n";
    return 2;
  }
#endif
  const oitref::DefaultFloatingPoint fp;  // every rule assumes IEEE defaults
  oitref::tools::keepLargeAllocations();
  CLI::App app{"oitref: a bit-exact CPU reference of the GPU pipeline for order-independent transparency"};
  app.require_subcommand(1);
  int exitCode = 0;
  oitref::tools::addBlendCommand(app, exitCode);
  oitref::tools::addDemoCommand(app, exitCode);
  oitref::tools::addRenderCommand(app, exitCode);
  oitref::tools::addMethodsCommand(app, exitCode);
  oitref::tools::addSuiteCommand(app, exitCode);
  oitref::tools::addStudyCommand(app, exitCode);
  oitref::tools::addStressCommand(app, exitCode);
  oitref::tools::addTrainCommand(app, exitCode);
  oitref::tools::addCompareCommand(app, exitCode);
#if defined(OITREF_HAVE_GLCHECK)
  oitref::tools::addGlcheckCommand(app, exitCode);
#endif
  CLI11_PARSE(app, argc, argv);
  return exitCode;
}
