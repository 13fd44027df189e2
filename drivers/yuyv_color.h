#pragma once
// YUYV (YUV 4:2:2, byte order Y0 U Y1 V per pixel pair) <-> RGB8, ITU-R BT.601 limited range
// (Y 16-235, U/V 16-240), the encoding of UVC colour streams such as the D415's. Integer
// arithmetic in 8.8 fixed point. Colour round trips within a few levels when both pixels of a
// pair share a colour; chroma is averaged over the pair otherwise. (libv4lconvert would also do
// it, but only behind its own buffer management; this is the 20 lines it takes.)

#include <cstddef>
#include <cstdint>
#include <vector>

namespace drivers {

// yuyv: width*height*2 bytes (width even); rgb resized to width*height*3.
void yuyv_to_rgb(const std::uint8_t* yuyv, int width, int height, std::vector<std::uint8_t>& rgb);

// rgb: width*height*3 bytes (width even); yuyv resized to width*height*2.
void rgb_to_yuyv(const std::uint8_t* rgb, int width, int height, std::vector<std::uint8_t>& yuyv);

}  // namespace drivers
