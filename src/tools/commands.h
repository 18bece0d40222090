// Subcommands of the `oitref` tool. Each registers itself on the CLI11 app and sets `exitCode`
// when it runs.
#pragma once

#include <CLI/CLI.hpp>

namespace oitref::tools {

void addBlendCommand(CLI::App& app, int& exitCode);
void addDemoCommand(CLI::App& app, int& exitCode);
void addRenderCommand(CLI::App& app, int& exitCode);
void addMethodsCommand(CLI::App& app, int& exitCode);
void addSuiteCommand(CLI::App& app, int& exitCode);

}  // namespace oitref::tools
