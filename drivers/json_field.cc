#include "drivers/json_field.h"

#include <cmath>
#include <ios>
#include <stdexcept>

namespace drivers {

void JsonField::fail(const std::string& what) const {
  throw std::invalid_argument(where_ + ": field '" + path_ + "' " + what);
}

JsonField JsonField::operator[](const char* key) const {
  if (!value_.is_object()) fail("must be an object");
  if (!value_.contains(key)) JsonField(value_, where_, child(key)).fail("is missing");
  return JsonField(value_.at(key), where_, child(key));
}

std::size_t JsonField::size() const {
  if (!value_.is_array()) fail("must be an array");
  return value_.size();
}

JsonField JsonField::at(std::size_t i) const {
  if (i >= size()) fail("has no element " + std::to_string(i));
  return JsonField(value_[i], where_, path_ + "[" + std::to_string(i) + "]");
}

void JsonField::only_keys(std::initializer_list<const char*> known) const {
  if (!value_.is_object()) fail("must be an object");
  for (const auto& item : value_.items()) {
    bool ok = false;
    for (const char* k : known) ok |= item.key() == k;
    if (ok) continue;
    std::string list;
    for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    JsonField(item.value(), where_, child(item.key())).fail("is not a known field; expected one of: " + list);
  }
}

double JsonField::number() const {
  if (!value_.is_number()) fail("must be a number");
  const double v = value_.get<double>();
  if (!std::isfinite(v)) fail("must be finite");
  return v;
}

double JsonField::positive() const {
  const double v = number();
  if (v <= 0) fail("must be > 0 (got " + std::to_string(v) + ")");
  return v;
}

int JsonField::positive_int() const {
  if (!value_.is_number_integer() || value_.get<long long>() <= 0 || value_.get<long long>() > 1000000)
    fail("must be a positive integer");
  return value_.get<int>();
}

int JsonField::integer(int lo, int hi) const {
  if (!value_.is_number_integer() || value_.get<long long>() < lo || value_.get<long long>() > hi)
    fail("must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  return static_cast<int>(value_.get<long long>());
}

std::string JsonField::string() const {
  if (!value_.is_string()) fail("must be a string");
  return value_.get<std::string>();
}

std::vector<double> JsonField::numbers(std::size_t n) const {
  if (!value_.is_array() || value_.size() != n) fail("must be an array of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(at(i).number());
  return out;
}

nlohmann::json parse_json_stream(std::istream& in, const std::string& source) {
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number beyond a double
    throw std::runtime_error(source + ": not valid JSON: " + e.what());
  } catch (const std::ios_base::failure& e) {
    throw std::runtime_error(source + ": cannot read the file (" + e.what() + ")");
  }
}

}  // namespace drivers
