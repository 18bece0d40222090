// The oitref command line with one more method: `custom_oitref study --methods clamped_sum,wsum`
// renders it beside oitref's own, against the A-buffer, in the same report.
#include <oitref/apps/cli.h>

#include "clamped_sum.h"

int main(int argc, char** argv) {
  custom::registerClampedSum();
  return oitref::runCommandLine(argc, argv);
}
