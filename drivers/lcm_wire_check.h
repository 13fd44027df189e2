#pragma once
// Checks an encoded LCM message against its type's layout before LCM's generated code decodes it.
//
// Why: lcm-gen's decode allocates an array's elements as soon as it has read the count, and
// checks that the bytes are there only afterwards. A 30-byte packet claiming 2^31 floats made
// the cell allocate (and zero) 8 GB before the decode failed (found by fuzzing, issue 36). Anyone
// on the network segment can publish such a packet. This walk reads the counts the way the
// decoder will and refuses a message whose arrays cannot fit in the bytes that arrived, or
// whose length is not exactly what its fields take. A negative count is refused too (the decode
// would throw std::length_error on it).
//
// The layouts are written out per type in lcm_wire_check.cc from drivers/lcmtypes/*.lcm;
// tests/drivers/lcm_wire_check_test.cc encodes every type and checks that its layout walks
// the message exactly, so a changed .lcm file without a changed layout fails there.

#include <string>
#include <string_view>

namespace drivers {

// Whether a layout is known for the LCM type named `type_name` (T::getTypeName()).
bool has_wire_layout(std::string_view type_name);

// "" when the message (fingerprint included, `size` bytes) fits its type's layout; otherwise
// what does not fit, naming the field ("num_vertices 2147483647 needs 8589934588 bytes, 13
// left"). Throws std::logic_error for a type without a layout.
std::string wire_problem(std::string_view type_name, const void* data, int size);

// Decodes `msg` from `size` bytes after checking them with wire_problem. "" on success,
// otherwise why it was refused (the layout problem, or LCM's fingerprint or length check).
template <typename T>
std::string decode_checked(const void* data, int size, T& msg) {
  std::string problem = wire_problem(T::getTypeName(), data, size);
  if (!problem.empty()) return problem;
  const int used = msg.decode(data, 0, size);
  if (used < 0) return "cannot decode as " + std::string(T::getTypeName()) + " (fingerprint or length)";
  if (used != size) return std::to_string(size - used) + " trailing bytes after " + std::string(T::getTypeName());
  return "";
}

}  // namespace drivers
