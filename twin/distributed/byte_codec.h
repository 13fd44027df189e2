#pragma once
// Results as bytes, for tasks whose results cross ranks (rank_group.h): numbers are copied bit
// for bit (a double arrives as the very value computed), strings and arrays carry their length.
// The reader throws std::runtime_error when the bytes end early, so a truncated message is an
// error, never a result made up of whatever followed.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace twin::distributed {

class ByteWriter {
 public:
  template <typename T>
  ByteWriter& put(const T& value) {
    static_assert(std::is_arithmetic_v<T>, "numbers only; strings and arrays have their own put");
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
    return *this;
  }
  ByteWriter& put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes_ += s;
    return *this;
  }
  ByteWriter& put_doubles(const double* values, std::size_t count) {
    put<std::uint64_t>(count);
    bytes_.append(reinterpret_cast<const char*>(values), count * sizeof(double));
    return *this;
  }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

// Reads bytes it does not own: the message must outlive the reader, so a temporary string is
// refused at compile time (a reader over one would read freed memory).
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  explicit ByteReader(std::string&&) = delete;
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>, "numbers only");
    T value;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  std::string get_string() {
    const auto n = static_cast<std::size_t>(get<std::uint64_t>());
    return std::string(take(n), n);
  }
  std::vector<double> get_doubles() {
    const auto n = static_cast<std::size_t>(get<std::uint64_t>());
    if (n > (bytes_.size() - at_) / sizeof(double)) throw std::runtime_error("byte_codec: array longer than its message");
    std::vector<double> values(n);
    if (n > 0) std::memcpy(values.data(), take(n * sizeof(double)), n * sizeof(double));
    return values;
  }
  bool at_end() const { return at_ == bytes_.size(); }

 private:
  const char* take(std::size_t n) {
    if (n > bytes_.size() - at_) throw std::runtime_error("byte_codec: message ends early");
    const char* p = bytes_.data() + at_;
    at_ += n;
    return p;
  }
  std::string_view bytes_;
  std::size_t at_ = 0;
};

}  // namespace twin::distributed
