// What a renderer's test suite asks oitref: the bits an RGBA16F target stores after one OVER
// blend, in each profile; and one frame of a scene with its hash and image.
//   oitref_consumer SCENE.json [OUT.png]
#include <cstdint>
#include <cstdio>
#include <exception>

#include <oitref/core/blend.h>
#include <oitref/core/format.h>
#include <oitref/oit/frame.h>
#include <oitref/oit/image_io.h>

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s SCENE.json [OUT.png]\n", argv[0]);
    return 2;
  }
  try {
    using namespace oitref;
    const Format rgba16f = parseFormat("rgba16f");
    const BlendState over = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha,
                                                 BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::OneMinusSrcAlpha);
    for (const char* name : {"exact", "llvmpipe", "nvidia"}) {
      const Profile profile = parseProfile(name);
      uint8_t texel[16] = {};
      encodeTexel(rgba16f, {0.2f, 0.4f, 0.6f, 1.0f}, profile, texel);
      blendIntoTexel(rgba16f, over, glm::vec4(0.0f), profile, {0.9f, 0.1f, 0.3f, 0.7f}, texel);
      std::printf("blend rgba16f %s bits %s\n", name, texelBitsToString(rgba16f, texel).c_str());
    }

    FrameRequest request;
    request.method = "wboit";
    request.width = 96, request.height = 72;
    request.threads = 2;
    const FrameResult frame = renderFrame(loadScene(argv[1]), request);
    std::printf("frame wboit %dx%d sha256 %s\n", frame.final8.width(), frame.final8.height(), frameHash(frame).c_str());
    if (argc == 3) writeImage(argv[2], frame.final8);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oitref_consumer: %s\n", e.what());
    return 1;
  }
}
