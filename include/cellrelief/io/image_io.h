// SPDX-License-Identifier: MIT
/// @file image_io.h
/// Reading PNG (8 and 16 bit), JPEG, TGA and BMP (including RLE-compressed BMP) through stb_image,
/// and writing PNG (8 and 16 bit) through libpng, atomically. stb does not write 16-bit PNG, and
/// distance maps and relief maps need 16 bits, hence libpng for writing.
#pragma once

#include <algorithm>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <png.h>
#include <stb_image.h>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/io/atomic_file.h"
#include "cellrelief/io/detail/bmp_rle.h"
#include "cellrelief/io/detail/image_checks.h"
#include "cellrelief/io/paths.h"

namespace cellrelief::io {

/// An image as stored in its file: 8-bit or 16-bit channels, 1 to 4 of them.
struct ImageFile {
  std::variant<Image<std::uint8_t>, Image<std::uint16_t>> pixels;
  std::string format;  ///< "png", "jpeg", "tga", "bmp"

  int width() const { return std::visit([](const auto& im) { return im.width(); }, pixels); }
  int height() const { return std::visit([](const auto& im) { return im.height(); }, pixels); }
  int channels() const { return std::visit([](const auto& im) { return im.channels(); }, pixels); }
  int bitDepth() const { return pixels.index() == 0 ? 8 : 16; }
  /// One texel as floats in [0, 1] (UNORM), missing channels as (0, 0, 0, 1).
  Vec4f fetch(int x, int y) const {
    return std::visit([&](const auto& im) { return im.fetch(x, y); }, pixels);
  }
  /// Channel `channel` (or the mean of the colour channels when -1) as a one-channel float image.
  Image<float> toFloat(int channel = -1) const {
    Image<float> out(width(), height(), 1);
    const int colours = channels() >= 3 ? 3 : 1;
    for (int y = 0; y < height(); ++y)
      for (int x = 0; x < width(); ++x) {
        const Vec4f t = fetch(x, y);
        out.at(x, y, 0) = channel >= 0 ? t[channel] : (colours == 3 ? (t.r + t.g + t.b) / 3 : t.r);
      }
    return out;
  }
};

inline const std::vector<std::string>& imageExtensions() {
  static const std::vector<std::string> kExtensions{".png", ".jpg", ".jpeg", ".tga", ".bmp"};
  return kExtensions;
}

inline bool isImageFile(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  return std::find(imageExtensions().begin(), imageExtensions().end(), ext) !=
         imageExtensions().end();
}

namespace detail {
inline std::string imageFormat(const std::vector<unsigned char>& b) {
  if (b.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return "png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "jpeg";
  if (b.size() >= 2 && b[0] == 'B' && b[1] == 'M') return "bmp";
  return "tga";  // TGA has no magic number; stb decides
}
}  // namespace detail

struct ImageReadOptions {
  /// Refuse (ResourceLimit) an image of more pixels than this before decoding it: decoding costs
  /// time in proportion to the pixels, and a small file can claim many (a 2.9 KB JPEG, 625,000).
  std::uint64_t maxPixels = std::numeric_limits<std::uint64_t>::max();
};

/// Reads an image. Throws Error naming the file and the problem.
inline ImageFile readImage(const std::filesystem::path& path, const ImageReadOptions& options = {}) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(ErrorKind::FileNotFound, path, "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::FileNotFound, path, "cannot open for reading");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  if (bytes.empty()) throw Error(ErrorKind::FileFormat, path, "file is empty");
  if (bytes.size() > std::size_t(std::numeric_limits<int>::max()))
    throw Error(ErrorKind::ResourceLimit, path, "file of 2 GiB or more");

  ImageFile result;
  result.format = detail::imageFormat(bytes);
  const std::string structure = result.format == "png"   ? detail::checkPngChunks(bytes)
                              : result.format == "jpeg" ? detail::checkJpegTables(bytes)
                              : result.format == "tga" ? detail::checkTgaSize(bytes)
                              : result.format == "bmp" && !detail::isRleBmp(bytes) ? detail::checkBmpSize(bytes)
                                                                                   : std::string();
  if (!structure.empty()) throw Error(ErrorKind::FileFormat, path, structure);
  if (detail::isRleBmp(bytes)) {
    std::string problem;
    Image<std::uint8_t> im = detail::decodeRleBmp(bytes, problem);
    if (!problem.empty()) throw Error(ErrorKind::FileFormat, path, problem);
    result.pixels = std::move(im);
    return result;
  }

  const auto* data = bytes.data();
  const int size = static_cast<int>(bytes.size());
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(data, size, &w, &h, &comp))
    throw Error(ErrorKind::FileFormat, path,
                std::string("not a readable PNG, JPEG, TGA or BMP image (") + stbi_failure_reason() +
                    ")");
  if (w <= 0 || h <= 0 || w > ImageArray<std::uint8_t>::kMaxDimension ||
      h > ImageArray<std::uint8_t>::kMaxDimension)
    throw Error(ErrorKind::FileFormat, path,
                "image size " + std::to_string(w) + "x" + std::to_string(h) + " is out of range");
  if (std::uint64_t(w) * std::uint64_t(h) > options.maxPixels)
    throw Error(ErrorKind::ResourceLimit, path,
                "image of " + std::to_string(w) + "x" + std::to_string(h) + " pixels, over the limit of " +
                    std::to_string(options.maxPixels));
  if (result.format == "jpeg")
    if (const std::string p = detail::checkJpegSize(std::uint64_t(w), std::uint64_t(h), bytes.size()); !p.empty())
      throw Error(ErrorKind::FileFormat, path, p);
  auto copyInto = [&](auto* pixels, auto& image) {
    std::copy(pixels, pixels + std::size_t(w) * h * comp, image.levelData(0).begin());
  };
  using StbPixels = std::unique_ptr<void, void (*)(void*)>;  // freed even if Image throws
  if (stbi_is_16_bit_from_memory(data, size)) {
    stbi_us* pixels = stbi_load_16_from_memory(data, size, &w, &h, &comp, 0);
    const StbPixels owner(pixels, stbi_image_free);
    if (!pixels)
      throw Error(ErrorKind::FileFormat, path,
                  std::string("cannot decode 16-bit image: ") + stbi_failure_reason());
    Image<std::uint16_t> im(w, h, comp);
    copyInto(pixels, im);
    result.pixels = std::move(im);
  } else {
    stbi_uc* pixels = stbi_load_from_memory(data, size, &w, &h, &comp, 0);
    const StbPixels owner(pixels, stbi_image_free);
    if (!pixels)
      throw Error(ErrorKind::FileFormat, path,
                  std::string("cannot decode image: ") + stbi_failure_reason());
    Image<std::uint8_t> im(w, h, comp);
    copyInto(pixels, im);
    result.pixels = std::move(im);
  }
  return result;
}

namespace detail {
template <class T>
void writePngImpl(const Image<T>& image, const std::filesystem::path& path) {
  static_assert(std::is_same_v<T, std::uint8_t> || std::is_same_v<T, std::uint16_t>);
  if (image.isEmpty()) throw Error(ErrorKind::InvalidArgument, path, "cannot write an empty image");
  AtomicFile file(path);
  std::FILE* fp = std::fopen(file.temporaryPath().c_str(), "wb");
  if (!fp) throw Error(ErrorKind::FileWrite, path, "cannot create the file");
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> closer(fp, &std::fclose);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, nullptr);
    throw Error(ErrorKind::FileWrite, path, "libpng could not start");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw Error(ErrorKind::FileWrite, path, "libpng failed while writing (disk full?)");
  }
  static constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                        PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
  const int bitDepth = sizeof(T) * 8;
  png_init_io(png, fp);
  png_set_IHDR(png, info, image.width(), image.height(), bitDepth,
               kColorTypes[image.channels() - 1], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bitDepth == 16) png_set_swap(png);  // PNG is big-endian; our texels are host order
  const auto texels = image.levelData(0);
  const std::size_t rowLength = std::size_t(image.width()) * image.channels();
  for (int y = 0; y < image.height(); ++y)
    png_write_row(png, reinterpret_cast<png_const_bytep>(texels.data() + y * rowLength));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  closer.reset();
  file.commit();
}
}  // namespace detail

/// Writes an 8-bit PNG (1 to 4 channels: gray, gray+alpha, RGB, RGBA), atomically.
inline void writePng(const Image<std::uint8_t>& image, const std::filesystem::path& path) {
  detail::writePngImpl(image, path);
}
/// Writes a 16-bit PNG, atomically.
inline void writePng(const Image<std::uint16_t>& image, const std::filesystem::path& path) {
  detail::writePngImpl(image, path);
}

}  // namespace cellrelief::io
