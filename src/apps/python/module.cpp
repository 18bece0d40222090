// `import oitref`: formats, blending, frames and metrics on numpy arrays (pybind11).
//
// Arrays of texels carry the channels in their last axis: values are float32 (..., 4) RGBA, bits
// are uint8 (..., bytes per texel) in the format's own layout. Images are (height, width, ...)
// with the top row first, as image files and plotting libraries expect (oitref's own images are
// stored bottom row first, as GL's).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <variant>
#include <stdexcept>
#include <string>
#include <vector>

#include "oitref/core/blend.h"
#include "oitref/core/format.h"
#include "oitref/oit/frame.h"
#include "oitref/oit/metrics.h"

namespace py = pybind11;
using namespace oitref;

namespace {

using Floats = py::array_t<float, py::array::c_style | py::array::forcecast>;
using Bytes = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>;

// The array's shape without its last axis, after checking that axis.
std::vector<py::ssize_t> leadingShape(const py::array& a, py::ssize_t last, const char* what) {
  if (a.ndim() < 1 || a.shape(a.ndim() - 1) != last)
    throw std::invalid_argument(std::string(what) + ": the last axis must have " + std::to_string(last) + " entries, got shape (" +
                                [&] {
                                  std::string s;
                                  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
                                  return s;
                                }() + ")");
  return std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim() - 1);
}
size_t count(const std::vector<py::ssize_t>& shape) {
  size_t n = 1;
  for (py::ssize_t s : shape) n *= size_t(s);
  return n;
}
std::vector<py::ssize_t> with(std::vector<py::ssize_t> shape, py::ssize_t last) {
  shape.push_back(last);
  return shape;
}
glm::vec4 rgba(const float* p, py::ssize_t channels) {
  glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f);
  for (py::ssize_t c = 0; c < channels; ++c) v[int(c)] = p[c];
  return v;
}

// Values of 1 to 4 channels (missing ones: 0, alpha 1) into the format's bits.
Bytes encode(const std::string& format, Floats values, const std::string& profile) {
  const Format f = parseFormat(format);
  const Profile p = parseProfile(profile);
  const py::ssize_t channels = values.ndim() ? values.shape(values.ndim() - 1) : 0;
  if (channels < 1 || channels > 4) throw std::invalid_argument("encode: the last axis must hold 1 to 4 channels");
  const std::vector<py::ssize_t> shape = leadingShape(values, channels, "encode");
  Bytes out(with(shape, f.bytesPerTexel()));
  const float* in = values.data();
  uint8_t* bits = out.mutable_data();
  for (size_t i = 0, n = count(shape); i < n; ++i) encodeTexel(f, rgba(in + i * channels, channels), p, bits + i * f.bytesPerTexel());
  return out;
}

// The format's bits as RGBA values, exactly (missing channels: 0, alpha 1).
Floats decode(const std::string& format, Bytes bits) {
  const Format f = parseFormat(format);
  const std::vector<py::ssize_t> shape = leadingShape(bits, f.bytesPerTexel(), "decode");
  Floats out(with(shape, 4));
  float* v = out.mutable_data();
  for (size_t i = 0, n = count(shape); i < n; ++i) {
    const glm::vec4 d = decodeTexel(f, bits.data() + i * f.bytesPerTexel());
    std::memcpy(v + 4 * i, &d, sizeof d);
  }
  return out;
}

// `oitref blend` over arrays: each destination stored first (converted to the format), then
// the source blended into it. Returns the stored bits and their values.
py::tuple blend(const std::string& format, Floats source, Floats destination, const std::string& equation,
                const std::string& func, std::vector<float> constant, const std::string& profile) {
  const Format f = parseFormat(format);
  const Profile p = parseProfile(profile);
  const BlendState state = parseBlendState(equation, func);
  if (constant.size() != 4) throw std::invalid_argument("constant: four values r, g, b, a");
  const std::vector<py::ssize_t> shape = leadingShape(source, 4, "source");
  if (leadingShape(destination, 4, "destination") != shape) throw std::invalid_argument("source and destination differ in shape");
  Bytes bits(with(shape, f.bytesPerTexel()));
  Floats values(with(shape, 4));
  const glm::vec4 k(constant[0], constant[1], constant[2], constant[3]);
  for (size_t i = 0, n = count(shape); i < n; ++i) {
    uint8_t* texel = bits.mutable_data() + i * f.bytesPerTexel();
    encodeTexel(f, rgba(destination.data() + 4 * i, 4), p, texel);
    blendIntoTexel(f, state, k, p, rgba(source.data() + 4 * i, 4), texel);
    const glm::vec4 d = decodeTexel(f, texel);
    std::memcpy(values.mutable_data() + 4 * i, &d, sizeof d);
  }
  return py::make_tuple(bits, values);
}

// An image as (height, width, channels) values, top row first.
Floats imageValues(const Image& image) {
  const int w = image.width(), h = image.height(), c = image.format().channels;
  Floats out({py::ssize_t(h), py::ssize_t(w), py::ssize_t(c)});
  float* v = out.mutable_data();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 d = image.fetch(x, h - 1 - y);
      for (int k = 0; k < c; ++k) v[(size_t(y) * w + x) * c + k] = d[k];
    }
  return out;
}
// An image's bits as (height, width, bytes per texel), top row first.
Bytes imageBits(const Image& image) {
  const int w = image.width(), h = image.height();
  const size_t b = image.bytesPerTexel();
  Bytes out({py::ssize_t(h), py::ssize_t(w), py::ssize_t(b)});
  for (int y = 0; y < h; ++y) std::memcpy(out.mutable_data() + size_t(y) * w * b, image.texel(0, h - 1 - y), w * b);
  return out;
}

py::dict statsDict(const FrameStats& s) {
  py::dict d;
  for (const FrameStats::Entry& e : s.entries()) std::visit([&](const auto& v) { d[e.key] = v; }, e.value);
  return d;
}

// A frame of a scene (a file's path, or its JSON as a dict, whose mesh and texture paths are
// relative to `folder`) with a method.
py::dict render(py::object scene, const std::string& method, std::map<std::string, std::string> options,
                std::optional<std::pair<int, int>> size, const std::string& profile, int threads, const std::string& folder) {
  Scene s;
  if (py::isinstance<py::dict>(scene)) {
    const std::string text = py::module_::import("json").attr("dumps")(scene).cast<std::string>();
    s = loadSceneText(text, (std::filesystem::path(folder) / "<dict>").string());
  } else {
    s = loadScene(py::str(scene).cast<std::string>());
  }
  FrameRequest request;
  request.method = method;
  request.options = std::move(options);
  if (size) request.width = size->first, request.height = size->second;
  request.profile = parseProfile(profile);
  request.threads = threads;
  FrameResult frame;
  {
    py::gil_scoped_release unlocked;  // the frame runs on oitref's own workers
    frame = renderFrame(s, request);
  }
  py::dict out;
  out["image"] = imageValues(frame.finalFloat);
  out["final8"] = imageBits(frame.final8);
  py::dict attachments;
  for (const auto& [name, image] : frame.dump) {
    py::dict a;
    a["format"] = image.format().name();
    a["values"] = imageValues(image);
    a["bits"] = imageBits(image);
    attachments[py::str(name)] = a;
  }
  out["attachments"] = attachments;
  out["stats"] = statsDict(frame.stats);
  py::list passes;
  for (const PassReport& p : frame.passes) passes.append(py::make_tuple(p.name, p.ms, p.stats.fragmentsShaded));
  out["passes"] = passes;
  out["frame_ms"] = frame.frameMs();
  out["sha256"] = frameHash(frame);
  return out;
}

// RGBA32F images from (height, width, 1–4) arrays, top row first.
Image imageFrom(Floats a, const char* what) {
  if (a.ndim() != 3 || a.shape(2) < 1 || a.shape(2) > 4)
    throw std::invalid_argument(std::string(what) + ": expected an array of shape (height, width, 1 to 4)");
  const int h = int(a.shape(0)), w = int(a.shape(1)), c = int(a.shape(2));
  Image image(parseFormat("rgba32f"), w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.store(x, h - 1 - y, rgba(a.data() + (size_t(y) * w + x) * c, c), exactProfile());
  return image;
}

py::dict compare(Floats a, Floats b, double threshold) {
  const Image ia = imageFrom(a, "a"), ib = imageFrom(b, "b");
  const ImageDifference d = compareImages(ia, ib, threshold);
  py::dict out;
  out["rmse"] = d.rmse, out["psnr"] = d.psnr, out["mean_abs"] = d.meanAbs, out["max_abs"] = d.maxAbs;
  out["pixels"] = d.pixels, out["pixels_above"] = d.pixelsAbove, out["non_finite_pixels"] = d.nonFinitePixels;
  out["flip"] = flip(ia, ib).mean;
  return out;
}

}  // namespace

PYBIND11_MODULE(oitref, m) {
  m.doc() = "oitref: bit-exact reference blending, formats and OIT frames (see README, 'Python')";
  py::register_exception<std::invalid_argument>(m, "InvalidArgument", PyExc_ValueError);
  m.def("formats", &builtinFormatNames, "The built-in format names (minifloats are also written as rgba:e5m6 and so on).");
  m.def("methods", [] {
    std::vector<std::string> names;
    for (const MethodInfo& i : allMethods()) names.push_back(i.name);
    return names;
  }, "The OIT methods, as `oitref methods` lists them.");
  m.def("encode", &encode, py::arg("format"), py::arg("values"), py::arg("profile") = "exact",
        "Values (..., 1-4 channels) to the format's bits (..., bytes per texel) under the profile's rules.");
  m.def("decode", &decode, py::arg("format"), py::arg("bits"), "The format's bits (..., bytes per texel) as float32 RGBA (..., 4), exactly.");
  m.def("blend", &blend, py::arg("format"), py::arg("source"), py::arg("destination"), py::arg("equation") = "add",
        py::arg("func") = "one,zero", py::arg("constant") = std::vector<float>{0, 0, 0, 0}, py::arg("profile") = "exact",
        "Stores each destination (..., 4) in the format, blends the source (..., 4) into it as a render target would; "
        "returns (bits, values). The same as `oitref blend`.");
  m.def("render", &render, py::arg("scene"), py::arg("method") = "abuffer", py::arg("options") = std::map<std::string, std::string>{},
        py::arg("size") = py::none(), py::arg("profile") = "exact", py::arg("threads") = 0, py::arg("folder") = ".",
        "Renders a scene (a path, or the scene's JSON as a dict whose files are relative to `folder`) with a method; returns the final image (float32, "
        "top row first), the RGBA8 target's bits, every attachment's values and bits, the stats, the passes and the "
        "frame's sha256 (as `oitref render` prints it).");
  m.def("compare", &compare, py::arg("a"), py::arg("b"), py::arg("threshold") = 0.0,
        "RMSE, PSNR, mean and max error, pixels above the threshold and mean FLIP of two (height, width, 1-4) images.");
}
