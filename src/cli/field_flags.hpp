// How the CLI names a request field (cubecal::Field): its flag. The one
// place that maps fields to flags; an exhaustive switch, so that a Field
// added to the library without a flag here is a compile error (-Wswitch).
#pragma once
#include <string>
#include <string_view>

#include "cubecal/error.hpp"
#include "cubecal/field.hpp"

namespace cubecal::cli {

struct FieldFlag {
  enum class Prefix { no, yes };
  // "--stream"; empty for a field no option sets (the record's own samples).
  std::string_view flag;
  // yes: a UsageError on the field reads "FLAG: message"; no: its message
  // already says which option it is about ("{frame}: unknown key").
  Prefix prefix = Prefix::no;
};

FieldFlag field_flag(Field f) noexcept;

// The flag of `f`, or its name where no option sets it.
std::string flag_of(Field f);

// `text` with each field marker as the field's flag ("leave out --stream").
std::string flag_words(std::string_view text);

// A library error's message in the CLI's words: the flag of a UsageError's
// field in front where it has one, every marker as its flag.
std::string cli_message(const Error& e);

}  // namespace cubecal::cli
