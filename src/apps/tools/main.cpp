// The oitref command-line tool.
#include "tools/command_line.h"

int main(int argc, char** argv) {
#if defined(OITREF_HAVE_GLCHECK)
  return oitref::tools::runProgram(argc, argv, &oitref::tools::addGlcheckCommand);
#else
  return oitref::tools::runProgram(argc, argv, nullptr);
#endif
}
