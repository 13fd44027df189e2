#pragma once
// A value inside a JSON input file, with its location, so that every input error names the file
// and the field ("scenario.json: field 'stages[2].clamps.B' must be ...") and says what was
// expected. Used by every file reader of the twin (material, scenario).

#include <exception>
#include <initializer_list>
#include <istream>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "twin/base/types.h"

namespace twin {

class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string source, std::string path = "");

  // Reads and parses a JSON file; throws std::runtime_error naming the file (and the parser's
  // line and column) when it cannot be opened or is not JSON.
  static nlohmann::json parse_file(const std::string& path);
  // Parses an opened file's stream; errors name `source`. Besides the parser's own errors this
  // catches a read that fails underneath it: libstdc++'s file buffer throws from a failed read()
  // (a path that is a directory, an I/O error), past the stream's error flags.
  static nlohmann::json parse_stream(std::istream& in, const std::string& source);

  const nlohmann::json& json() const { return *value_; }
  const std::string& source() const { return source_; }
  const std::string& path() const { return path_; }

  bool has(const std::string& key) const;
  JsonField operator[](const std::string& key) const;  // throws "is missing"
  std::optional<JsonField> optional(const std::string& key) const;
  JsonField operator[](std::size_t index) const;
  std::size_t array_size() const;  // throws unless an array
  // Throws for any key not in `known`, listing the known ones.
  void only_keys(std::initializer_list<const char*> known) const;

  double number(const char* unit) const;  // any finite number
  double positive(const char* unit) const;
  double non_negative(const char* unit) const;
  int positive_integer() const;
  std::string string() const;
  bool is_string() const { return value_->is_string(); }
  bool is_object() const { return value_->is_object(); }
  bool is_array() const { return value_->is_array(); }
  Vec2 vec2(const char* unit) const;  // [a, b]
  Vec3 vec3(const char* unit) const;  // [a, b, c]

  [[noreturn]] void fail(const std::string& what) const;
  // Fails naming the child `key` (which need not exist): "field 'parent.key' <what>".
  [[noreturn]] void fail_child(const std::string& key, const std::string& what) const;

  // Runs `read` on the file this field names. Its error names that file, which may be anywhere;
  // it is rethrown naming this file and field too, so a user knows which reference to fix
  // ("scene.json: field 'meshes[0].file' names a file that cannot be used: /x.obj: cannot open").
  template <typename Read>
  auto read_named_file(Read&& read) const -> decltype(read()) {
    try {
      return read();
    } catch (const std::exception& e) {
      fail(std::string("names a file that cannot be used: ") + e.what());
    }
  }

 private:
  const nlohmann::json* value_;
  std::string source_;
  std::string path_;
};

}  // namespace twin
