// oitref/apps/cli.h: the program's set-up and command line, for `oitref` itself and for programs that
// add methods of their own.
#include "oitref/apps/cli.h"

#include <iostream>

#include "oitref/core/fp16.h"
#include "oitref/core/fp_environment.h"
#include "tools/command_line.h"
#include "tools/process_setup.h"

namespace oitref {

int tools::runProgram(int argc, char** argv, AddCommandFn extra) {
#if defined(OITREF_HAVE_F16C)
  if (!cpuHasF16C()) {
    std::cerr << "oitref: this build uses the x86 F16C instructions, which this CPU lacks; "
                 "rebuild with -DOITREF_F16C=OFF (same results, portable code)\n";
    return 2;
  }
#endif
  const DefaultFloatingPoint fp;  // every rule assumes IEEE defaults
  keepLargeAllocations();
  return runCommandLine(argc, argv, extra);
}

int runCommandLine(int argc, char** argv) { return tools::runProgram(argc, argv, nullptr); }

}  // namespace oitref
