// The oitref command-line tool.
#include <iostream>

#include "oitref/fp16.h"
#include "oitref/fp_environment.h"
#include "tools/command_line.h"
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
#if defined(OITREF_HAVE_GLCHECK)
  return oitref::tools::runCommandLine(argc, argv, &oitref::tools::addGlcheckCommand);
#else
  return oitref::tools::runCommandLine(argc, argv, nullptr);
#endif
}
