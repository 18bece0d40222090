#include "tools/command_line.h"

#include <cstring>

#include "tools/commands.h"
#include "util/did_you_mean.h"

namespace oitref::tools {
namespace {

std::vector<CLI::App*> subcommandsOf(CLI::App* app) {
  return app->get_subcommands([](CLI::App*) { return true; });
}

// The command words of argv (`render`, `glcheck scene`): each must name a subcommand of the one
// before it. CLI11 reads an unknown word as a stray argument ("A subcommand is required" for
// `oitref rendr`); here it is named, with the nearest command. Returns the deepest command
// named, or nullptr after printing the error.
CLI::App* commandNamed(CLI::App* app, int argc, char** argv, std::string& path) {
  for (int i = 1; i < argc; ++i) {
    const std::vector<CLI::App*> subs = subcommandsOf(app);
    if (subs.empty() || argv[i][0] == '-') return app;
    std::vector<std::string> names;
    CLI::App* next = nullptr;
    for (CLI::App* s : subs) {
      names.push_back(s->get_name());
      if (s->get_name() == argv[i]) next = s;
    }
    if (!next) {
      if (app->get_require_subcommand_min() == 0) return app;  // a positional argument of `app` itself
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      std::cerr << path << ": unknown command '" << argv[i] << "'" << util::didYouMean(argv[i], names) << "; the commands are "
                << list << " (" << path << " --help says what each does)\n";
      return nullptr;
    }
    app = next;
    path += " " + next->get_name();
  }
  return app;
}

}  // namespace

int runCommandLine(int argc, char** argv, AddCommandFn extra) {
  CLI::App app{"oitref: a bit-exact CPU reference of the GPU pipeline for order-independent transparency"};
  app.require_subcommand(1);
  int exitCode = 0;
  addBlendCommand(app, exitCode);
  addDemoCommand(app, exitCode);
  addRenderCommand(app, exitCode);
  addMethodsCommand(app, exitCode);
  addSuiteCommand(app, exitCode);
  addStudyCommand(app, exitCode);
  addStressCommand(app, exitCode);
  addJobCommands(app, exitCode);
  addTrainCommand(app, exitCode);
  addCompareCommand(app, exitCode);
  if (extra) extra(app, exitCode);
  // Exit statuses, one scheme for every command (README, "Exit statuses"): 0 success, 1 a check
  // that ran and found a difference (compare, blend, glcheck, reference), 2 an error — a
  // malformed command line included (CLI11's own codes, 105–109, are not passed on).
  std::string path = "oitref";
  CLI::App* named = commandNamed(&app, argc, argv, path);
  if (!named) return 2;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << path << ": " << e.what() << " (" << path << " --help lists the options)\n";
    return 2;
  }
  return exitCode;
}

}  // namespace oitref::tools
