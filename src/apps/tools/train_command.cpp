// `oitref train-dfaoit`: regenerates the DFAOIT weights (src/oit/methods/dfaoit_weights.h).
#include <chrono>
#include <cstdio>
#include <memory>

#include "tools/commands.h"
#include "tools/dfaoit_training.h"
#include "oitref/oit/image_io.h"

namespace oitref::tools {
namespace {

struct TrainOptions {
  std::string out = "src/oit/methods/dfaoit_weights.h";
  int epochs = DfaoitTraining{}.epochs, threads = 0;
  bool quiet = false;
};

int runTrain(const TrainOptions& c) {
  if (c.epochs < 1 || c.epochs > 100000) throw std::invalid_argument("--epochs must be in 1..100000");
  const auto start = std::chrono::steady_clock::now();
  Renderer renderer(RendererOptions{.threads = c.threads});
  const std::vector<DfaoitSample> samples = dfaoitDataset(dfaoitTrainingScenes(), renderer);
  DfaoitTraining o;
  o.epochs = c.epochs;
  double last = 0;
  const methods::DfaoitParameters p = trainDfaoit(samples, o, [&](int epoch, double loss) {
    last = loss;
    if (!c.quiet && (epoch == 1 || epoch % 25 == 0 || epoch == o.epochs))
      std::fprintf(stderr, "epoch %d/%d: MSE %.6g\n", epoch, o.epochs, loss);
  });
  char provenance[512];
  std::snprintf(provenance, sizeof provenance,
                "Training data: %zu pixels with more than two layers from the 16 scenes of\n"
                "tools/dfaoit_training.cpp (A-buffer targets). Adam, learning rate %g, batch %d, %d epochs,\n"
                "seed %u; mean squared error of the last epoch %.6g.",
                samples.size(), o.learningRate, o.batch, o.epochs, o.seed, last);
  writeTextFile(c.out, dfaoitWeightsHeader(p, provenance));
  std::printf("oitref train-dfaoit: %zu samples, %d epochs, final MSE %.6g, %.1f s; wrote %s\n", samples.size(), o.epochs,
              last, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), c.out.c_str());
  return 0;
}

}  // namespace

void addTrainCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<TrainOptions>();
  CLI::App* cmd = app.add_subcommand("train-dfaoit", "Train the DFAOIT network and write its weights (deterministic)");
  nonEmptyPath(cmd->add_option("--out", o->out, "Weights header to write"))->capture_default_str();
  cmd->add_option("--epochs", o->epochs, "Training epochs")->capture_default_str();
  addThreadsOption(cmd, o->threads, "Worker threads for the A-buffer renders (0: all)");
  addQuietFlag(cmd, o->quiet);
  cmd->callback([o, &exitCode] { exitCode = runReportingErrors("train-dfaoit", [&] { return runTrain(*o); }); });
}

}  // namespace oitref::tools
