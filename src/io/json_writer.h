// Writing JSON text directly, without building an nlohmann tree (private to io/).
//
// The result files of `ringlet solve` hold tens of thousands of numbers per file; formatting each
// through a json temporary and dump() cost more than the solve itself (docs/benchmarks.md, "CLI
// overhead"). These append one value to a string; the caller writes the fixed layout around them.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ringlet::internal {

// Appends x as a JSON number: the shortest decimal that reads back as the same double
// (std::to_chars, round-trip exact), with ".0" added when that decimal has neither a fraction nor
// an exponent ("2.0", "-0.0"), so that it stays a floating-point number for readers that tell
// integers apart (Python, nlohmann), as nlohmann's dump() writes it. NaN and infinities, which
// JSON has no literal for, are written as null.
void AppendJsonNumber(double x, std::string* out);

// The same text written at out, which has room for kMaxJsonNumberChars; returns its end.
constexpr size_t kMaxJsonNumberChars = 32;
char* WriteJsonNumber(double x, char* out);

// Appends x as a JSON integer.
void AppendJsonInteger(long long x, std::string* out);

// Appends text as a JSON string literal, quoted and escaped as nlohmann's dump() does (", \ and
// control characters escaped, other characters as they are); invalid UTF-8 is replaced by
// U+FFFD rather than throwing.
void AppendJsonString(std::string_view text, std::string* out);

}  // namespace ringlet::internal
