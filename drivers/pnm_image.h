#pragma once
// Binary Netpbm images, the frame files of a recorded camera session: depth as 16-bit PGM (P5,
// maxval 65535, big-endian samples as the Netpbm spec says; value = raw depth count) and colour
// as 8-bit PPM (P6, maxval 255, RGB). Any image viewer and numpy/OpenCV read them.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace drivers {

// Write the image to `path`; return an error message naming the path, or "" on success.
std::string write_pgm16(const std::filesystem::path& path, int width, int height,
                        const std::vector<std::uint16_t>& pixels);
std::string write_ppm8(const std::filesystem::path& path, int width, int height,
                       const std::vector<std::uint8_t>& rgb);

// Read an image and check its size; throw std::runtime_error naming the path and what was wrong
// (bad magic, header, maxval, size other than expected, truncated data).
std::vector<std::uint16_t> read_pgm16(const std::filesystem::path& path, int width, int height);
std::vector<std::uint8_t> read_ppm8(const std::filesystem::path& path, int width, int height);

}  // namespace drivers
