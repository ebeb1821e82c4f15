// compare_images A B [C ...]: exit 0 when all images have the same size and identical pixels,
// else print where the first difference is and exit 1.
#include <cstdio>

#include "forest/core/image.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: compare_images A B [C ...]\n");
    return 2;
  }
  try {
    const forest::Image8 reference = forest::readImage8(argv[1]);
    for (int i = 2; i < argc; ++i) {
      const forest::Image8 other = forest::readImage8(argv[i]);
      if (other.width != reference.width || other.height != reference.height ||
          other.channels != reference.channels) {
        std::fprintf(stderr, "%s and %s differ in size\n", argv[1], argv[i]);
        return 1;
      }
      for (size_t k = 0; k < reference.pixels.size(); ++k) {
        if (reference.pixels[k] != other.pixels[k]) {
          const size_t pixel = k / static_cast<size_t>(reference.channels);
          std::fprintf(stderr, "%s and %s differ at pixel (%zu, %zu)\n", argv[1], argv[i],
                       pixel % static_cast<size_t>(reference.width), pixel / static_cast<size_t>(reference.width));
          return 1;
        }
      }
    }
    std::printf("%d images identical (%dx%d)\n", argc - 1, reference.width, reference.height);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare_images: %s\n", e.what());
    return 1;
  }
}
