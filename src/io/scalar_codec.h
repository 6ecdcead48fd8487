// Internal: the PLY scalar types in binary (either byte order) and in text.
// Values travel as double, which holds every PLY scalar exactly.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "detexture/io/point_cloud.h"

namespace detexture::io_detail {

inline bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

template <class T>
T load_bytes(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  if (swap) {
    for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
  } else {
    std::memcpy(b, p, sizeof(T));
  }
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

template <class T>
void store_bytes(unsigned char* p, T value, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) p[i] = swap ? b[sizeof(T) - 1 - i] : b[i];
}

/// The value stored at p (scalar_size(type) bytes); swap when the file's byte
/// order differs from the host's.
inline double decode_scalar(const unsigned char* p, ScalarType type, bool swap) {
  switch (type) {
    case ScalarType::Int8:
      return load_bytes<std::int8_t>(p, swap);
    case ScalarType::UInt8:
      return load_bytes<std::uint8_t>(p, swap);
    case ScalarType::Int16:
      return load_bytes<std::int16_t>(p, swap);
    case ScalarType::UInt16:
      return load_bytes<std::uint16_t>(p, swap);
    case ScalarType::Int32:
      return load_bytes<std::int32_t>(p, swap);
    case ScalarType::UInt32:
      return load_bytes<std::uint32_t>(p, swap);
    case ScalarType::Float32:
      return load_bytes<float>(p, swap);
    case ScalarType::Float64:
      return load_bytes<double>(p, swap);
  }
  return 0.0;
}

inline bool is_integer_type(ScalarType type) {
  return type != ScalarType::Float32 && type != ScalarType::Float64;
}

inline double lowest_value(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return std::numeric_limits<std::int8_t>::lowest();
    case ScalarType::Int16:
      return std::numeric_limits<std::int16_t>::lowest();
    case ScalarType::Int32:
      return std::numeric_limits<std::int32_t>::lowest();
    case ScalarType::Float32:
      return std::numeric_limits<float>::lowest();
    case ScalarType::Float64:
      return std::numeric_limits<double>::lowest();
    default:
      return 0.0;
  }
}

inline double max_value(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return std::numeric_limits<std::int8_t>::max();
    case ScalarType::UInt8:
      return std::numeric_limits<std::uint8_t>::max();
    case ScalarType::Int16:
      return std::numeric_limits<std::int16_t>::max();
    case ScalarType::UInt16:
      return std::numeric_limits<std::uint16_t>::max();
    case ScalarType::Int32:
      return std::numeric_limits<std::int32_t>::max();
    case ScalarType::UInt32:
      return std::numeric_limits<std::uint32_t>::max();
    case ScalarType::Float32:
      return std::numeric_limits<float>::max();
    case ScalarType::Float64:
      return std::numeric_limits<double>::max();
  }
  return 0.0;
}

/// Whether value can be stored as type: integers must be whole and in range;
/// float32 rounds to nearest but must not overflow (NaN and Inf are kept).
inline bool fits_scalar(double value, ScalarType type) {
  if (type == ScalarType::Float64) return true;
  if (type == ScalarType::Float32)
    return !std::isfinite(value) || std::fabs(value) <= std::numeric_limits<float>::max();
  return std::isfinite(value) && value == std::trunc(value) && value >= lowest_value(type) &&
         value <= max_value(type);
}

/// Store value (which must satisfy fits_scalar) at p.
inline void encode_scalar(unsigned char* p, double value, ScalarType type, bool swap) {
  switch (type) {
    case ScalarType::Int8:
      return store_bytes(p, static_cast<std::int8_t>(value), swap);
    case ScalarType::UInt8:
      return store_bytes(p, static_cast<std::uint8_t>(value), swap);
    case ScalarType::Int16:
      return store_bytes(p, static_cast<std::int16_t>(value), swap);
    case ScalarType::UInt16:
      return store_bytes(p, static_cast<std::uint16_t>(value), swap);
    case ScalarType::Int32:
      return store_bytes(p, static_cast<std::int32_t>(value), swap);
    case ScalarType::UInt32:
      return store_bytes(p, static_cast<std::uint32_t>(value), swap);
    case ScalarType::Float32:
      return store_bytes(p, static_cast<float>(value), swap);
    case ScalarType::Float64:
      return store_bytes(p, value, swap);
  }
}

/// Parse a whole text token as a double ("+1", "1e3", "nan", "inf" are
/// accepted); false if any part of it is not a number or it overflows.
inline bool parse_double(std::string_view token, double* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, *value);
  return ec == std::errc() && ptr == end;
}

/// Parse a whole text token as a non-negative integer (a count).
inline bool parse_count(std::string_view token, std::uint64_t* value) {
  if (token.size() > 1 && token[0] == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, *value);
  return ec == std::errc() && ptr == end;
}

enum class ParseResult { Ok, NotANumber, OutOfRange };

/// Parse a whole text token as a value of type. A float32 token is rounded
/// straight to float (not via double, which could round twice); integer types
/// accept whole numbers written as decimals ("255.0").
inline ParseResult parse_scalar(std::string_view token, ScalarType type, double* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (type == ScalarType::Float32) {
    float f = 0.0f;
    const auto [ptr, ec] = std::from_chars(begin, end, f);
    if (ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
      return ParseResult::NotANumber;
    if (ec == std::errc::result_out_of_range) return ParseResult::OutOfRange;
    *value = f;
    return ParseResult::Ok;
  }
  if (is_integer_type(type)) {
    std::int64_t i = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, i);
    if (ptr == end && ec == std::errc()) {
      *value = static_cast<double>(i);
      return fits_scalar(*value, type) ? ParseResult::Ok : ParseResult::OutOfRange;
    }
  }
  double d = 0.0;
  const auto [ptr, ec] = std::from_chars(begin, end, d);
  if (ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
    return ParseResult::NotANumber;
  if (ec == std::errc::result_out_of_range) return ParseResult::OutOfRange;
  *value = d;
  if (is_integer_type(type) && !fits_scalar(d, type))
    return std::isfinite(d) && d == std::trunc(d) ? ParseResult::OutOfRange
                                                  : ParseResult::NotANumber;
  return ParseResult::Ok;
}

/// Append value (which must satisfy fits_scalar) as the shortest text that
/// reads back as the same value of type.
inline void append_scalar_text(std::string& out, double value, ScalarType type) {
  char buffer[64];
  std::to_chars_result r;
  if (is_integer_type(type))
    r = std::to_chars(buffer, buffer + sizeof buffer, static_cast<std::int64_t>(value));
  else if (type == ScalarType::Float32)
    r = std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value));
  else
    r = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, r.ptr);
}

/// A token as it may appear inside an error message: quoted, at most 40
/// characters, control and non-ASCII bytes replaced by '?', so the message
/// stays on one line whatever the file holds.
inline std::string quoted(std::string_view token) {
  std::string out = "'";
  const std::size_t n = token.size() < 40 ? token.size() : 40;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (token.size() > n) out += "...";
  return out + "'";
}

}  // namespace detexture::io_detail
