#pragma once
// Reading a JSON input file field by field, so every error names the file (or the part of it,
// "cell.json: camera 1 (cam_right)"), the field's path ("cameras[0].depth_intrinsics.fx") and
// what was expected. Shared by the camera config (camera_config_json.cc) and recorded sessions
// (camera_session.cc). (twin/ has its own JsonField; drivers/ may not depend on twin/.)

#include <cstddef>
#include <initializer_list>
#include <istream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace drivers {

// Every failure throws std::invalid_argument "<where>: field '<path>' <what>". The JSON value
// must outlive the field (a field is a view with its location).
class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string where, std::string path = "")
      : value_(value), where_(std::move(where)), path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& what) const;

  const nlohmann::json& value() const { return value_; }
  bool has(const char* key) const { return value_.is_object() && value_.contains(key); }
  // Object member; fails "must be an object" or "is missing".
  JsonField operator[](const char* key) const;
  // Array element i (path "x[i]"); `size()` fails "must be an array" on anything else.
  std::size_t size() const;
  JsonField at(std::size_t i) const;
  // Fails on the first member whose key is not listed, naming the known ones.
  void only_keys(std::initializer_list<const char*> known) const;

  double number() const;    // finite
  double positive() const;  // finite and > 0
  int positive_int() const;  // 1 .. 1000000
  int integer(int lo, int hi) const;
  std::string string() const;
  std::vector<double> numbers(std::size_t n) const;  // an array of exactly n finite numbers

 private:
  std::string child(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  const nlohmann::json& value_;
  std::string where_, path_;
};

// Parses an opened JSON file; throws std::runtime_error "<source>: ..." when it is not JSON
// (a parse error, or a number beyond a double) or cannot be read (libstdc++'s file buffer throws
// from a failed read(), e.g. of a directory, past the stream's error flags).
nlohmann::json parse_json_stream(std::istream& in, const std::string& source);

}  // namespace drivers
