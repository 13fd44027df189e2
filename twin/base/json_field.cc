#include "twin/base/json_field.h"

#include <cmath>
#include <fstream>
#include <ios>
#include <sstream>
#include <stdexcept>

namespace twin {
namespace {

std::string short_number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

JsonField::JsonField(const nlohmann::json& value, std::string source, std::string path)
    : value_(&value), source_(std::move(source)), path_(std::move(path)) {}

nlohmann::json JsonField::parse_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  return parse_stream(in, path);
}

nlohmann::json JsonField::parse_stream(std::istream& in, const std::string& source) {
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double (1e400).
    throw std::runtime_error(source + ": not valid JSON: " + e.what());
  } catch (const std::ios_base::failure& e) {
    throw std::runtime_error(source + ": cannot read the file (" + e.what() + ")");
  }
}

void JsonField::fail(const std::string& what) const {
  throw std::invalid_argument(source_ + ": " + (path_.empty() ? "the file" : "field '" + path_ + "'") +
                              " " + what);
}

void JsonField::fail_child(const std::string& key, const std::string& what) const {
  JsonField(*value_, source_, path_.empty() ? key : path_ + "." + key).fail(what);
}

bool JsonField::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

JsonField JsonField::operator[](const std::string& key) const {
  if (!value_->is_object()) fail("must be an object");
  const std::string child = path_.empty() ? key : path_ + "." + key;
  if (!value_->contains(key)) JsonField(*value_, source_, child).fail("is missing");
  return JsonField(value_->at(key), source_, child);
}

std::optional<JsonField> JsonField::optional(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return (*this)[key];
}

JsonField JsonField::operator[](std::size_t index) const {
  return JsonField(value_->at(index), source_, path_ + "[" + std::to_string(index) + "]");
}

std::size_t JsonField::array_size() const {
  if (!value_->is_array()) fail("must be an array");
  return value_->size();
}

void JsonField::only_keys(std::initializer_list<const char*> known) const {
  if (!value_->is_object()) fail("must be an object");
  for (const auto& item : value_->items()) {
    bool ok = false;
    for (const char* k : known) ok |= item.key() == k;
    if (!ok) {
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      (*this)[item.key()].fail("is not a known field; expected one of: " + list);
    }
  }
}

double JsonField::number(const char* unit) const {
  if (!value_->is_number()) {
    fail(std::string("must be a number in ") + unit + ", got " + value_->type_name());
  }
  const double v = value_->get<double>();
  if (!std::isfinite(v)) fail("must be finite");
  return v;
}

double JsonField::positive(const char* unit) const {
  const double v = number(unit);
  if (!(v > 0.0)) fail(std::string("must be a positive number in ") + unit + ", got " + short_number(v));
  return v;
}

double JsonField::non_negative(const char* unit) const {
  const double v = number(unit);
  if (!(v >= 0.0)) fail(std::string("must be >= 0 in ") + unit + ", got " + short_number(v));
  return v;
}

int JsonField::positive_integer() const {
  if (!value_->is_number_integer() || value_->get<long long>() <= 0 ||
      value_->get<long long>() > 1000000000LL) {
    fail("must be a positive integer");
  }
  return static_cast<int>(value_->get<long long>());
}

std::string JsonField::string() const {
  if (!value_->is_string()) fail(std::string("must be a string, got ") + value_->type_name());
  return value_->get<std::string>();
}

Vec2 JsonField::vec2(const char* unit) const {
  if (!value_->is_array() || value_->size() != 2) fail(std::string("must be [a, b] in ") + unit);
  return Vec2((*this)[0].number(unit), (*this)[1].number(unit));
}

Vec3 JsonField::vec3(const char* unit) const {
  if (!value_->is_array() || value_->size() != 3) fail(std::string("must be [x, y, z] in ") + unit);
  return Vec3((*this)[0].number(unit), (*this)[1].number(unit), (*this)[2].number(unit));
}

}  // namespace twin
