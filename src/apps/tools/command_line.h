// The `oitref` program's command line, kept apart from main() so that only one file of the
// program includes CLI11 (compiled with the subcommands, see CMakeLists.txt).
#pragma once

namespace CLI {
class App;
}

namespace oitref::tools {

// Adds a subcommand that lives outside oitref_tools (glcheck); it sets `exitCode` when it runs.
using AddCommandFn = void (*)(CLI::App& app, int& exitCode);

// Registers every subcommand (and `extra`, when given), parses argv and runs the chosen one:
// its exit status, or CLI11's for a malformed command line.
int runCommandLine(int argc, char** argv, AddCommandFn extra);

// The program around it (oitref/apps/cli.h's runCommandLine, and main with glcheck's command): the
// CPU check, the floating-point defaults, the allocator's set-up, then runCommandLine.
int runProgram(int argc, char** argv, AddCommandFn extra);

// glcheck's subcommand (src/apps/glcheck/glcheck_command.cpp), only when built with OITREF_HAVE_GLCHECK.
void addGlcheckCommand(CLI::App& app, int& exitCode);

}  // namespace oitref::tools
