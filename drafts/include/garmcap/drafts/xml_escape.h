#pragma once
// Escaping text for XML 1.0 and HTML output (SVG drafts, Valentina .vit files, the daemon's
// size guides and pattern exports). One implementation, so every writer refuses the same
// characters the same way.

#include <string>
#include <string_view>

namespace garmcap::drafts {

/// Text safe inside XML 1.0 or HTML character data and in attribute values quoted with either
/// " or '. Escapes & < > " ' (the apostrophe as &#39;, which HTML 4 knows and &apos; is not).
/// Characters XML 1.0 does not allow at all, not even as character references - the C0
/// controls other than tab, newline and carriage return, and U+FFFE / U+FFFF - are replaced
/// by U+FFFD, so that a stray control byte in a name cannot make a whole file unreadable.
/// Other bytes, including UTF-8 sequences, pass through unchanged.
std::string xmlEscape(std::string_view text);

}  // namespace garmcap::drafts
