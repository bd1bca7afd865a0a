// Small helpers for bytes <-> values. The .probes format is little-endian and its payloads are the
// in-memory bytes of the GPU structs, so these are plain copies on the (little-endian) hosts we support.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

namespace probebake::formats::detail {

static_assert(std::endian::native == std::endian::little, ".probes I/O assumes a little-endian host");

inline std::uint64_t align_up(std::uint64_t value, std::uint64_t alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

template <typename T>
std::span<const std::uint8_t> as_bytes(const std::vector<T>& elements) {
  static_assert(std::is_trivially_copyable_v<T>);
  return {reinterpret_cast<const std::uint8_t*>(elements.data()), elements.size() * sizeof(T)};
}

template <typename T>
std::span<const std::uint8_t> as_bytes(const T& value) {
  static_assert(std::is_trivially_copyable_v<T>);
  return {reinterpret_cast<const std::uint8_t*>(&value), sizeof(T)};
}

// Copies bytes.size() / sizeof(T) elements out of bytes (whose size the caller checked).
template <typename T>
std::vector<T> elements_from(std::span<const std::uint8_t> bytes) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<T> elements(bytes.size() / sizeof(T));
  if (!elements.empty()) std::memcpy(elements.data(), bytes.data(), elements.size() * sizeof(T));
  return elements;
}

template <typename T>
T value_from(std::span<const std::uint8_t> bytes) {
  static_assert(std::is_trivially_copyable_v<T>);
  T value{};
  std::memcpy(&value, bytes.data(), sizeof(T));
  return value;
}

} // namespace probebake::formats::detail
