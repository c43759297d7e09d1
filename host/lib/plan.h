// host/lib/plan.h - test plans: protocol programs (docs/protocol.md, one command a line) with
// `#@` directives for the sim-vs-real experiment (hil/plans/README.md). The one reader of
// them: the harness (hil/harness/plan.py) and the studio's Experiment panel both call it.
//
//   #@ title TEXT              the plan's title
//   #@ note TEXT               a paragraph for the report (any number)
//   #@ expect ok|error:N       the reply the next command must get (default ok)
//   #@ timeout SECONDS         the next command's time limit, line sent to Idle
//   #@ single-joint J ANGLE    the next command is a single-joint test of actuator J at the
//                              thesis's angle ANGLE (thesis 5.2, Table 4)
//   #@ repeat N out|back       the next command is a move of repeatability chain N, on its
//                              way out or back (thesis 5.3, Table 5)
#ifndef ARTICULA_HOST_PLAN_H
#define ARTICULA_HOST_PLAN_H

#include <stdexcept>
#include <string>
#include <vector>

namespace articula::host {

// A plan that cannot run: the message names name:line.
class PlanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PlanCommand {
  int line = 0;             // 1-based line in the plan
  std::string text;         // the line as sent: without its line end and the blanks around it
  std::string expect = "ok";
  double timeout_s = 0;     // 0: the default
  int joint = -1;           // single-joint: the actuator (-1: not a single-joint test)
  double thesis_angle = 0;  //   and the thesis's angle
  int chain = -1;           // repeat: the chain (-1: not a repeatability move)
  std::string leg;          //   "out" or "back"
};

struct Plan {
  std::string name;  // as given (a file name or path)
  std::string title;  // #@ title, else the name's stem
  std::vector<std::string> notes;
  std::vector<PlanCommand> commands;
};

// Reads a plan's text; `name` names it in messages. Throws PlanError.
Plan parse_plan(const std::string& text, const std::string& name);

}  // namespace articula::host

#endif  // ARTICULA_HOST_PLAN_H
