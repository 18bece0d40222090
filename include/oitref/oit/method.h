// OIT methods: each is the sequence of passes a GPU would run, over the emulated pipeline, on the
// attachments it declares.
//
// Every method draws the scene's opaque objects into "opaque" (RGBA8, cleared to the
// background) and "depth" (d24, cleared to 1), runs its own transparent passes, and composites
// into "opaque" as a GPU would present it. Beside the declared attachments oitref keeps one
// analysis target, an RGBA32F copy of the background that receives the same composite, so the
// result is also available without the final 8-bit quantisation; it is not counted in the
// memory a GPU would need.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "oitref/core/depth.h"
#include "oitref/core/format.h"
#include "oitref/oit/fragment_lists.h"
#include "oitref/oit/frame_stats.h"
#include "oitref/core/image.h"
#include "oitref/core/memory_limit.h"
#include "oitref/core/profile.h"
#include "oitref/core/renderer.h"
#include "oitref/oit/scene.h"
#include "oitref/oit/scene_geometry.h"

namespace oitref {

struct AttachmentDecl {
  std::string name;
  std::string purpose;
  bool isDepth = false;
  Format format{};                       // colour attachments
  DepthFormat depthFormat = DepthFormat::D24;  // depth attachments
  // Whether the method's composite (its last full-screen pass) reads it: false for a depth
  // attachment, and for one only earlier passes read (AttachmentList::readBeforeCompositeOnly).
  // What glcheck's composite floor counts.
  bool readByComposite = true;
  int bytesPerTexel() const;
  std::string formatName() const;
};

// What a free-form option's value may be: text (none), an integer or a real number, finite and in
// [min, max]; `orAuto`: the word "auto" too. MethodOptions checks every given value against it.
struct OptionNumber {
  enum class Kind : uint8_t { None, Integer, Real };
  Kind kind = Kind::None;
  double min = 0, max = 0;
  bool orAuto = false;
  static OptionNumber integer(double min, double max) { return {Kind::Integer, min, max, false}; }
  static OptionNumber real(double min, double max, bool orAuto = false) { return {Kind::Real, min, max, orAuto}; }
  // "an integer in 1..1024", "a number in 0..1 or auto"; empty for text.
  std::string describe() const;
};

struct MethodOption {
  std::string key, defaultValue, meaning;
  std::vector<std::string> choices;  // empty: free-form (a number as `number` says)
  OptionNumber number{};
};

// A named configuration of a method's options, e.g. "thesis": the formats, weights and constants a
// source prints. Given as the option preset=NAME, its values replace the defaults, and the other
// options given beside it replace those in turn (preset=thesis accum=rgba16f: the thesis's
// configuration with 16-bit accumulation).
struct MethodPreset {
  std::string name, meaning;
  std::map<std::string, std::string> values;
};

// Option values by key, as given: {{"accum", "rgba16f"}}; {} is a method's defaults.
using OptionValues = std::map<std::string, std::string>;

struct MethodInfo {
  std::string name, summary;
  std::vector<MethodOption> options;
  std::vector<MethodPreset> presets = {};  // when not empty, the method also takes preset=none|NAME…
  // When not empty: the inputs for which the method's published arithmetic gives NaN or inf pixels
  // at its defaults (as a GPU running it would). Empty: a non-finite pixel at defaults is a defect.
  std::string nonFiniteWhen = {};
  // The configurations worth a row of `oitref study` beside the method's defaults (formats,
  // weights, the presets its sources print).
  std::vector<OptionValues> studyVariants = {};
  // The configurations of the stability atlas, `oitref stress` ({} is the defaults); empty: the
  // method is not in the atlas.
  std::vector<OptionValues> stressVariants = {};
};

// Option values by key ("accum" -> "rgba16f"); every key of the method, defaults filled in (and
// "preset", "none" unless given, for a method with presets).
class MethodOptions {
 public:
  // Throws std::invalid_argument for unknown keys (with the nearest valid key) or values outside
  // the option's choices, presets included.
  MethodOptions(const MethodInfo& info, const std::map<std::string, std::string>& given);
  // Every value converted here, once, as its option declares it:
  const std::string& text(const std::string& key) const;
  double number(const std::string& key) const;  // throws naming the key when not a number
  int integer(const std::string& key) const;    // an OptionNumber::integer option
  bool flag(const std::string& key) const;      // "true" / "false"
  Format format(const std::string& key) const;  // a format name (parseFormat); throws naming the key
  // The value's place among the option's choices, as E: an enum whose enumerators are declared
  // in the order of the choices (weight=az5 of {one, z3, z5, az3, az5} → E(4)).
  template <typename E>
  E choice(const std::string& key) const {
    return E(choiceIndex(key));
  }
  int choiceIndex(const std::string& key) const;
  // Whether the option's value is `choice`: one of its choices (or "auto" where it allows that);
  // naming anything else throws std::logic_error, so a misspelt comparison cannot be silently false.
  bool is(const std::string& key, const std::string& choice) const;
  const std::map<std::string, std::string>& all() const { return values_; }

 private:
  std::string method_;
  std::vector<MethodOption> options_;
  std::map<std::string, std::string> values_;
};

class AttachmentPool;

struct FrameContext {
  const Scene& scene;
  const SceneGeometry& geometry;
  int width, height;
  Profile profile;
  Renderer& renderer;
  // Bytes a frame may use. Checked up front against Method::memoryNeed (checkMemory), and by
  // methods whose storage is known only while rendering (the A-buffer's fragments).
  uint64_t memoryLimit = UINT64_MAX;
  // Where the frame's attachments come from: a pool keeps them between frames, as a GL
  // application keeps its render targets; without one, each frame allocates its own.
  AttachmentPool* pool = nullptr;

  // The camera's projection (at the frame's aspect) times its view: world to clip space.
  glm::mat4 viewProjection() const;
};

// One item of what a frame allocates, for the memory check and its error message.
struct MemoryItem {
  std::string what;
  uint64_t bytes = 0;
};

struct PassReport {
  std::string name;
  double ms = 0;
  DrawStats stats;
};

struct FrameResult {
  Image final8;      // the presented RGBA8 target ("opaque" after compositing)
  Image finalFloat;  // the same composite into the RGBA32F analysis target
  std::vector<PassReport> passes;
  FrameStats stats;                                        // what the frame reports about its own work
  std::vector<std::pair<std::string, Image>> dump;         // every colour attachment, by name
  FragmentLists fragmentLists;  // the A-buffer's (oitref/oit/fragment_lists.h); empty for other methods

  double frameMs() const;
  uint64_t fragmentsShaded() const;
};

// Colour images and depth buffers kept between frames. A frame takes what its method declares
// (FrameTargets), and gives back its depth buffers when it ends and its colour images when the
// caller recycles the FrameResult. What a taken attachment holds is undefined, as a new GL
// texture's contents are: every method clears what it reads (checked by "methods: a pooled frame
// gives the bits of a fresh one").
class AttachmentPool {
 public:
  Image takeImage(const Format& format, int width, int height);
  DepthBuffer takeDepth(DepthFormat format, int width, int height);
  // Takes an attachment back when one of its format and size is out on loan (else lets it go):
  // what the pool holds never outgrows what frames take from it.
  void give(Image&& image);
  void give(DepthBuffer&& depth);
  // The A-buffer's fragment storage, as a GL application keeps its storage buffer: n fragments
  // whose values are undefined (the A-buffer writes every one), in the kept buffer where there is
  // one (no new pages to fault in and zero: at 1080p of `dense`, 1.7 GB a frame).
  std::vector<TransparentFragment> takeFragments(size_t n);
  // Gives back every image of a finished frame (final8, finalFloat, dump) and its fragment
  // storage, and empties it.
  void recycle(FrameResult&& frame);
  size_t size() const { return images_.size() + depths_.size() + (fragments_.capacity() > 0); }  // attachments kept

 private:
  template <typename F>
  struct Kind {
    F format;
    int width, height;
    bool operator==(const Kind&) const = default;
  };
  using ImageKind = Kind<Format>;
  using DepthKind = Kind<DepthFormat>;
  std::vector<Image> images_;
  std::vector<DepthBuffer> depths_;
  std::vector<ImageKind> lentImages_;  // one entry per attachment out on loan
  std::vector<DepthKind> lentDepths_;
  std::vector<TransparentFragment> fragments_;  // kept fragment storage (capacity 0: none)
  int lentFragments_ = 0;                       // fragment buffers out on loan
};

class Method {
 public:
  virtual ~Method() = default;
  virtual const MethodInfo& info() const = 0;
  // What the method allocates at each pixel, as a GPU would.
  virtual std::vector<AttachmentDecl> attachments() const = 0;
  virtual FrameResult render(const FrameContext& context) = 0;
  int bytesPerPixel() const;
  // What render() allocates for a frame, known before it starts: the declared attachments, the
  // RGBA32F analysis copy and the presented copy in the result, plus each method's own storage.
  virtual std::vector<MemoryItem> memoryNeed(int width, int height, const SceneGeometry& geometry) const;
};

// Throws std::runtime_error when the method's memoryNeed exceeds `limit`, listing the items.
void checkMemory(const Method& method, int width, int height, const SceneGeometry& geometry, uint64_t limit);

// Makes a method with its options checked and converted (MethodOptions).
using MethodFactory = std::function<std::unique_ptr<Method>(const MethodOptions&)>;

// The methods there are, in the order `oitref methods` lists them: the built-in ones
// (src/oit/methods/builtin_methods.def), then those added with registerMethod, in the order added.
std::vector<MethodInfo> allMethods();
// Throws std::invalid_argument for an unknown method (with the nearest name) or bad options.
std::unique_ptr<Method> makeMethod(const std::string& name, const std::map<std::string, std::string>& options = {});
// Adds a method beside the built-in ones: from then on makeMethod, allMethods and every tool
// that goes through them (render, study, stress, suite, the Python module) know it. Throws
// std::invalid_argument, naming the method and what is wrong, when the name is taken or not
// [a-z][a-z0-9_]*, when two options share a key, or when a default, preset or variant is not
// valid for the options: the checks every built-in method passes too. Safe to call from any
// thread; a program usually registers its methods once, at start.
void registerMethod(MethodInfo info, MethodFactory make);

}  // namespace oitref
