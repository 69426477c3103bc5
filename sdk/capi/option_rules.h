// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The rules an options field obeys, for the one table per options struct in
// option_conversion.cpp: each row names the field, its default (static_assert'ed against the
// header's *_INIT macro), its rule and where its value goes in the C++ options. apply() checks a
// value against its rule and converts it, failing with invalid_argument in the one message format
// "cagekit_<struct>.<field> must be …, not <value>".
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "capi/api_guard.h"
#include "core/edge_key.h"

namespace cagekit_capi {

// An unsigned integer in min..max.
struct UintIn {
  uint64_t min, max;
};

// Worker-thread counts: 0 (all cores) .. 1024, everywhere.
constexpr UintIn kThreads{0, 1024};

// A finite real number, bounded below and above (an infinite bound is no bound), each bound
// inclusive or exclusive.
struct RealIn {
  double min, max;
  bool min_exclusive, max_exclusive;
};
constexpr RealIn at_least(double min) { return {min, HUGE_VAL, false, false}; }
constexpr RealIn greater_than(double min) { return {min, HUGE_VAL, true, false}; }
constexpr RealIn at_most(double max) { return {-HUGE_VAL, max, false, false}; }
constexpr RealIn closed_range(double min, double max) { return {min, max, false, false}; }
constexpr RealIn half_open_range(double min, double max) { return {min, max, true, false}; }  // (min, max]

// A cagekit_bool32: 0 or 1.
struct Boolean {};

// One enumerator of a C enum and the C++ value it stands for.
template <class T>
struct EnumValue {
  int32_t c_value;
  const char* c_name;
  T value;
};
// A C enum whose values map onto a C++ enum; `type` is the C type's name.
template <class T, size_t N>
struct EnumRule {
  const char* type;
  EnumValue<T> values[N];
};

// A field checked and converted by the code after the table (arrays, cross-field rules).
struct ByHand {};

inline std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

inline std::string rule_text(const RealIn& r) {
  const bool has_min = std::isfinite(r.min), has_max = std::isfinite(r.max);
  if (has_min && has_max)
    return "in " + std::string(r.min_exclusive ? "(" : "[") + number_text(r.min) + ", " + number_text(r.max) +
           (r.max_exclusive ? ")" : "]");
  if (has_min) return (r.min_exclusive ? "> " : ">= ") + number_text(r.min);
  if (has_max) return (r.max_exclusive ? "< " : "<= ") + number_text(r.max);
  return "any value";
}

template <class V, class Dest>
void apply(const UintIn& rule, V value, const char* name, Dest& dest) {
  static_assert(std::is_integral<V>::value, "UintIn is for integer fields");
  bool negative = false;
  if constexpr (std::is_signed<V>::value) negative = value < 0;
  if (negative || static_cast<uint64_t>(value) < rule.min || static_cast<uint64_t>(value) > rule.max)
    fail(Status::invalid_argument, std::string(name) + " must be in " + std::to_string(rule.min) + ".." +
                                       std::to_string(rule.max) + ", not " + std::to_string(value));
  dest = static_cast<Dest>(value);
}

// A bit set: only the bits of `known` may be set.
struct FlagsIn {
  uint32_t known;
  const char* flags;  // the flags' common name, e.g. "CAGEKIT_REPAIR_*"
};
template <class Dest>
void apply(const FlagsIn& rule, uint32_t value, const char* name, Dest& dest) {
  if ((value & ~rule.known) != 0) {
    char text[96];
    std::snprintf(text, sizeof(text), " must be a combination of %s flags (0x%x), not 0x%x", rule.flags, rule.known,
                  value);
    fail(Status::invalid_argument, std::string(name) + text);
  }
  dest = static_cast<Dest>(value);
}

template <class Dest>
void apply(const RealIn& rule, double value, const char* name, Dest& dest) {
  const bool above = rule.min_exclusive ? value > rule.min : value >= rule.min;
  const bool below = rule.max_exclusive ? value < rule.max : value <= rule.max;
  if (!std::isfinite(value) || !above || !below)
    fail(Status::invalid_argument,
         std::string(name) + " must be finite and " + rule_text(rule) + ", not " + number_text(value));
  dest = static_cast<Dest>(value);
}

inline void apply(Boolean, cagekit_bool32 value, const char* name, bool& dest) { dest = bool_from_c(value, name); }

template <class E, class T, size_t N>
void apply(const EnumRule<T, N>& rule, const E& value, const char* name, T& dest) {
  const int32_t raw = raw_enum(value);
  std::string names;
  for (const EnumValue<T>& v : rule.values) {
    if (v.c_value == raw) {
      dest = v.value;
      return;
    }
    names += (names.empty() ? "" : ", ") + std::string(v.c_name);
  }
  fail(Status::invalid_argument,
       std::string(name) + " must be a " + rule.type + " (" + names + "), not " + std::to_string(raw));
}

template <class V, class Dest>
void apply(ByHand, const V&, const char*, Dest&) {}

// The sharp_edges / sharp_edge_count pair of an options struct as edge keys: a non-NULL array
// when the count is not 0, no pair joining a vertex to itself (whether each is an edge of the
// mesh the algorithm checks). `prefix`: "cagekit_<struct>.".
inline std::vector<uint64_t> sharp_edges_from_c(const uint32_t* pairs, uint32_t count, const std::string& prefix) {
  std::vector<uint64_t> keys;
  if (count == 0) return keys;
  if (pairs == nullptr)
    fail(Status::invalid_argument, prefix + "sharp_edges must not be NULL with sharp_edge_count " + std::to_string(count));
  keys.reserve(count);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t a = pairs[2 * size_t(i)], b = pairs[2 * size_t(i) + 1];
    if (a == b)
      fail(Status::invalid_argument, prefix + "sharp_edges: pair " + std::to_string(i) + " (" + std::to_string(a) +
                                         ", " + std::to_string(b) + ") is no edge");
    keys.push_back(cagekit::edge_key(a, b));
  }
  return keys;
}

// The row of sharp_edge_count: the rule holds the struct's sharp_edges pointer (SharpEdgePairs{o.sharp_edges}).
struct SharpEdgePairs {
  const uint32_t* pairs;
};
inline void apply(const SharpEdgePairs& rule, uint32_t count, const char* name, std::vector<uint64_t>& dest) {
  const std::string field(name);
  dest = sharp_edges_from_c(rule.pairs, count, field.substr(0, field.rfind('.') + 1));
}

// Expansions of a table row X(A, field, default, rule, destination); A is the table's argument.
// The header's *_INIT macro must give each field the table's default (A: the INIT value)...
#define CAGEKIT_ASSERT_DEFAULT(init, field, default_value, rule, destination) \
  static_assert(init.field == (default_value), #init "." #field " differs from its options table");
// ...and every field is checked and converted, in declaration order (A: "cagekit_<struct>.", the
// struct read into `o`).
#define CAGEKIT_APPLY_OPTION(prefix, field, default_value, rule, destination) \
  apply(rule, o.field, prefix #field, destination);

// Defines `cpp_type function(const c_struct* options)` from a table: the caller's struct is read
// over the header's defaults `init` (NULL: the defaults; a shorter struct_size: the defaults for
// the rest), each row is applied into `var`, then the statements `finish` ({} for none) run with
// `o` and `var` in scope.
#define CAGEKIT_OPTIONS_FROM_C(function, c_struct, init, table, cpp_type, var, ...)            \
  constexpr c_struct k_##c_struct##_defaults = init;                                           \
  table(CAGEKIT_ASSERT_DEFAULT, k_##c_struct##_defaults)                                       \
  cpp_type function(const c_struct* options) {                                                 \
    const c_struct o = read_versioned(options, k_##c_struct##_defaults, #c_struct);            \
    cpp_type var;                                                                              \
    table(CAGEKIT_APPLY_OPTION, #c_struct ".")                                                 \
    __VA_ARGS__                                                                                \
    return var;                                                                                \
  }

}  // namespace cagekit_capi
