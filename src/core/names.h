#pragma once
/// Names of objects, types, attributes and parameters, and "did you mean" suggestions.
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace sscs {

/// A name starts with a letter, then letters, digits, `_` or `-`.
bool is_valid_name(std::string_view name);

/// The red, green and blue of "#RRGGBB" in [0, 1] (as written: sRGB), or `fallback` for
/// anything else (an object without a colour).
std::array<float, 3> color_rgb(std::string_view hex, std::array<float, 3> fallback);

/// Whether `c` is a colour as files write it: "#RRGGBB" (hex sRGB).
bool is_valid_color(std::string_view c);

/// Levenshtein distance, for suggestions.
size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `name` when it is close enough to be a likely typo, else "".
std::string closest_name(std::string_view name, const std::vector<std::string>& candidates);

/// " (did you mean 'X'?)" or "" when nothing is close.
std::string did_you_mean(std::string_view name, const std::vector<std::string>& candidates);

/// Whether `a` sorts before `b` with runs of digits compared as numbers (slot_2 before slot_10).
bool natural_less(std::string_view a, std::string_view b);

/// Names joined with ", ", the first `most` of them and how many there are in all beyond that
/// (a rack's 600 slot frames in a message would hide what it says).
std::string name_list(const std::vector<std::string>& names, size_t most = 24);

/// `s` without its leading and trailing spaces and tabs.
std::string_view trim_blanks(std::string_view s);

/// Glob match with `*` and `?` over a whole name.
bool glob_match(std::string_view pattern, std::string_view name);

}  // namespace sscs
