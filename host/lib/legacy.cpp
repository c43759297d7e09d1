// host/lib/legacy.cpp - the appendix C robot format, set by set (legacy.h).
//
// The sets, with the number of lines each takes (N arms, J = N + 1 joints):
//   1 number of arms (1)          2 arm model scales y z joint (N)   3 DH: length offset theta alpha (J)
//   4 arm model rotations (N)     5 hand 1|0 (1)                     6 arm model paths (N)
//   7 base model path (1)         8 joint model paths or 0 (J)       9 variable flags: theta alpha length (J)
//  10 restrictions, unused (1)   11 final joint model path (1)      12 hand model paths (2)
//  13 arm overlap (N)            14 arm x offset (N)                15 base offset x y z (1)
//  16 base scale (1)             17 show joints, one flag per joint (1)
//  18 rotate the gripper or keep it horizontal 1|0 (1)             19 number of bits B (1)
//  20 bits (B)
// The DH rows map to our rows (length -> a(i-1), offset -> d(i)); flags 1 make theta and
// alpha joint variables (limits -180..180: the original had none); the hand maps to a
// gripper. Everything about models, scales and drawing does not map and is listed.
#include "legacy.h"

#include <cmath>
#include <sstream>

namespace articula::host {
namespace {

struct Reader {
  std::string name;
  std::vector<std::pair<int, std::string>> lines;  // (line number, text)
  size_t next = 0;

  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw LegacyError(name + ":" + std::to_string(line) + ": " + problem);
  }

  const std::pair<int, std::string>& take(const std::string& what) {
    if (next >= lines.size())
      fail(lines.empty() ? 0 : lines.back().first, "the file ends before " + what);
    return lines[next++];
  }

  std::vector<double> numbers(const std::string& what, size_t count) {
    const auto& [line, text] = take(what);
    std::istringstream in(text);
    std::vector<double> out;
    std::string word;
    while (in >> word) {
      size_t used = 0;
      double v = 0;
      try {
        v = std::stod(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || !std::isfinite(v)) fail(line, what + ": '" + word + "' is not a number");
      out.push_back(v);
    }
    if (out.size() != count)
      fail(line, what + ": " + std::to_string(count) + " numbers expected, " + std::to_string(out.size()) + " given");
    return out;
  }

  std::string text_line(const std::string& what) { return take(what).second; }
  int line_of_next() const { return next < lines.size() ? lines[next].first : 0; }
};

}  // namespace

LegacyImport import_legacy(const std::string& text, const std::string& name, double mm_per_unit) {
  if (!(mm_per_unit > 0) || !std::isfinite(mm_per_unit))
    throw LegacyError(name + ":0: the length scale must be a positive number of mm per unit");
  Reader r{name, {}, 0};
  std::istringstream in(text);
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    const size_t hash = s.find('#');
    if (hash != std::string::npos) s.erase(hash);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    size_t b = 0;
    while (b < s.size() && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    if (b < s.size()) r.lines.push_back({n, s.substr(b)});
  }

  LegacyImport out;
  auto drop = [&](int line, const std::string& what) {
    out.dropped.push_back(name + ":" + std::to_string(line) + ": " + what);
  };

  const int arms_line = r.line_of_next();
  const double arms_value = r.numbers("set 1 (number of arms)", 1)[0];
  if (arms_value < 1 || arms_value > 15 || arms_value != std::floor(arms_value))
    r.fail(arms_line, "set 1 (number of arms): a whole number from 1 to 15 expected");
  const size_t arms = size_t(arms_value), joints = arms + 1;

  for (size_t i = 0; i < arms; ++i) {
    const int l = r.line_of_next();
    r.numbers("set 2 (arm model scale y z joint)", 3);
    drop(l, "arm " + std::to_string(i) + " model scale (drawing only)");
  }
  std::vector<std::vector<double>> dh;
  for (size_t i = 0; i < joints; ++i) dh.push_back(r.numbers("set 3 (DH: length offset theta alpha)", 4));
  for (size_t i = 0; i < arms; ++i) {
    const int l = r.line_of_next();
    r.numbers("set 4 (arm model rotation x y z)", 3);
    drop(l, "arm " + std::to_string(i) + " model rotation (drawing only)");
  }
  const int hand_line = r.line_of_next();
  const double hand = r.numbers("set 5 (hand 1 or 0)", 1)[0];
  if (hand != 0 && hand != 1) r.fail(hand_line, "set 5 (hand): 1 or 0 expected");
  for (size_t i = 0; i < arms; ++i) drop(r.line_of_next(), "arm model path '" + r.text_line("set 6 (arm model path)") + "'");
  drop(r.line_of_next(), "base model path '" + r.text_line("set 7 (base model path)") + "'");
  for (size_t i = 0; i < joints; ++i)
    drop(r.line_of_next(), "joint model path '" + r.text_line("set 8 (joint model path)") + "'");
  std::vector<std::vector<double>> flags;
  for (size_t i = 0; i < joints; ++i) {
    const int l = r.line_of_next();
    flags.push_back(r.numbers("set 9 (variable flags theta alpha length)", 3));
    for (double f : flags.back())
      if (f != 0 && f != 1) r.fail(l, "set 9 (variable flags): each flag is 1 or 0");
    if (flags.back()[2] == 1) drop(l, "joint " + std::to_string(i) + ": variable length (not functional in the original either)");
  }
  drop(r.line_of_next(), "restrictions '" + r.text_line("set 10 (restrictions)") + "' (unused in the original)");
  drop(r.line_of_next(), "final joint model path '" + r.text_line("set 11 (final joint model)") + "'");
  for (int k = 0; k < 2; ++k) drop(r.line_of_next(), "hand model path '" + r.text_line("set 12 (hand model)") + "'");
  for (size_t i = 0; i < arms; ++i) {
    const int l = r.line_of_next();
    r.numbers("set 13 (arm overlap)", 1);
    drop(l, "arm " + std::to_string(i) + " model overlap (drawing only)");
  }
  for (size_t i = 0; i < arms; ++i) {
    const int l = r.line_of_next();
    r.numbers("set 14 (arm x offset)", 1);
    drop(l, "arm " + std::to_string(i) + " model x offset (drawing only)");
  }
  {
    const int l = r.line_of_next();
    r.numbers("set 15 (base offset x y z)", 3);
    drop(l, "base model offset (drawing only)");
  }
  {
    const int l = r.line_of_next();
    r.numbers("set 16 (base scale)", 1);
    drop(l, "base model scale (drawing only)");
  }
  {
    const int l = r.line_of_next();
    r.numbers("set 17 (show joints)", joints);
    drop(l, "which joint models are shown (drawing only)");
  }
  const int level_line = r.line_of_next();
  const double keep_level = r.numbers("set 18 (rotate gripper 1 or keep it horizontal 0)", 1)[0];
  if (keep_level == 0) drop(level_line, "gripper kept horizontal: model it with a linked theta row (robots/README.md)");
  const int bits_line = r.line_of_next();
  const double bits = r.numbers("set 19 (number of bits)", 1)[0];
  if (bits < 0 || bits != std::floor(bits)) r.fail(bits_line, "set 19 (number of bits): a whole number expected");
  for (int i = 0; i < int(bits); ++i) drop(r.line_of_next(), "bit '" + r.text_line("set 20 (bit)") + "' (drawing only)");
  if (r.next < r.lines.size()) r.fail(r.lines[r.next].first, "more lines than the 20 sets take");

  nlohmann::json robot;
  robot["name"] = name;
  std::ostringstream scale;
  scale << mm_per_unit;
  robot["description"] = "Imported from the original system's robot file " + name + " (thesis appendix C); lengths at " +
                         scale.str() + " mm per unit.";
  for (size_t i = 0; i < joints; ++i) {
    const auto& d = dh[i];
    nlohmann::json row = {{"a", d[0] * mm_per_unit}, {"d", d[1] * mm_per_unit}};
    if (d[0] < 0) r.fail(0, "set 3, joint " + std::to_string(i) + ": negative length");
    auto param = [&](double value, bool variable, const std::string& joint) -> nlohmann::json {
      if (!variable) return value;
      return {{"joint", joint}, {"min", -180}, {"max", 180}};
    };
    row["theta"] = param(d[2], flags[i][0] == 1, "theta" + std::to_string(i));
    row["alpha"] = param(d[3], flags[i][1] == 1, "alpha" + std::to_string(i));
    robot["dh"].push_back(row);
  }
  nlohmann::json home = nlohmann::json::object();
  for (size_t i = 0; i < joints; ++i) {
    if (flags[i][0] == 1) home["theta" + std::to_string(i)] = dh[i][2];
    if (flags[i][1] == 1) home["alpha" + std::to_string(i)] = dh[i][3];
  }
  if (home.empty()) throw LegacyError(name + ":0: no joint variable: set 9 flags no theta or alpha of any joint");
  robot["home"] = home;
  if (hand == 1)
    robot["gripper"] = {{"max_opening", 40}, {"finger_length", 40}, {"servo_open", 90}, {"servo_closed", 150}};
  out.robot = robot;
  return out;
}

}  // namespace articula::host
