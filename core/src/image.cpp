#include "forest/core/image.hpp"

#include <OpenImageIO/imageio.h>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"

namespace forest {
namespace fs = std::filesystem;
namespace {

// OpenImageIO and OpenEXR start worker pools on first use that outlive the call and are torn down
// in static destructors, racing the leak checker at exit. The engine's images are small: run both
// single-threaded (exr_threads = -1 is OpenEXR's single-threaded mode, "threads" = 1 OIIO's).
void useOiioSingleThreaded() {
  static const bool once = [] {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", -1);
    return true;
  }();
  (void)once;
}

template <typename T>
void writeWithOiio(const fs::path& file, const Image<T>& image, OIIO::TypeDesc type) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height * image.channels) {
    throw Error(file.string() + ": cannot write an image with inconsistent size " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
                std::to_string(image.channels));
  }
  useOiioSingleThreaded();
  writeAtomicallyWith(file, [&](const fs::path& temporary) {
    auto out = OIIO::ImageOutput::create(temporary.string());
    if (!out) throw Error(file.string() + ": no image writer for this extension: " + OIIO::geterror());
    OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // pixels are stored as given, never premultiplied
    if (!out->open(temporary.string(), spec) || !out->write_image(type, image.pixels.data()) ||
        !out->close()) {
      // OpenImageIO names the temporary file; the user asked for `file`.
      std::string why = out->geterror();
      for (const std::string& name : {temporary.string(), temporary.filename().string()})
        for (std::size_t at = why.find(name); at != std::string::npos; at = why.find(name, at + file.string().size()))
          why.replace(at, name.size(), file.string());
      throw Error(file.string() + ": writing the image failed: " + why);
    }
  });
}

template <typename T>
Image<T> readWithOiio(const fs::path& file, OIIO::TypeDesc type) {
  if (!fs::exists(file)) throw InputError(file.string() + ": no such file");
  useOiioSingleThreaded();
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // return the file's pixels, not premultiplied ones
  auto in = OIIO::ImageInput::open(file.string(), &config);
  if (!in) throw InputError(file.string() + ": not a readable image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  Image<T> image(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, type, image.pixels.data())) {
    throw InputError(file.string() + ": reading the image failed: " + in->geterror());
  }
  return image;
}

}  // namespace

void writeImage(const fs::path& file, const Image8& image) { writeWithOiio(file, image, OIIO::TypeDesc::UINT8); }
void writeImage(const fs::path& file, const ImageF& image) { writeWithOiio(file, image, OIIO::TypeDesc::FLOAT); }
Image8 readImage8(const fs::path& file) { return readWithOiio<std::uint8_t>(file, OIIO::TypeDesc::UINT8); }
ImageF readImageF(const fs::path& file) { return readWithOiio<float>(file, OIIO::TypeDesc::FLOAT); }

}  // namespace forest
