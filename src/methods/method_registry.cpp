// The list of methods, their options, and the pieces of the Method interface they share.
#include <algorithm>
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
      {methods::wboitInfo, methods::makeWboit},   {methods::mboitInfo, methods::makeMboit},
      {methods::peelInfo, methods::makePeel},
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

MethodOptions::MethodOptions(const MethodInfo& info, const std::map<std::string, std::string>& given)
    : method_(info.name) {
  std::vector<std::string> keys;
  for (const MethodOption& o : info.options) {
    values_[o.key] = o.defaultValue;
    keys.push_back(o.key);
  }
  for (const auto& [key, value] : given) {
    const auto option = std::find_if(info.options.begin(), info.options.end(), [&](const MethodOption& o) { return o.key == key; });
    if (option == info.options.end())
      throw std::invalid_argument("method '" + info.name + "' has no option '" + key + "'" + util::didYouMean(key, keys) +
                                  (keys.empty() ? " (it takes none)" : ""));
    if (!option->choices.empty() && std::find(option->choices.begin(), option->choices.end(), value) == option->choices.end()) {
      std::string valid;
      for (const std::string& c : option->choices) valid += (valid.empty() ? "" : ", ") + c;
      throw std::invalid_argument("method '" + info.name + "' option '" + key + "': '" + value + "' is not one of " + valid);
    }
    values_[key] = value;
  }
  for (const MethodOption& o : info.options)
    if (o.choices.empty()) number(o.key);  // free-form options are numbers: check them now
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
