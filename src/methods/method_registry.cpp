// The list of methods, their options, and the pieces of the Method interface they share.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "methods/methods.h"
#include "util/did_you_mean.h"

namespace oitref {
namespace {

struct Entry {
  const MethodInfo& (*info)();
  std::unique_ptr<Method> (*make)(const MethodOptions&);
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = {
      {methods::opaqueInfo, methods::makeOpaque}, {methods::overInfo, methods::makeOver},
      {methods::sortedInfo, methods::makeSorted},
      {methods::wsumInfo, methods::makeWsum},     {methods::wavgInfo, methods::makeWavg},
      {methods::meshkin3Info, methods::makeMeshkin3},
      {methods::wboitInfo, methods::makeWboit},   {methods::mboitInfo, methods::makeMboit},
      {methods::mtInfo, methods::makeMt},
      {methods::peelInfo, methods::makePeel},     {methods::dualpeelInfo, methods::makeDualpeel},
      {methods::screendoorInfo, methods::makeScreendoor},
      {methods::hybridInfo, methods::makeHybrid},
      {methods::stochasticInfo, methods::makeStochastic},
      {methods::mlabInfo, methods::makeMlab},     {methods::kbufferInfo, methods::makeKbuffer},
      {methods::dfaoitInfo, methods::makeDfaoit},
      {methods::abufferInfo, methods::makeAbuffer}, {methods::raycastInfo, methods::makeRaycast},
  };
  return entries;
}

}  // namespace

int AttachmentDecl::bytesPerTexel() const {
  if (!isDepth) return format.bytesPerTexel();
  return depthFormat == DepthFormat::D16 ? 2 : 4;
}

std::string AttachmentDecl::formatName() const { return isDepth ? toString(depthFormat) : format.name(); }

namespace {

// The option preset=none|NAME… of a method with presets, as if it were declared.
MethodOption presetOption(const MethodInfo& info) {
  MethodOption o{"preset", "none", "a named configuration of the options above (those given beside it still apply)", {"none"}};
  for (const MethodPreset& p : info.presets) o.choices.push_back(p.name);
  return o;
}

}  // namespace

namespace {

std::string shortNumber(double v) {
  char text[40];
  std::snprintf(text, sizeof text, v == std::floor(v) && std::fabs(v) < 0x1p53 ? "%.0f" : "%.10g", v);
  return text;
}

// The one place a number option's value is checked: finite, of its kind, in its range.
void checkNumber(const std::string& method, const MethodOption& option, const std::string& value) {
  const OptionNumber& n = option.number;
  if (n.kind == OptionNumber::Kind::None || (n.orAuto && value == "auto")) return;
  const std::string what = "method '" + method + "' option '" + option.key + "': '" + value + "' ";
  const bool integer = n.kind == OptionNumber::Kind::Integer;
  const std::string range = n.describe();
  char* end = nullptr;
  const double d = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(d)) throw std::invalid_argument(what + "is not a finite number (" + range + ")");
  if (integer && d != std::floor(d)) throw std::invalid_argument(what + "is not an integer (" + range + ")");
  if (d < n.min || d > n.max) throw std::invalid_argument(what + "is outside " + range.substr(range.find(" in ") + 4));
}

}  // namespace

std::string OptionNumber::describe() const {
  if (kind == Kind::None) return "";
  return std::string(kind == Kind::Integer ? "an integer" : "a number") + " in " + shortNumber(min) + ".." + shortNumber(max) +
         (orAuto ? " or auto" : "");
}

MethodOptions::MethodOptions(const MethodInfo& info, const std::map<std::string, std::string>& given)
    : method_(info.name) {
  std::vector<MethodOption> options = info.options;
  if (!info.presets.empty()) options.push_back(presetOption(info));
  std::vector<std::string> keys;
  for (const MethodOption& o : options) {
    values_[o.key] = o.defaultValue;
    keys.push_back(o.key);
  }
  for (const auto& entry : given) {
    const std::string& key = entry.first;  // not a structured binding: lambdas capture those only from C++20 compilers on
    const std::string& value = entry.second;
    const auto option = std::find_if(options.begin(), options.end(), [&](const MethodOption& o) { return o.key == key; });
    if (option == options.end())
      throw std::invalid_argument("method '" + info.name + "' has no option '" + key + "'" + util::didYouMean(key, keys) +
                                  (keys.empty() ? " (it takes none)" : ""));
    if (!option->choices.empty() && std::find(option->choices.begin(), option->choices.end(), value) == option->choices.end()) {
      std::string valid;
      for (const std::string& c : option->choices) valid += (valid.empty() ? "" : ", ") + c;
      throw std::invalid_argument("method '" + info.name + "' option '" + key + "': '" + value + "' is not one of " + valid);
    }
    checkNumber(info.name, *option, value);
  }
  // The preset's values first, then every option given (the preset's name among them). A preset
  // names only declared options (at() throws otherwise; the methods test runs every preset).
  if (const auto chosen = given.find("preset"); chosen != given.end())
    for (const MethodPreset& p : info.presets)
      if (p.name == chosen->second)
        for (const auto& [key, value] : p.values) values_.at(key) = value;
  for (const auto& [key, value] : given) values_[key] = value;
  for (const MethodOption& o : options)
    if (o.choices.empty() && values_[o.key] != "auto") number(o.key);  // free-form options are numbers (or "auto"): check now
}

const std::string& MethodOptions::text(const std::string& key) const { return values_.at(key); }

double MethodOptions::number(const std::string& key) const {
  const std::string& v = values_.at(key);
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0')
    throw std::invalid_argument("method '" + method_ + "' option '" + key + "': '" + v + "' is not a number");
  return d;
}

bool MethodOptions::flag(const std::string& key) const { return values_.at(key) == "true"; }

double FrameResult::frameMs() const {
  double ms = 0;
  for (const PassReport& p : passes) ms += p.ms;
  return ms;
}

uint64_t FrameResult::fragmentsShaded() const {
  uint64_t n = 0;
  for (const PassReport& p : passes) n += p.stats.fragmentsShaded;
  return n;
}

int Method::bytesPerPixel() const {
  int bytes = 0;
  for (const AttachmentDecl& a : attachments()) bytes += a.bytesPerTexel();
  return bytes;
}

std::vector<MemoryItem> Method::memoryNeed(int width, int height, const SceneGeometry&) const {
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  return {{"attachments (" + std::to_string(bytesPerPixel()) + " B/pixel)", pixels * uint64_t(bytesPerPixel())},
          {"RGBA32F analysis copy (16 B/pixel)", pixels * 16},
          {"presented RGBA8 copy (4 B/pixel)", pixels * 4}};
}

void checkMemory(const Method& method, int width, int height, const SceneGeometry& geometry, uint64_t limit) {
  const std::vector<MemoryItem> items = method.memoryNeed(width, height, geometry);
  uint64_t total = 0;
  for (const MemoryItem& i : items) total = i.bytes > UINT64_MAX - total ? UINT64_MAX : total + i.bytes;
  if (total <= limit) return;
  std::string list;
  for (const MemoryItem& i : items) list += "\n  " + formatBytes(i.bytes) + "  " + i.what;
  throw std::runtime_error("method '" + method.info().name + "' at " + std::to_string(width) + "x" + std::to_string(height) +
                           " needs " + formatBytes(total) + ", above the memory limit of " + formatBytes(limit) +
                           " (--memory-limit):" + list + "\nRender smaller or raise --memory-limit.");
}

std::vector<MethodInfo> allMethods() {
  std::vector<MethodInfo> out;
  for (const Entry& e : registry()) out.push_back(e.info());
  return out;
}

std::unique_ptr<Method> makeMethod(const std::string& name, const std::map<std::string, std::string>& options) {
  std::vector<std::string> names;
  for (const Entry& e : registry()) {
    if (e.info().name == name) return e.make(MethodOptions(e.info(), options));
    names.push_back(e.info().name);
  }
  std::string valid;
  for (const std::string& n : names) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown method '" + name + "'" + util::didYouMean(name, names) + " (valid: " + valid + ")");
}

}  // namespace oitref
