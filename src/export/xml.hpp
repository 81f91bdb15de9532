// XML text for the KML and WPML writers: one escaping function used by every XML writer.
#pragma once

#include <string>
#include <string_view>

namespace uavcover::exporting {

/// `s` as XML 1.0 character data or attribute value: & < > " ' escaped; tab, newline and carriage
/// return written as character references (so they survive attribute normalisation); characters
/// XML 1.0 forbids (U+0000-U+001F other than those three, U+FFFE, U+FFFF, UTF-16 surrogates) and
/// bytes that are not valid UTF-8 replaced by U+FFFD.
std::string xml_escape(std::string_view s);

}  // namespace uavcover::exporting
