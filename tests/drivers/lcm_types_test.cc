// The iiwa types must be wire-compatible with Drake's lcmt_iiwa_command / lcmt_iiwa_status so a
// real KUKA iiwa LCM driver accepts our commands and we accept its status. Two independent
// checks: (1) the generated fingerprint equals the one computed here from Drake's definitions
// with LCM's fingerprint algorithm (lcm-gen, lcmgen.c: lcm_struct_hash, hash_update,
// hash_string_update; the C++ emitter rotates the result left by one bit), and (2) an encoded
// command has the byte layout Drake's definition implies.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <lcmt_iiwa_command.hpp>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>

namespace {

// One member of an LCM struct: name, primitive type, and its array dimensions (each either a
// constant size or the name of the member holding the size).
struct Dimension {
  bool variable;
  std::string size;
};
struct Member {
  std::string name;
  std::string type;
  std::vector<Dimension> dimensions;
};

// LCM's hash step: v = ((v << 8) ^ (v >> 55)) + c on a signed 64-bit value (arithmetic shift).
std::int64_t hash_update(std::int64_t v, char c) {
  const std::uint64_t mixed =
      (static_cast<std::uint64_t>(v) << 8) ^ static_cast<std::uint64_t>(v >> 55);
  const auto c64 = static_cast<std::uint64_t>(static_cast<std::int64_t>(c));  // sign-extended
  return static_cast<std::int64_t>(mixed + c64);
}

std::int64_t hash_string(std::int64_t v, const std::string& s) {
  v = hash_update(v, static_cast<char>(s.size()));
  for (char c : s) v = hash_update(v, c);
  return v;
}

// The fingerprint of a struct of primitive members, as getHash() returns it. The struct's and
// package's names are not part of it.
std::int64_t fingerprint(const std::vector<Member>& members) {
  std::int64_t v = 0x12345678;
  for (const Member& m : members) {
    v = hash_string(v, m.name);
    v = hash_string(v, m.type);  // all members here are primitive
    v = hash_update(v, static_cast<char>(m.dimensions.size()));
    for (const Dimension& d : m.dimensions) {
      v = hash_update(v, d.variable ? 1 : 0);  // LCM_CONST = 0, LCM_VAR = 1
      v = hash_string(v, d.size);
    }
  }
  const auto h = static_cast<std::uint64_t>(v);
  return static_cast<std::int64_t>((h << 1) + ((h >> 63) & 1));
}

// RobotLocomotion/drake lcmtypes/lcmt_iiwa_command.lcm (package drake).
const std::vector<Member> kDrakeIiwaCommand = {
    {"utime", "int64_t", {}},
    {"num_joints", "int32_t", {}},
    {"joint_position", "double", {{true, "num_joints"}}},
    {"num_torques", "int32_t", {}},
    {"joint_torque", "double", {{true, "num_torques"}}},
};

// RobotLocomotion/drake lcmtypes/lcmt_iiwa_status.lcm (package drake).
const std::vector<Member> kDrakeIiwaStatus = {
    {"utime", "int64_t", {}},
    {"num_joints", "int32_t", {}},
    {"joint_position_measured", "double", {{true, "num_joints"}}},
    {"joint_velocity_estimated", "double", {{true, "num_joints"}}},
    {"joint_position_commanded", "double", {{true, "num_joints"}}},
    {"joint_position_ipo", "double", {{true, "num_joints"}}},
    {"joint_torque_measured", "double", {{true, "num_joints"}}},
    {"joint_torque_commanded", "double", {{true, "num_joints"}}},
    {"joint_torque_external", "double", {{true, "num_joints"}}},
};

std::uint64_t read_be(const std::vector<std::uint8_t>& bytes, std::size_t offset, int size) {
  std::uint64_t value = 0;
  for (int i = 0; i < size; ++i) value = (value << 8) | bytes.at(offset + i);
  return value;
}

double read_be_double(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  const std::uint64_t bits = read_be(bytes, offset, 8);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

}  // namespace

TEST_CASE("iiwa command and status fingerprints equal those of Drake's definitions",
          "[lcm_types]") {
  CHECK(lcmt_iiwa_command::getHash() == fingerprint(kDrakeIiwaCommand));
  CHECK(lcmt_iiwa_status::getHash() == fingerprint(kDrakeIiwaStatus));
  CHECK(std::string(lcmt_iiwa_command::getTypeName()) == "lcmt_iiwa_command");
  CHECK(std::string(lcmt_iiwa_status::getTypeName()) == "lcmt_iiwa_status");
}

TEST_CASE("the hand-computed fingerprint is sensitive to member order, names and types",
          "[lcm_types]") {
  // Guards the check above against a fingerprint function that ignores its input.
  auto swapped = kDrakeIiwaCommand;
  std::swap(swapped[1], swapped[3]);
  CHECK(fingerprint(swapped) != fingerprint(kDrakeIiwaCommand));
  auto renamed = kDrakeIiwaCommand;
  renamed[2].name = "joint_positions";
  CHECK(fingerprint(renamed) != fingerprint(kDrakeIiwaCommand));
  auto retyped = kDrakeIiwaCommand;
  retyped[0].type = "int32_t";
  CHECK(fingerprint(retyped) != fingerprint(kDrakeIiwaCommand));
  // Our own types are told apart from the iiwa ones and from each other.
  CHECK(prepreg_lcm::sheet_state_t::getHash() != lcmt_iiwa_command::getHash());
  CHECK(prepreg_lcm::sheet_state_t::getHash() != prepreg_lcm::cell_state_t::getHash());
}

TEST_CASE("an encoded iiwa command has Drake's byte layout", "[lcm_types]") {
  lcmt_iiwa_command msg;
  msg.utime = 0x0102030405060708;
  msg.num_joints = 7;
  for (int i = 0; i < 7; ++i) msg.joint_position.push_back(0.25 * (i + 1) - 1.0);
  msg.num_torques = 2;
  msg.joint_torque = {1.5, -2.5};

  const int size = msg.getEncodedSize();
  // hash (8) + utime (8) + num_joints (4) + 7 doubles + num_torques (4) + 2 doubles.
  REQUIRE(size == 8 + 8 + 4 + 7 * 8 + 4 + 2 * 8);
  std::vector<std::uint8_t> bytes(size);
  REQUIRE(msg.encode(bytes.data(), 0, size) == size);

  // Everything big-endian, in declaration order.
  CHECK(static_cast<std::int64_t>(read_be(bytes, 0, 8)) == fingerprint(kDrakeIiwaCommand));
  CHECK(read_be(bytes, 8, 8) == 0x0102030405060708u);
  CHECK(read_be(bytes, 16, 4) == 7u);
  for (int i = 0; i < 7; ++i) CHECK(read_be_double(bytes, 20 + 8 * i) == 0.25 * (i + 1) - 1.0);
  CHECK(read_be(bytes, 76, 4) == 2u);
  CHECK(read_be_double(bytes, 80) == 1.5);
  CHECK(read_be_double(bytes, 88) == -2.5);

  lcmt_iiwa_command back;
  REQUIRE(back.decode(bytes.data(), 0, size) == size);
  CHECK(back.joint_position == msg.joint_position);
  CHECK(back.joint_torque == msg.joint_torque);
}

TEST_CASE("an encoded iiwa status has Drake's byte layout", "[lcm_types]") {
  lcmt_iiwa_status msg;
  msg.utime = 42;
  msg.num_joints = 7;
  std::vector<double>* arrays[] = {&msg.joint_position_measured, &msg.joint_velocity_estimated,
                                   &msg.joint_position_commanded, &msg.joint_position_ipo,
                                   &msg.joint_torque_measured, &msg.joint_torque_commanded,
                                   &msg.joint_torque_external};
  for (int a = 0; a < 7; ++a) {
    for (int j = 0; j < 7; ++j) arrays[a]->push_back(10.0 * a + j);
  }
  const int size = msg.getEncodedSize();
  REQUIRE(size == 8 + 8 + 4 + 7 * 7 * 8);
  std::vector<std::uint8_t> bytes(size);
  REQUIRE(msg.encode(bytes.data(), 0, size) == size);
  CHECK(static_cast<std::int64_t>(read_be(bytes, 0, 8)) == fingerprint(kDrakeIiwaStatus));
  CHECK(read_be(bytes, 8, 8) == 42u);
  CHECK(read_be(bytes, 16, 4) == 7u);
  // The seven arrays follow one another in declaration order.
  for (int a = 0; a < 7; ++a) {
    for (int j = 0; j < 7; ++j) CHECK(read_be_double(bytes, 20 + 56 * a + 8 * j) == 10.0 * a + j);
  }
}
