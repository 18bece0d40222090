// The `oitref` command line as a library call. A program that registers methods of its own
// (registerMethod, oitref/oit/method.h) and then calls runCommandLine is the oitref tool with those
// methods beside the built-in ones: `render`, `study`, `stress` and `suite` draw them, `methods`
// lists them (examples/custom_method). Link oitref::apps.
#pragma once

namespace oitref {

// Checks that this CPU runs this build (F16C), sets the IEEE floating-point defaults every rule
// assumes, parses argv as `oitref` does and runs the chosen subcommand: its exit status (2 and a
// message on stderr when it fails; CLI11's status for a malformed command line). glcheck's
// subcommand is only in the `oitref` program itself.
int runCommandLine(int argc, char** argv);

}  // namespace oitref
