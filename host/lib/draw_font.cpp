// host/lib/draw_font.cpp - text as strokes: the Hershey font read and cached, text laid out
// line by line (draw.h).
#include "draw.h"

#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "draw_detail.h"

namespace articula::host {

namespace {

// The code points of UTF-8 text (a malformed byte stands for itself).
std::vector<uint32_t> code_points(const std::string& s) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 0 : c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    uint32_t cp = n == 0 ? c : c & (0x3F >> n);
    size_t k = 1;
    for (; k <= size_t(n) && i + k < s.size() && (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80; ++k)
      cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    if (k != size_t(n) + 1) cp = c, k = 1;
    out.push_back(cp);
    i += k;
  }
  return out;
}

std::string utf8(uint32_t cp) {
  std::string s;
  if (cp < 0x80) {
    s += char(cp);
  } else if (cp < 0x800) {
    s += char(0xC0 | (cp >> 6)), s += char(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    s += char(0xE0 | (cp >> 12)), s += char(0x80 | ((cp >> 6) & 0x3F)), s += char(0x80 | (cp & 0x3F));
  } else {
    s += char(0xF0 | (cp >> 18)), s += char(0x80 | ((cp >> 12) & 0x3F)), s += char(0x80 | ((cp >> 6) & 0x3F)),
        s += char(0x80 | (cp & 0x3F));
  }
  return s;
}

namespace {
std::invalid_argument unreadable_font(const std::string& path) {
  return std::invalid_argument("cannot read the font " + path +
                               (path == default_font_path() ? " (Debian's hershey-fonts-data: scripts/bootstrap installs it)" : ""));
}
}  // namespace

}  // namespace

// ---- the font

std::string default_font_path() { return "/usr/share/hershey-fonts/futural.jhf"; }

HersheyFont parse_hershey(const std::string& text, const std::string& name) {
  HersheyFont font;
  font.source = name;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const int first = number;
    auto bad = [&](const std::string& why) {
      return std::invalid_argument(name + ":" + std::to_string(first) + ": " + why + " (a Hershey .jhf glyph)");
    };
    if (line.size() < 10) throw bad("too short");
    int count = 0;
    try {
      count = std::stoi(line.substr(5, 3));
    } catch (const std::exception&) {
      throw bad("no vertex count in columns 6-8");
    }
    if (count < 1) throw bad("a vertex count below 1");
    std::string pairs = line.substr(8);
    // a long glyph may go on over the next lines
    while (pairs.size() < size_t(count) * 2 && std::getline(in, line)) {
      ++number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      pairs += line;
    }
    if (pairs.size() < size_t(count) * 2) throw bad("fewer coordinates than its count, " + std::to_string(count));
    HersheyGlyph g;
    g.left = pairs[0] - 'R';
    g.right = pairs[1] - 'R';
    Stroke cur;
    for (int i = 1; i < count; ++i) {
      const char cx = pairs[size_t(i) * 2], cy = pairs[size_t(i) * 2 + 1];
      if (cx == ' ' && cy == 'R') {
        if (!cur.empty()) g.strokes.push_back(cur);
        cur.clear();
        continue;
      }
      if (cx < ' ' || cx > '~' || cy < ' ' || cy > '~') throw bad("a coordinate outside ' ' .. '~'");
      cur.push_back({double(cx - 'R'), -double(cy - 'R')});  // the font's y points down
    }
    if (!cur.empty()) g.strokes.push_back(cur);
    font.glyphs.push_back(std::move(g));
  }
  if (font.glyphs.size() < size_t('H' - ' ' + 1))
    throw std::invalid_argument(name + ": " + std::to_string(font.glyphs.size()) +
                                " glyphs: a font for text has one for each character from ' ' to '~' (95)");
  const Bounds h = bounds_of(font.glyphs[size_t('H' - ' ')].strokes);
  if (!(h.height() > 0)) throw std::invalid_argument(name + ": its 'H' has no height");
  font.cap_height = h.height();
  // the baseline at y 0: the foot of the 'H'
  for (HersheyGlyph& g : font.glyphs)
    for (Stroke& s : g.strokes)
      for (Point2& p : s) p.y -= h.min_y;
  return font;
}

HersheyFont load_hershey(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw unreadable_font(path);
  std::ostringstream s;
  s << f.rdbuf();
  return parse_hershey(s.str(), path);
}

const HersheyFont& draw_detail::cached_font(const std::string& path) {
  static std::mutex lock;
  static std::map<std::string, std::pair<std::string, HersheyFont>> fonts;
  std::ifstream f(path, std::ios::binary);
  if (!f) throw unreadable_font(path);
  std::ostringstream s;
  s << f.rdbuf();
  const std::lock_guard<std::mutex> hold(lock);
  auto it = fonts.find(path);
  if (it == fonts.end() || it->second.first != s.str())
    it = fonts.insert_or_assign(path, std::make_pair(s.str(), parse_hershey(s.str(), path))).first;
  return it->second.second;
}

using namespace draw_detail;

std::vector<Stroke> text_strokes(const HersheyFont& font, const std::string& text, double cap_height_mm,
                                 double line_spacing) {
  if (!(cap_height_mm > 0) || !std::isfinite(cap_height_mm)) throw std::invalid_argument("the text's height must be > 0 mm");
  if (!(line_spacing > 0) || !std::isfinite(line_spacing)) throw std::invalid_argument("the line spacing must be > 0");
  const std::vector<uint32_t> cps = code_points(text);
  std::vector<std::string> missing;
  for (uint32_t c : cps) {
    if (c == '\n' || c == '\r') continue;
    if (c < 32 || c > 126 || c - 32 >= font.glyphs.size()) {
      char code[16];
      std::snprintf(code, sizeof code, "U+%04X", unsigned(c));
      const std::string name = c < 32 || c == 0x7F ? std::string(code) : "'" + utf8(c) + "' (" + code + ")";
      if (std::find(missing.begin(), missing.end(), name) == missing.end()) missing.push_back(name);
    }
  }
  if (!missing.empty()) {
    std::string list;
    for (size_t i = 0; i < missing.size(); ++i) list += (i ? ", " : "") + missing[i];
    throw std::invalid_argument("the font (" + font.source + ") has no " + list +
                                ": it holds the characters from ' ' to '~' (ASCII)");
  }
  const double s = cap_height_mm / font.cap_height;
  std::vector<Stroke> out;
  double x = 0, y = 0;
  for (uint32_t c : cps) {
    if (c == '\r') continue;
    if (c == '\n') {
      x = 0;
      y -= line_spacing * cap_height_mm;
      continue;
    }
    const HersheyGlyph& g = font.glyphs[c - 32];
    for (const Stroke& st : g.strokes) {
      Stroke placed;
      for (const Point2& p : st) placed.push_back({x + (p.x - g.left) * s, y + p.y * s});
      out.push_back(placed);
    }
    x += (g.right - g.left) * s;
  }
  return out;
}

}  // namespace articula::host
