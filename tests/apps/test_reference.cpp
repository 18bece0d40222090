// The golden set (reference/manifest.txt): every built-in scene × method re-rendered must give
// the same SHA-256 of its raw pixel bits, with 1 and with 3 threads. The images were produced by
// oitref itself; the methods' correctness is checked by the oracle tests, this guards against
// any unintended change of bits.
#include <catch2/catch.hpp>

#include "tools/suite.h"
#include "frame/sha256.h"

using namespace oitref;

TEST_CASE("sha256: the FIPS 180-4 example vectors", "[reference]") {
  auto hash = [](const std::string& s) {
    util::Sha256 h;
    h.update(s.data(), s.size());
    return h.hex();
  };
  CHECK(hash("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(hash("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(hash("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  std::string million(1000000, 'a');
  CHECK(hash(million) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("reference: every scene × method renders to the manifest's bits", "[reference]") {
  const auto manifest = tools::readManifest(OITREF_SOURCE_DIR "/reference/manifest.txt");
  REQUIRE(manifest.size() >= 7 * 9);
  // The per-fragment path (RendererOptions::perFragment) is the span path's oracle: both give the manifest's bits.
  for (auto [threads, perFragment] : {std::pair{1, false}, {3, false}, {2, true}}) {
    Renderer renderer(RendererOptions{threads, 64, perFragment});
    const auto entries = tools::renderReferences(OITREF_SOURCE_DIR "/scenes", renderer, "", false);
    REQUIRE(entries.size() == manifest.size());
    for (size_t i = 0; i < entries.size(); ++i) {
      INFO(entries[i].scene << " " << entries[i].method << " with " << threads << " threads"
                            << (perFragment ? ", per fragment" : ""));
      CHECK(entries[i].scene == manifest[i].scene);
      CHECK(entries[i].method == manifest[i].method);
      CHECK(entries[i].hash == manifest[i].hash);
    }
  }
}

// The llvmpipe profile's golden hashes (reference/manifest_llvmpipe.txt): frames that glcheck
// scene finds bit-equal to Mesa's llvmpipe, kept from changing unnoticed.
// Two of the exact set's three configurations (one thread is the determinism tests' own case).
TEST_CASE("reference: the llvmpipe profile renders to its manifest's bits", "[reference]") {
  const auto manifest = tools::readManifest(OITREF_SOURCE_DIR "/reference/manifest_llvmpipe.txt");
  REQUIRE(manifest.size() >= 7 * 9);
  for (auto [threads, perFragment] : {std::pair{3, false}, {2, true}}) {
    Renderer renderer(RendererOptions{threads, 64, perFragment});
    const auto entries = tools::renderReferences(OITREF_SOURCE_DIR "/scenes", renderer, "", false, "llvmpipe");
    REQUIRE(entries.size() == manifest.size());
    for (size_t i = 0; i < entries.size(); ++i) {
      INFO(entries[i].scene << " " << entries[i].method << " with " << threads << " threads" << (perFragment ? ", per fragment" : ""));
      CHECK(entries[i].method == manifest[i].method);
      CHECK(entries[i].hash == manifest[i].hash);
    }
  }
}
