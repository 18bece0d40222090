// oitref/oit/method.h: the registry of methods (built-in and registered), their options checked and converted (MethodOptions), and the pieces of the Method interface they share.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <stdexcept>

#include "methods/methods.h"
#include "util/did_you_mean.h"

namespace oitref {
namespace {

// One registered method. Entries live in a deque: a reference to one stays valid as others are
// added.
struct Entry {
  MethodInfo info;
  MethodFactory make;
};

class Registry {
 public:
  Registry();
  void add(MethodInfo info, MethodFactory make);
  std::vector<MethodInfo> infos() const {
    const std::lock_guard lock(mutex_);
    std::vector<MethodInfo> out;
    for (const Entry& e : entries_) out.push_back(e.info);
    return out;
  }
  // The entry called `name`, or null; its `names` are every method's, for the error message.
  const Entry* find(const std::string& name, std::vector<std::string>& names) const {
    const std::lock_guard lock(mutex_);
    for (const Entry& e : entries_) {
      if (e.info.name == name) return &e;
      names.push_back(e.info.name);
    }
    return nullptr;
  }

 private:
  mutable std::mutex mutex_;
  std::deque<Entry> entries_;
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

glm::mat4 FrameContext::viewProjection() const {
  return scene.camera.projection(float(width) / float(height)) * scene.camera.view();
}

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
  options_ = info.options;
  if (!info.presets.empty()) options_.push_back(presetOption(info));
  const std::vector<MethodOption>& options = options_;
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
  // names only declared options (registerMethod has checked every preset).
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

int MethodOptions::integer(const std::string& key) const {
  const double d = number(key);
  if (d != std::floor(d) || std::fabs(d) > 0x1p31)
    throw std::invalid_argument("method '" + method_ + "' option '" + key + "': '" + values_.at(key) + "' is not an integer");
  return int(d);
}

Format MethodOptions::format(const std::string& key) const {
  try {
    return parseFormat(values_.at(key));
  } catch (const std::exception& e) {
    throw std::invalid_argument("method '" + method_ + "' option '" + key + "': " + e.what());
  }
}

bool MethodOptions::is(const std::string& key, const std::string& choice) const {
  for (const MethodOption& o : options_)
    if (o.key == key) {
      const bool declared = std::find(o.choices.begin(), o.choices.end(), choice) != o.choices.end() ||
                            (o.number.orAuto && choice == "auto");
      if (!declared) throw std::logic_error("method '" + method_ + "' option '" + key + "' has no choice '" + choice + "'");
      return values_.at(key) == choice;
    }
  throw std::logic_error("method '" + method_ + "' has no option '" + key + "'");
}

int MethodOptions::choiceIndex(const std::string& key) const {
  for (const MethodOption& o : options_)
    if (o.key == key) {
      const auto it = std::find(o.choices.begin(), o.choices.end(), values_.at(key));
      if (it == o.choices.end()) throw std::logic_error("method '" + method_ + "' option '" + key + "' has no choices to index");
      return int(it - o.choices.begin());
    }
  throw std::logic_error("method '" + method_ + "' has no option '" + key + "'");
}

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

namespace {

bool validMethodName(const std::string& name) {
  if (name.empty() || !(name[0] >= 'a' && name[0] <= 'z')) return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}

// What registerMethod checks, built-in methods included: a method's own description must be
// valid before a user's option can be judged against it.
void checkInfo(const MethodInfo& info) {
  const std::string who = "method '" + info.name + "': ";
  if (!validMethodName(info.name))
    throw std::invalid_argument(who + "a method's name is a lower-case letter, then lower-case letters, digits or '_'");
  std::vector<std::string> keys;
  for (const MethodOption& o : info.options) {
    if (std::find(keys.begin(), keys.end(), o.key) != keys.end() || (o.key == "preset" && !info.presets.empty()))
      throw std::invalid_argument(who + "option '" + o.key + "' is declared twice");
    keys.push_back(o.key);
    if (!o.choices.empty() && std::find(o.choices.begin(), o.choices.end(), o.defaultValue) == o.choices.end())
      throw std::invalid_argument(who + "option '" + o.key + "': the default '" + o.defaultValue + "' is not one of its choices");
    try {
      checkNumber(info.name, o, o.defaultValue);
    } catch (const std::exception& e) {
      throw std::invalid_argument(std::string("the default of ") + e.what());
    }
  }
  const auto check = [&](const std::string& what, const OptionValues& values) {
    try {
      MethodOptions(info, values);
    } catch (const std::exception& e) {
      throw std::invalid_argument(who + what + ": " + e.what());
    }
  };
  check("the defaults", {});
  for (const MethodPreset& p : info.presets) {
    for (const auto& [key, value] : p.values)
      if (std::find(keys.begin(), keys.end(), key) == keys.end())
        throw std::invalid_argument(who + "preset '" + p.name + "' sets option '" + key + "', which the method does not have");
    check("preset '" + p.name + "'", {{"preset", p.name}});
  }
  for (const OptionValues& v : info.studyVariants) check("study variant", v);
  for (const OptionValues& v : info.stressVariants) check("stress variant", v);
}

}  // namespace

Registry::Registry() {
#define OITREF_METHOD(name) add(methods::name##Info(), &methods::name##Factory);
#include "methods/builtin_methods.def"
#undef OITREF_METHOD
}

void Registry::add(MethodInfo info, MethodFactory make) {
  checkInfo(info);
  if (!make) throw std::invalid_argument("method '" + info.name + "': no factory given");
  const std::lock_guard lock(mutex_);
  for (const Entry& e : entries_)
    if (e.info.name == info.name) throw std::invalid_argument("method '" + info.name + "' is already registered");
  entries_.push_back({std::move(info), std::move(make)});
}

void registerMethod(MethodInfo info, MethodFactory make) { registry().add(std::move(info), std::move(make)); }

std::vector<MethodInfo> allMethods() { return registry().infos(); }

std::unique_ptr<Method> makeMethod(const std::string& name, const std::map<std::string, std::string>& options) {
  std::vector<std::string> names;
  if (const Entry* e = registry().find(name, names)) return e->make(MethodOptions(e->info, options));
  std::string valid;
  for (const std::string& n : names) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown method '" + name + "'" + util::didYouMean(name, names) + " (valid: " + valid + ")");
}

}  // namespace oitref
