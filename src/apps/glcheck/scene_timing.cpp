#include "glcheck/scene_timing.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "tools/suite.h"

namespace oitref::glcheck {
namespace {

double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

struct Samples {
  std::vector<double> wall, cpu;

  template <typename F>
  void measure(F&& frame) {
    const double cpu0 = processCpuMs();
    const auto wall0 = std::chrono::steady_clock::now();
    frame();
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count());
    cpu.push_back(processCpuMs() - cpu0);
  }

  static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }
  TimingStats stats() const {
    return {*std::min_element(wall.begin(), wall.end()), median(wall), *std::min_element(cpu.begin(), cpu.end()),
            median(cpu)};
  }
};

// Per-run pass times, grouped by kind: the name without a trailing " N" (a layer or pass number).
struct PassSamples {
  std::vector<std::string> kinds;                 // in first-seen order
  std::vector<std::vector<double>> perRun;        // [kind][run]: summed over the frame
  std::vector<int> perFrame;

  void add(const std::vector<std::pair<std::string, double>>& frame) {
    std::vector<double> sums(kinds.size(), 0.0);
    std::vector<int> counts(kinds.size(), 0);
    for (const auto& [name, ms] : frame) {
      const size_t space = name.find_last_of(' ');
      const bool numbered = space != std::string::npos && space + 1 < name.size() &&
                            name.find_first_not_of("0123456789", space + 1) == std::string::npos;
      const std::string kind = numbered ? name.substr(0, space) : name;
      size_t k = size_t(std::find(kinds.begin(), kinds.end(), kind) - kinds.begin());
      if (k == kinds.size()) {
        kinds.push_back(kind);
        perRun.emplace_back();
        perFrame.push_back(0);
        sums.push_back(0.0);
        counts.push_back(0);
      }
      sums[k] += ms;
      ++counts[k];
    }
    for (size_t k = 0; k < kinds.size(); ++k) {
      perRun[k].push_back(sums[k]);
      perFrame[k] = counts[k];
    }
  }
  std::vector<PassTiming> stats() const {
    std::vector<PassTiming> out;
    for (size_t k = 0; k < kinds.size(); ++k) out.push_back({kinds[k], Samples::median(perRun[k]), perFrame[k]});
    return out;
  }
};

}  // namespace

double medianOfRatios(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.empty() || a.size() != b.size()) throw std::invalid_argument("medianOfRatios: two series of one non-zero length");
  std::vector<double> ratios(a.size());
  for (size_t i = 0; i < a.size(); ++i) ratios[i] = a[i] / b[i];
  return Samples::median(std::move(ratios));
}

double measureMemoryBandwidth() {
  const size_t bytes = size_t(256) << 20;
  std::vector<uint8_t> from(bytes, 1), to(bytes, 0);  // touched: no page faults inside the clock
  double best = 1e300;
  for (int i = 0; i < 5; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    std::memcpy(to.data(), from.data(), bytes);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    from[size_t(i)] = to[bytes - 1 - size_t(i)];  // the copies depend on each other: none is elided
  }
  return 2.0 * double(bytes) / best * 1e-9;
}

double compositeTrafficBytes(const std::vector<AttachmentDecl>& attachments, int width, int height) {
  const double pixels = double(width) * double(height);
  double perPixel = 0;
  for (const AttachmentDecl& a : attachments)
    if (a.readByComposite) perPixel += a.bytesPerTexel();
  perPixel += 4 + 16 + 16;  // the presented RGBA8 ("opaque", counted once above) written, the analysis copy read and written
  return perPixel * pixels;
}

MethodTiming timeMethod(const GlContext& context, const FrameContext& frame, Method& method, GlMethod glMethod,
                        const MethodOptions& options, int runs) {
  if (runs < 1) throw std::invalid_argument("--time needs at least one run");
  Samples ours, gl;
  MethodTiming timing;
  // GL draws into one frame for every run: its programs are compiled and its geometry uploaded
  // once, as an application would. Its passes clear what they use, so every run must present the
  // same bits, which a read after the last run checks.
  GlFrame glFrame(context, frame, method.attachments());
  const std::string presented = glMethod(glFrame, options);
  const Image firstGl = glFrame.read(presented);
  // oitref keeps its attachments the same way: a pool, filled by one untimed frame, from which
  // every timed frame takes them and to which it gives them back after the clock stops.
  AttachmentPool pool;
  FrameContext pooled = frame;
  pooled.pool = &pool;
  pool.recycle(method.render(pooled));
  PassSamples ourPasses, glPasses;
  glFrame.timePasses(true);
  for (int run = 0; run < runs; ++run) {
    FrameResult result;  // emptied before the clock starts, hashed after it stops
    ours.measure([&] { result = method.render(pooled); });
    const std::string hash = frameHash(result);
    std::vector<std::pair<std::string, double>> passes;
    for (const PassReport& p : result.passes) passes.emplace_back(p.name, p.ms);
    ourPasses.add(passes);
    pool.recycle(std::move(result));
    if (timing.sha256.empty()) timing.sha256 = hash;
    // A speed-up must never come from changed bits, not even between runs of one process.
    if (hash != timing.sha256) throw std::runtime_error(method.info().name + ": oitref's frame changed between timed runs");
    gl.measure([&] {
      glMethod(glFrame, options);
      context.gl().Finish();
    });
    glPasses.add(glFrame.takePassTimes());  // the queries' results, read after the clock stopped
  }
  glFrame.timePasses(false);
  if (glFrame.read(presented).bytes() != firstGl.bytes())
    throw std::runtime_error(method.info().name + ": GL's frame changed between timed runs (a pass relies on an uncleared attachment)");
  timing.oitref = ours.stats();
  timing.gl = gl.stats();
  timing.pairedCpuRatio = medianOfRatios(ours.cpu, gl.cpu);
  timing.pairedWallRatio = medianOfRatios(ours.wall, gl.wall);
  timing.compositeTrafficBytes = compositeTrafficBytes(method.attachments(), frame.width, frame.height);
  timing.oitrefPasses = ourPasses.stats();
  timing.glPasses = glPasses.stats();
  return timing;
}

}  // namespace oitref::glcheck
