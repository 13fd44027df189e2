#include "drivers/pnm_image.h"

#include <cctype>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "common/durable_file.h"

namespace drivers {
namespace {

// Written beside, flushed and renamed (common/durable_file.h): after a crash a frame file is whole
// or absent, and the session index names a frame only once it is on the disk.
std::string write_pnm(const std::filesystem::path& path, const char* magic, int width, int height, int maxval,
                      const char* data, std::size_t bytes) {
  try {
    prepreg::write_file_atomically(path, [&](std::ostream& out) {
      out << magic << '\n' << width << ' ' << height << '\n' << maxval << '\n';
      out.write(data, std::streamsize(bytes));
    });
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Reads the next header integer, skipping whitespace and # comments.
int header_int(std::istream& in, const std::filesystem::path& path, const char* what) {
  int c = in.get();
  while (c != EOF && (std::isspace(c) || c == '#')) {
    if (c == '#') {
      while (c != EOF && c != '\n') c = in.get();
    }
    c = in.get();
  }
  std::string digits;
  while (c != EOF && std::isdigit(c)) {
    digits += char(c);
    c = in.get();
  }
  if (digits.empty() || digits.size() > 9) throw std::runtime_error(fmt::format("{}: header: expected the {}", path.string(), what));
  if (c == EOF || !std::isspace(c)) throw std::runtime_error(fmt::format("{}: header: expected whitespace after the {}", path.string(), what));
  return std::stoi(digits);
}

std::string read_pnm(const std::filesystem::path& path, const char* magic, int width, int height, int maxval,
                     std::size_t bytes_per_pixel) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path.string()));
  char m[2] = {0, 0};
  in.read(m, 2);
  if (!in || m[0] != magic[0] || m[1] != magic[1]) {
    throw std::runtime_error(fmt::format("{}: not a binary {} file (magic {} expected)", path.string(),
                                         magic[1] == '5' ? "PGM" : "PPM", magic));
  }
  const int w = header_int(in, path, "width");
  const int h = header_int(in, path, "height");
  const int mv = header_int(in, path, "maxval");
  if (w != width || h != height) {
    throw std::runtime_error(fmt::format("{}: image is {}x{}, expected {}x{}", path.string(), w, h, width, height));
  }
  if (mv != maxval) throw std::runtime_error(fmt::format("{}: maxval {}, expected {}", path.string(), mv, maxval));
  std::string data(std::size_t(width) * height * bytes_per_pixel, '\0');
  in.read(data.data(), std::streamsize(data.size()));
  if (std::size_t(in.gcount()) != data.size()) {
    throw std::runtime_error(fmt::format("{}: truncated: {} of {} data bytes", path.string(), in.gcount(), data.size()));
  }
  if (in.peek() != EOF) throw std::runtime_error(fmt::format("{}: extra bytes after the image data", path.string()));
  return data;
}

}  // namespace

std::string write_pgm16(const std::filesystem::path& path, int width, int height,
                        const std::vector<std::uint16_t>& pixels) {
  if (pixels.size() != std::size_t(width) * height) {
    return fmt::format("{}: {} depth pixels for a {}x{} image", path.string(), pixels.size(), width, height);
  }
  std::string bytes(2 * pixels.size(), '\0');
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    bytes[2 * i] = char(pixels[i] >> 8);  // big-endian, as Netpbm requires
    bytes[2 * i + 1] = char(pixels[i] & 0xff);
  }
  return write_pnm(path, "P5", width, height, 65535, bytes.data(), bytes.size());
}

std::string write_ppm8(const std::filesystem::path& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (rgb.size() != 3 * std::size_t(width) * height) {
    return fmt::format("{}: {} colour bytes for a {}x{} RGB image", path.string(), rgb.size(), width, height);
  }
  return write_pnm(path, "P6", width, height, 255, reinterpret_cast<const char*>(rgb.data()), rgb.size());
}

std::vector<std::uint16_t> read_pgm16(const std::filesystem::path& path, int width, int height) {
  const std::string data = read_pnm(path, "P5", width, height, 65535, 2);
  std::vector<std::uint16_t> pixels(data.size() / 2);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    pixels[i] = std::uint16_t((std::uint8_t(data[2 * i]) << 8) | std::uint8_t(data[2 * i + 1]));
  }
  return pixels;
}

std::vector<std::uint8_t> read_ppm8(const std::filesystem::path& path, int width, int height) {
  const std::string data = read_pnm(path, "P6", width, height, 255, 3);
  return std::vector<std::uint8_t>(data.begin(), data.end());
}

}  // namespace drivers
