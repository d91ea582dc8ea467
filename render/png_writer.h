#pragma once
// PNG files (libpng, the only libpng user): atomic writes and reads into an Image.

#include <string>

#include "render/image.h"

namespace ecpsim::render {

/// Fast zlib level for frame sequences: ~3× faster than the default 6 for ~20% larger files.
inline constexpr int kFastPngCompression = 1;

/// Writes `image` as an 8-bit RGB PNG at `path`, atomically (common/atomic_file.h): to a temporary
/// file in the same directory, then renamed over `path`, so readers never see a half-written file.
/// `compression` is the zlib level, 0 (none) to 9 (smallest).
/// @throws InputError naming the path and the system's reason if the file cannot be written, if
///         something other than a regular file is at `path`, or if the image is empty or its
///         buffer size does not match width × height × 3.
void WritePng(const std::string& path, const Image& image, int compression = kFastPngCompression);

/// Reads any PNG (grey, palette, RGBA, 16-bit: converted to 8-bit RGB; alpha composited on black
/// per libpng's simplified API) into an Image.
/// @throws InputError naming the path if it is missing, unreadable or not a valid PNG.
Image ReadPng(const std::string& path);

}  // namespace ecpsim::render
