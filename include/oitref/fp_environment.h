// oitref's arithmetic assumes IEEE defaults: round to nearest even, denormals kept (no FTZ/DAZ
// on x86). A host application may have changed them; oitref's stages (the vertex stage of
// Geometry::fromVertexShader, every pipeline task) run inside this guard, which sets the default
// environment and restores the thread's own on exit.
#pragma once

#include <cfenv>

namespace oitref {

class DefaultFloatingPoint {
 public:
  DefaultFloatingPoint() {
    std::fegetenv(&saved_);
    std::fesetenv(FE_DFL_ENV);
  }
  ~DefaultFloatingPoint() { std::fesetenv(&saved_); }
  DefaultFloatingPoint(const DefaultFloatingPoint&) = delete;
  DefaultFloatingPoint& operator=(const DefaultFloatingPoint&) = delete;

 private:
  std::fenv_t saved_;
};

}  // namespace oitref
