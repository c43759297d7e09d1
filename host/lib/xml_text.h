// host/lib/xml_text.h - text for an XML document (a URDF, an SVG): & < > " and ' as entities, so
// a name from a file is always text, never markup. One home for the rule (urdf.cpp, draw_ink.cpp,
// host/physics/mat.cpp).
#ifndef ARTICULA_HOST_XML_TEXT_H
#define ARTICULA_HOST_XML_TEXT_H

#include <string>

namespace articula::host {

inline std::string xml_text(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace articula::host

#endif  // ARTICULA_HOST_XML_TEXT_H
