// PNG files of rendered images with libpng (http://www.libpng.org/pub/png/libpng-manual.txt):
// linear radiance -> exposure, clamp, sRGB transfer function (IEC 61966-2-1, io/srgb.h) -> 8-bit
// RGB, encoded in memory and written atomically (atomic_file.h); reading does the inverse.
//
// libpng reports errors by longjmp to the setjmp point of the caller (manual, section III, "Setup").
// Every libpng call therefore lives in a small function whose locals are plain pointers and
// integers, so that the jump skips no destructor; buffers are owned by the callers.
#include "ringlet/png_image.h"

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstring>
#include <string>
#include <vector>

#include "io/srgb.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

// Largest image read back (pixels): a corrupt header cannot ask for gigabytes.
constexpr long long kMaxReadPixels = 1LL << 28;

// Where libpng's error callback leaves its message before jumping back.
struct PngErrorState {
  char message[256] = {};
};

[[noreturn]] void OnPngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
  if (state) {
    std::strncpy(state->message, message ? message : "unknown libpng error",
                 sizeof(state->message) - 1);
  }
  png_longjmp(png, 1);
}

void OnPngWarning(png_structp, png_const_charp) {}  // warnings change nothing we report

void AppendBytes(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data),
                                                         length);
}

void FlushNothing(png_structp) {}

// The bytes being decoded and the read position.
struct MemorySource {
  const unsigned char* data = nullptr;
  size_t size = 0;
  size_t position = 0;
};

void ReadBytes(png_structp png, png_bytep out, png_size_t length) {
  auto* source = static_cast<MemorySource*>(png_get_io_ptr(png));
  if (length > source->size - source->position) {
    png_error(png, "truncated file (unexpected end of data)");
  }
  std::memcpy(out, source->data + source->position, length);
  source->position += length;
}

// Encodes 8-bit RGB rows (top first) into *bytes with an sRGB chunk (plus the gAMA and cHRM
// values the PNG specification, section 11.3.3.5, recommends alongside it for old readers).
// With srgb false and grey true: 8-bit grey rows, stored as they are (label maps), no colour chunk.
bool EncodeRgb8(png_bytep* rows, int width, int height, std::string* bytes,
                PngErrorState* state, bool srgb = true, bool grey = false) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, state, OnPngError,
                                            OnPngWarning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, bytes, AppendBytes, FlushNothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               grey ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (srgb) png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_set_rows(png, info, rows);
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// Reads the header: size, colour type and bit depth.
bool ReadHeader(png_structp png, png_infop info, png_uint_32* width, png_uint_32* height,
                int* color_type, int* bit_depth) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  *width = png_get_image_width(png, info);
  *height = png_get_image_height(png, info);
  *color_type = png_get_color_type(png, info);
  *bit_depth = png_get_bit_depth(png, info);
  return true;
}

// Reads every row (interlaced images included, libpng handles the passes) and the end chunks.
bool ReadRows(png_structp png, png_infop info, png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  return true;
}

}  // namespace

std::vector<unsigned char> EncodeSrgb8(const Image& image, double exposure) {
  std::vector<unsigned char> rgb(image.pixels.size() * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      rgb[3 * i + c] = internal::LinearToSrgb8(exposure * static_cast<double>(image.pixels[i][c]));
    }
  }
  return rgb;
}

bool WritePng(const std::string& path, const Image& image, double exposure, bool overwrite,
              std::string* error) {
  std::string bytes, why;
  if (!EncodePng(image, exposure, &bytes, &why)) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return WriteFileAtomically(path, bytes, overwrite, error);
}

bool EncodePng(const Image& image, double exposure, std::string* png, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (image.width < 1 || image.height < 1) {
    return fail("cannot write an image of " + std::to_string(image.width) + " x " +
                std::to_string(image.height) + " pixels (expected at least 1 x 1)");
  }
  if (image.pixels.size() != static_cast<size_t>(image.width) * image.height) {
    return fail("image has " + std::to_string(image.pixels.size()) + " pixels, expected " +
                std::to_string(image.width) + " x " + std::to_string(image.height));
  }
  if (!std::isfinite(exposure) || exposure < 0.0) {
    return fail("exposure must be a finite number >= 0, got " + std::to_string(exposure));
  }
  // Quantize: exposure, clamp, sRGB, 8 bits (io/srgb.h).
  std::vector<unsigned char> rgb = EncodeSrgb8(image, exposure);
  std::vector<png_bytep> rows(static_cast<size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    rows[static_cast<size_t>(y)] = rgb.data() + static_cast<size_t>(y) * image.width * 3;
  }
  std::string bytes;
  PngErrorState state;
  if (!EncodeRgb8(rows.data(), image.width, image.height, &bytes, &state)) {
    return fail(std::string("cannot encode PNG: ") +
                (state.message[0] ? state.message : "libpng could not start"));
  }
  *png = std::move(bytes);
  return true;
}

bool EncodePngCodes(const std::vector<unsigned char>& codes, int width, int height, int channels,
                    std::string* png, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (width < 1 || height < 1 || (channels != 1 && channels != 3)) {
    return fail("cannot write " + std::to_string(width) + " x " + std::to_string(height) +
                " pixels of " + std::to_string(channels) +
                " channels (expected at least 1 x 1, 1 or 3 channels)");
  }
  const size_t row = static_cast<size_t>(width) * channels;
  if (codes.size() != row * height) {
    return fail("label image has " + std::to_string(codes.size()) + " codes, expected " +
                std::to_string(row * height));
  }
  // libpng takes non-const rows; it only reads them while writing.
  std::vector<unsigned char> copy = codes;
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) rows[static_cast<size_t>(y)] = copy.data() + static_cast<size_t>(y) * row;
  std::string bytes;
  PngErrorState state;
  if (!EncodeRgb8(rows.data(), width, height, &bytes, &state, false, channels == 1)) {
    return fail(std::string("cannot encode PNG: ") +
                (state.message[0] ? state.message : "libpng could not start"));
  }
  *png = std::move(bytes);
  return true;
}

bool ReadPng(const std::string& path, Image* image, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  };
  std::string bytes;
  // The largest image ringlet writes (16384 x 16384 RGB) is well below 1 GiB.
  if (!ReadFile(path, &bytes, error, std::uint64_t{1} << 30)) return false;
  if (bytes.size() < 8 ||
      png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0) {
    return fail("not a PNG file (bad signature)");
  }
  PngErrorState state;
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, OnPngError, OnPngWarning);
  if (!png) return fail("libpng could not start");
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return fail("libpng could not start");
  }
  MemorySource source{reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), 0};
  png_set_read_fn(png, &source, ReadBytes);
  const auto invalid = [&]() {
    png_destroy_read_struct(&png, &info, nullptr);
    return fail(std::string("invalid PNG: ") + state.message);
  };

  png_uint_32 width = 0, height = 0;
  int color_type = 0, bit_depth = 0;
  if (!ReadHeader(png, info, &width, &height, &color_type, &bit_depth)) return invalid();
  if (bit_depth != 8 || (color_type != PNG_COLOR_TYPE_RGB && color_type != PNG_COLOR_TYPE_RGBA)) {
    png_destroy_read_struct(&png, &info, nullptr);
    return fail("expected an 8-bit RGB or RGBA PNG, got bit depth " + std::to_string(bit_depth) +
                " and colour type " + std::to_string(color_type));
  }
  if (static_cast<long long>(width) * height > kMaxReadPixels) {
    png_destroy_read_struct(&png, &info, nullptr);
    return fail("image of " + std::to_string(width) + " x " + std::to_string(height) +
                " pixels is too large to read");
  }
  const int channels = color_type == PNG_COLOR_TYPE_RGBA ? 4 : 3;
  const size_t row_bytes = static_cast<size_t>(width) * channels;
  std::vector<unsigned char> pixels(row_bytes * height);
  std::vector<png_bytep> rows(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = pixels.data() + y * row_bytes;
  if (!ReadRows(png, info, rows.data())) return invalid();
  png_destroy_read_struct(&png, &info, nullptr);

  // Decode: 8-bit sRGB -> linear (alpha dropped).
  float table[256];
  for (int v = 0; v < 256; ++v) table[v] = static_cast<float>(internal::SrgbToLinear(v / 255.0));
  Image out;
  out.width = static_cast<int>(width);
  out.height = static_cast<int>(height);
  out.pixels.resize(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    const unsigned char* p = pixels.data() + i * channels;
    out.pixels[i] = Eigen::Vector3f(table[p[0]], table[p[1]], table[p[2]]);
  }
  *image = std::move(out);
  return true;
}

}  // namespace ringlet
