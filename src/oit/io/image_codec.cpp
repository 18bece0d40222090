#include "io/image_codec.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "io/image_codec_abi.h"

namespace oitref::detail {
namespace {

constexpr const char* kModuleName = "liboitref_imageio.so";

// The module's functions, resolved once.
struct Module {
  decltype(&oitref_imageio_open) open = nullptr;
  decltype(&oitref_imageio_read) read = nullptr;
  decltype(&oitref_imageio_close) close = nullptr;
  decltype(&oitref_imageio_can_write) canWrite = nullptr;
  decltype(&oitref_imageio_write) write = nullptr;
};

// The folder of the program or shared module this code is linked into.
std::filesystem::path ownFolder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&ownFolder), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe", ec);
  std::filesystem::path file(info.dli_fname);
  // The program itself is reported by the name it was started with; its real path is surer.
  if (!ec && (file.filename() == self.filename() || file.empty())) file = self;
  return std::filesystem::absolute(file, ec).parent_path();
}

template <typename F>
F symbol(void* handle, const char* name, const std::string& path) {
  void* s = dlsym(handle, name);
  if (!s) throw std::runtime_error(path + ": not oitref's image module (it has no " + name + ")");
  return reinterpret_cast<F>(s);
}

Module load() {
  std::vector<std::string> tried;
  void* handle = nullptr;
  std::string loaded;
  auto attempt = [&](const std::string& path) {
    if (handle) return;
    dlerror();
    handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle) loaded = path;
    else tried.push_back(dlerror());
  };
  if (const char* chosen = std::getenv("OITREF_IMAGEIO_MODULE"); chosen && *chosen) {
    attempt(chosen);
  } else {
    attempt(kModuleName);
    const std::filesystem::path here = ownFolder();
    if (!here.empty()) {
      attempt((here / "lib" / "oitref" / kModuleName).string());
      attempt((here / ".." / OITREF_IMAGEIO_LIBDIR / "oitref" / kModuleName).string());
    }
    attempt(std::string(OITREF_IMAGEIO_BUILD_DIR) + "/" + kModuleName);
  }
  if (!handle) {
    std::string why;
    for (const std::string& t : tried) why += "\n  " + t;
    throw std::runtime_error(std::string("cannot load ") + kModuleName +
                             ", oitref's module for image files (OpenImageIO), which reads and writes PNG and EXR:" + why +
                             "\nInstall or build it with oitref, or set OITREF_IMAGEIO_MODULE to its path.");
  }
  const auto abi = symbol<decltype(&oitref_imageio_abi)>(handle, "oitref_imageio_abi", loaded);
  if (abi() != OITREF_IMAGEIO_ABI)
    throw std::runtime_error(loaded + ": an image module of interface " + std::to_string(abi()) + ", but this oitref needs " +
                             std::to_string(OITREF_IMAGEIO_ABI) + " (a module from another build)");
  Module m;
  m.open = symbol<decltype(m.open)>(handle, "oitref_imageio_open", loaded);
  m.read = symbol<decltype(m.read)>(handle, "oitref_imageio_read", loaded);
  m.close = symbol<decltype(m.close)>(handle, "oitref_imageio_close", loaded);
  m.canWrite = symbol<decltype(m.canWrite)>(handle, "oitref_imageio_can_write", loaded);
  m.write = symbol<decltype(m.write)>(handle, "oitref_imageio_write", loaded);
  return m;  // the handle stays open for the process's life
}

// Loaded by the first caller (a failure throws to that caller and is tried again by the next).
const Module& module() {
  static const Module m = load();
  return m;
}

constexpr size_t kErrorSize = 2048;

}  // namespace

std::unique_ptr<ImageFileReader> ImageFileReader::open(const std::string& path, std::string& error) {
  const Module& m = module();
  oitref_imageio_spec s{};
  char text[kErrorSize] = {};
  void* handle = m.open(path.c_str(), &s, text, sizeof text);
  if (!handle) {
    error = text;
    return nullptr;
  }
  ImageFileSpec spec;
  spec.width = s.width, spec.height = s.height, spec.channels = s.channels;
  spec.sample = ImageSample(s.sample);
  spec.bitsPerSample = s.bits_per_sample;
  spec.formatName = s.format_name;
  return std::unique_ptr<ImageFileReader>(new ImageFileReader(handle, std::move(spec)));
}

ImageFileReader::~ImageFileReader() { module().close(handle_); }

bool ImageFileReader::read(ImageSample sample, void* pixels, std::string& error) {
  char text[kErrorSize] = {};
  if (module().read(handle_, int(sample), pixels, text, sizeof text)) return true;
  error = text;
  return false;
}

bool imageWriterExists(const std::string& path) { return module().canWrite(path.c_str()) != 0; }

bool writeImagePixels(const std::string& path, int width, int height, int channels, ImageSample sample,
                      const void* topRow, std::ptrdiff_t pixelStride, std::ptrdiff_t rowStride, std::string& error) {
  char text[kErrorSize] = {};
  if (module().write(path.c_str(), width, height, channels, int(sample), topRow, pixelStride, rowStride, text, sizeof text))
    return true;
  error = text;
  return false;
}

}  // namespace oitref::detail
