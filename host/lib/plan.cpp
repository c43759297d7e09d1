// host/lib/plan.cpp - the test plan reader (plan.h).
#include "plan.h"

#include "program.h"  // trim_blanks

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <sstream>

namespace articula::host {

namespace {
std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

double number(const std::string& text, const std::string& where, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size())
    throw PlanError(where + ": " + what + " must be a number, not '" + text + "'");
  if (!std::isfinite(v)) throw PlanError(where + ": " + what + " must be a finite number, not '" + text + "'");
  return v;
}

std::string stem(const std::string& name) {
  const size_t slash = name.find_last_of("/\\");
  std::string base = slash == std::string::npos ? name : name.substr(slash + 1);
  const size_t dot = base.rfind('.');
  return dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
}
}  // namespace

Plan parse_plan(const std::string& text, const std::string& name) {
  static const std::regex kExpect("^(ok|error:[0-9]{1,3})$");
  Plan plan;
  plan.name = name;
  plan.title = stem(name);
  PlanCommand pending;
  bool has_pending = false;
  int pending_line = 0;
  std::istringstream in(text);
  std::string raw;
  for (int n = 1; std::getline(in, raw); ++n) {
    const std::string where = name + ":" + std::to_string(n);
    std::string line = raw;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string stripped = trim_blanks(line);
    if (stripped.rfind("#@", 0) == 0) {
      const std::string body = trim_blanks(stripped.substr(2));
      const size_t sp = body.find(' ');
      const std::string directive = body.substr(0, sp);
      const std::string rest = sp == std::string::npos ? "" : trim_blanks(body.substr(sp + 1));
      const std::vector<std::string> args = words(rest);
      if (directive == "title" || directive == "note") {
        if (rest.empty()) throw PlanError(where + ": #@ " + directive + " needs a text");
        if (directive == "title")
          plan.title = rest;
        else
          plan.notes.push_back(rest);
        continue;
      }
      if (!has_pending) pending_line = n;
      has_pending = true;
      if (directive == "expect") {
        if (args.size() != 1 || !std::regex_match(args[0], kExpect))
          throw PlanError(where + ": #@ expect takes ok or error:N, not '" + rest + "'");
        pending.expect = args[0];
      } else if (directive == "timeout") {
        if (args.size() != 1) throw PlanError(where + ": #@ timeout takes one number of seconds");
        const double t = number(args[0], where, "the timeout");
        if (t <= 0) throw PlanError(where + ": the timeout must be above 0 s");
        pending.timeout_s = t;
      } else if (directive == "single-joint") {
        if (args.size() != 2 || !all_digits(args[0]) || args[0].size() > 2)
          throw PlanError(where + ": #@ single-joint takes a joint index and the thesis's angle");
        pending.joint = std::atoi(args[0].c_str());
        pending.thesis_angle = number(args[1], where, "the thesis's angle");
      } else if (directive == "repeat") {
        if (args.size() != 2 || !all_digits(args[0]) || args[0].size() > 6 || (args[1] != "out" && args[1] != "back"))
          throw PlanError(where + ": #@ repeat takes a chain number and out or back");
        pending.chain = std::atoi(args[0].c_str());
        pending.leg = args[1];
      } else {
        throw PlanError(where + ": unknown directive '#@ " + directive +
                        "' (title, note, expect, timeout, single-joint, repeat)");
      }
      continue;
    }
    if (stripped.empty() || stripped[0] == '#') continue;
    // The arm acts on '?' and '!' wherever they come, comments included: a plan line must not
    // hold them (the harness sends them itself, '?' to poll the status).
    if (line.find_first_of("?!") != std::string::npos)
      throw PlanError(where + ": '" + line + "' holds a realtime byte (? or !), which the arm would act on");
    pending.line = n;
    pending.text = stripped;  // as `articula predict` reads it: without the blanks around it
    plan.commands.push_back(pending);
    pending = PlanCommand();
    has_pending = false;
  }
  if (has_pending) throw PlanError(name + ":" + std::to_string(pending_line) + ": directive without a command line after it");
  if (plan.commands.empty()) throw PlanError(name + ": no command lines");
  return plan;
}

}  // namespace articula::host
