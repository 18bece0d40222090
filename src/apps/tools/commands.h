// Subcommands of the `oitref` tool. Each registers itself on the CLI11 app and sets `exitCode`
// when it runs.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <exception>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "oitref/oit/method.h"
#include "tools/number_parse.h"

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

// A file or folder option that must name something: "" is refused (it would write nothing, or
// select another mode, silently).
inline CLI::Option* nonEmptyPath(CLI::Option* option) {
  return option->check(CLI::Validator([](std::string& value) { return value.empty() ? std::string("must not be empty") : std::string(); },
                                      "PATH", "NonEmpty"));
}

// --memory-limit, as render, suite and glcheck scene take it: empty means defaultMemoryLimit().
inline void addMemoryLimitOption(CLI::App* cmd, std::string& text) {
  cmd->add_option("--memory-limit", text, "Refuse frames that need more, e.g. 8G (default: half the machine's memory)");
}
inline uint64_t memoryLimitFrom(const std::string& text) {
  return text.empty() ? defaultMemoryLimit() : parseByteSize(text, "--memory-limit");
}

// --profile, as every command that renders or blends takes it (oitref/core/profile.h).
inline CLI::Option* addProfileOption(CLI::App* cmd, std::string& text, const char* what = "Profile") {
  return cmd->add_option("--profile", text, std::string(what) + ": exact | llvmpipe | nvidia, optionally with ,key=value overrides")
      ->capture_default_str();
}

// --threads, as every command that renders takes it: the renderer's workers (0: every hardware
// thread). `what` names whose threads they are where a command has more than one kind.
inline CLI::Option* addThreadsOption(CLI::App* cmd, int& threads, const char* what = "Worker threads (0: all)") {
  return cmd->add_option("--threads", threads, what)->check(CLI::Range(0, 1024));
}

// --size WxH, as render, suite and study take it: the scenes' resolution overridden (parseSize).
inline CLI::Option* addSizeOption(CLI::App* cmd, std::string& size, const char* what = "Override the scenes' resolution, WxH") {
  return cmd->add_option("--size", size, what);
}

// --quiet, as the long-running commands take it.
inline CLI::Option* addQuietFlag(CLI::App* cmd, bool& quiet) { return cmd->add_flag("--quiet", quiet, "No progress on stderr"); }

// --set key=value (repeatable), as render and glcheck scene take method options: the map that
// makeMethod and MethodOptions read, which name the method when a key or value is not its own.
inline void addMethodSetOption(CLI::App* cmd, std::vector<std::string>& sets) {
  cmd->add_option("--set", sets, "Method option key=value (repeatable)");
}
inline std::map<std::string, std::string> methodOptionsFrom(const std::vector<std::string>& sets) {
  std::map<std::string, std::string> options;
  for (const std::string& kv : sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("--set '" + kv + "': expected key=value");
    options[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  return options;
}

void addBlendCommand(CLI::App& app, int& exitCode);
void addCompareCommand(CLI::App& app, int& exitCode);
void addDemoCommand(CLI::App& app, int& exitCode);
void addRenderCommand(CLI::App& app, int& exitCode);
void addMethodsCommand(CLI::App& app, int& exitCode);
void addSuiteCommand(CLI::App& app, int& exitCode);
void addStudyCommand(CLI::App& app, int& exitCode);
void addStressCommand(CLI::App& app, int& exitCode);
void addTrainCommand(CLI::App& app, int& exitCode);
void addJobCommands(CLI::App& app, int& exitCode);  // job, collect

}  // namespace oitref::tools
