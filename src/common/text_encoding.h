// Text for files others read: base64 for the page's inlined arrays and pictures, and the
// escaping of markup (HTML pages, VTK's XML headers), so each encoder is written once.
#pragma once

#include <string>
#include <string_view>

namespace cmcsurf {

// RFC 4648 base64 (section 4: the standard alphabet, '=' padding, no line breaks).
std::string base64(std::string_view bytes);

// & < > " as entities: text and double-quoted attributes of an HTML page.
std::string html_escape(std::string_view s);

// & < > " ' as entities: XML text and attributes in either quote (VTK's headers).
std::string xml_escape(std::string_view s);

}  // namespace cmcsurf
