#pragma once
// User text inside error messages: every byte visible. A NUL would cut the message, a UTF-8
// byte-order mark or a control byte would hide in it, and bytes that are not UTF-8 would turn
// into replacement characters that name no file.

#include <string>
#include <string_view>

namespace wheelpose {

// Whether `text` is well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, ≤ U+10FFFF).
bool is_valid_utf8(std::string_view text);

// `text` with printable ASCII and well-formed UTF-8 letters kept, and every other byte (controls,
// DEL, bytes of malformed sequences, the byte-order mark U+FEFF) written as \xNN. Escaped text
// is printable, so escaping it again changes nothing (main escapes every error it prints).
std::string escape_bytes(std::string_view text);

}  // namespace wheelpose
