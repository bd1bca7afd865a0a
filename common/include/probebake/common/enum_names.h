// One table of names for an enum's values serves both directions: printing a value and parsing a name
// (command-line options, JSON), so that the two cannot drift apart.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace probebake {

template <typename Enum>
struct EnumName {
  Enum value;
  std::string_view name;
};

// The name of `value` in `names`, or `fallback` when the table has no row for it.
template <typename Enum, std::size_t N>
constexpr std::string_view name_in(const EnumName<Enum> (&names)[N], Enum value, std::string_view fallback) {
  for (const EnumName<Enum>& row : names)
    if (row.value == value) return row.name;
  return fallback;
}

// The value named exactly `name` in `names` (case-sensitive), or nullopt.
template <typename Enum, std::size_t N>
constexpr std::optional<Enum> parse_name_in(const EnumName<Enum> (&names)[N], std::string_view name) {
  for (const EnumName<Enum>& row : names)
    if (row.name == name) return row.value;
  return std::nullopt;
}

} // namespace probebake
