#include "glcheck/scene_timing.h"

#include <time.h>

#include <algorithm>
#include <chrono>
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

}  // namespace

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
  for (int run = 0; run < runs; ++run) {
    FrameResult result;  // emptied before the clock starts, hashed after it stops
    ours.measure([&] { result = method.render(pooled); });
    const std::string hash = tools::frameHash(result);
    pool.recycle(std::move(result));
    if (timing.sha256.empty()) timing.sha256 = hash;
    // A speed-up must never come from changed bits, not even between runs of one process.
    if (hash != timing.sha256) throw std::runtime_error(method.info().name + ": oitref's frame changed between timed runs");
    gl.measure([&] {
      glMethod(glFrame, options);
      context.gl().Finish();
    });
  }
  if (glFrame.read(presented).bytes() != firstGl.bytes())
    throw std::runtime_error(method.info().name + ": GL's frame changed between timed runs (a pass relies on an uncleared attachment)");
  timing.oitref = ours.stats();
  timing.gl = gl.stats();
  return timing;
}

}  // namespace oitref::glcheck
