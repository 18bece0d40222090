// Subcommands of the `oitref` tool. Each registers itself on the CLI11 app and sets `exitCode`
// when it runs.
#pragma once

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

namespace oitref::tools {

// Runs a command's body: its exit status, or — when it throws — "oitref NAME: reason" on stderr
// and status 2.
template <typename Body>
int runReportingErrors(const char* name, Body&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::cerr << "oitref " << name << ": " << e.what() << "\n";
    return 2;
  }
}

void addBlendCommand(CLI::App& app, int& exitCode);
void addCompareCommand(CLI::App& app, int& exitCode);
void addDemoCommand(CLI::App& app, int& exitCode);
void addRenderCommand(CLI::App& app, int& exitCode);
void addMethodsCommand(CLI::App& app, int& exitCode);
void addSuiteCommand(CLI::App& app, int& exitCode);
void addGlcheckCommand(CLI::App& app, int& exitCode);  // only when built with OITREF_HAVE_GLCHECK

}  // namespace oitref::tools
