/// @file
/// Text that is safe to print as (part of) one line of a terminal.
#pragma once
#include <string>
#include <string_view>

namespace cubecal {

/// `text` with its control bytes (line breaks, NUL, escape sequences) and the
/// bytes that are not well-formed UTF-8 written as `\xNN`; anything else, UTF-8
/// included, is kept. InputError messages, which quote file contents, are
/// made so; faces that print other messages use it too.
std::string printable_text(std::string_view text);

/// `text` with the bytes that are not well-formed UTF-8 written as `\xNN` (the
/// rule of printable_text for them) and everything else kept, control bytes
/// included: text for a JSON string or a Python str, which escape the rest.
std::string utf8_text(std::string_view text);

}  // namespace cubecal
