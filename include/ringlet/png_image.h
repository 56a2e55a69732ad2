// PNG files of rendered images (libpng): linear radiance to 8-bit sRGB, and back for tests.
#pragma once

#include <string>
#include <vector>

#include "ringlet/render.h"

namespace ringlet {

/// The 8-bit sRGB codes that WritePng stores, row-major, 3 per pixel (R, G, B): each channel
/// times exposure, clamped to [0, 1] (NaN counts as 0), encoded with the sRGB transfer function
/// (IEC 61966-2-1) and rounded to the nearest of the 256 codes.
std::vector<unsigned char> EncodeSrgb8(const Image& image, double exposure);

/// Writes image to path as an 8-bit RGB PNG: each channel is multiplied by exposure, clamped to
/// [0, 1] and encoded with the sRGB transfer function (IEC 61966-2-1), with an sRGB chunk.
/// Written through a temporary file (atomic_file.h): an existing file is replaced only when
/// overwrite is true, and a failure leaves nothing behind. Returns false with a one-line message.
bool WritePng(const std::string& path, const Image& image, double exposure, bool overwrite,
              std::string* error);

/// The bytes of the PNG file WritePng writes, for writing with other files at once
/// (WriteFilesAtomically). Returns false with a one-line message (no path).
bool EncodePng(const Image& image, double exposure, std::string* png, std::string* error);

/// The bytes of a PNG file of 8-bit codes stored as they are (label maps, docs/batch.md): no
/// exposure, no transfer function and no colour chunk; channels 1 (grey) or 3 (RGB), codes
/// row-major (top row first, channels interleaved), width x height x channels of them. Returns
/// false with a one-line message.
bool EncodePngCodes(const std::vector<unsigned char>& codes, int width, int height, int channels,
                    std::string* png, std::string* error);

/// Reads an 8-bit RGB or RGBA PNG into linear values (the inverse sRGB transfer function;
/// alpha dropped). Returns false with a one-line message naming the file.
bool ReadPng(const std::string& path, Image* image, std::string* error);

}  // namespace ringlet
