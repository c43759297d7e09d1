// host/lib/program.h - programs: the RoboSim language of the thesis's appendix B, and the
// arm's own serial protocol (docs/protocol.md), read into one list of statements that
// `articula run` / `predict` and the harness execute.
#ifndef ARTICULA_HOST_PROGRAM_H
#define ARTICULA_HOST_PROGRAM_H

#include <articula/protocol.h>
#include <articula/status.h>

#include <stdexcept>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

// RoboSim's ranges (appendix B): s from 1 (slow) to kRoboSimFastest, h from 0.0 (open) to
// kRoboSimClosedHand.
constexpr double kRoboSimFastest = 82;
constexpr double kRoboSimClosedHand = 0.5;

struct Statement {
  enum class Kind {
    // RoboSim (appendix B)
    kJoints,       // m: one value per joint variable (deg or mm), absolute
    kTarget,       // a: x y z (mm) through IK
    kLinkLengths,  // l: a(i-1) of every row that has an allowed range (mm)
    kWeights,      // w: one IK weight per joint variable
    kSpeed,        // s: 1 (slow) .. 82 (fast)
    kHand,         // h: aperture 0.0 (open) .. 0.5 (closed)
    kZoom,         // z: 0.1 .. 3.5, for a viewer; no effect on the arm
    // The serial protocol: the line itself, executed by the shared codec.
    kProtocol,
  };
  Kind kind;
  std::vector<double> values;  // RoboSim arguments in file units; empty for kProtocol
  std::string text;            // kProtocol: the line as written (without comment-only lines)
  int line = 0;                // 1-based line of the command in its file
};

struct Program {
  enum class Format { kRoboSim, kProtocol };
  Format format = Format::kRoboSim;
  std::string source;  // the file (or name) it was read from
  std::vector<Statement> statements;
};

// A program that cannot be read: what() is "<file>:<line>: <problem>", a line for each line
// that cannot be read (a protocol program is read to its end, so that a student sees every
// line to mend at once; a RoboSim one stops at its first: its values span lines).
class ProgramError : public std::runtime_error {
 public:
  struct Problem {
    int line = 0;
    std::string problem;
    // the program is written for an arm of another shape (a wrong number of values for this
    // robot's joints or motors, a joint it does not have), not broken for every arm
    bool other_arm = false;
  };
  ProgramError(const std::string& file, int line, const std::string& problem, bool other_arm = false);
  ProgramError(const std::string& file, std::vector<Problem> problems);  // at least one
  // The first problem's.
  int line() const { return problems_.front().line; }
  bool other_arm() const { return problems_.front().other_arm; }
  // Every line that cannot be read, in order.
  const std::vector<Problem>& problems() const { return problems_; }

 private:
  std::vector<Problem> problems_;
};

// The RoboSim letter of a statement kind ('m', 'a', ...); '?' for kProtocol.
char robosim_letter(Statement::Kind kind);

// Which language a text is in. A file ending in .robosim or .file (the thesis's name for
// RoboSim programs) is RoboSim, one ending in .arm or .txt the protocol; otherwise the first
// command decides: a command letter alone on its line is RoboSim, a letter followed by its
// arguments (or a protocol command without any, like H or $) is the protocol.
Program::Format detect_format(const std::string& text, const std::string& name);

// A gripper action: RoboSim's h, or the protocol's G or S (in either case). A robot without
// motors spends its settle time on one (the physics and the studio's time line).
bool is_gripper_statement(const Statement& st);

// Reads a RoboSim program for `robot`: argument counts follow the robot (m and w take one
// value per joint variable, l one per row with an allowed length range), and every value
// is checked against its range. Throws ProgramError.
Program parse_robosim(const std::string& text, const std::string& name, const Robot& robot);

// Reads a protocol program: every line is checked with the shared codec now, so a program
// with a malformed line is rejected before anything runs. Throws ProgramError.
Program parse_protocol_program(const std::string& text, const std::string& name, const Robot& robot);

// Reads a program file in either language (detect_format). Throws ProgramError.
Program load_program(const std::string& path, const Robot& robot);
// The same from text in memory; `name` stands for the file (and its extension picks the language).
Program parse_program(const std::string& text, const std::string& name, const Robot& robot);

// Whether a program fits a robot, as a structured answer (the studio's examples menu offers a
// shipped program only where it fits): it reads (fits), or it is written for an arm of
// another shape (other_arm: error:4, 5 or 6 on a protocol line, or a RoboSim m, w or l with
// this robot's count of values wrong), or it is broken for every arm; the line and the problem.
struct ProgramFit {
  bool fits = true;
  bool other_arm = false;
  int line = 0;
  std::string problem;
};
ProgramFit program_fit(const std::string& text, const std::string& name, const Robot& robot);
nlohmann::json program_fit_json(const ProgramFit& fit);

// Why a protocol line was refused, in words a beginner reads, or "" when the status says it
// all: how many values its command takes and what they are (error:4, error:5), the word that
// is not a number (error:3), the commands there are (error:2), the joints there are (error:6).
std::string explain_line_error(const std::string& line, Status status, const Robot& robot);

// A program's comments, as its parser sees them (a `#` to the end of the line): the line, and
// the comment's text without the `#` and surrounding blanks; `whole_line` when nothing but
// blanks comes before it. The studio keeps them when a program opens as blocks.
struct Comment {
  int line;
  std::string text;
  bool whole_line;
};
std::vector<Comment> program_comments(const std::string& text);

// What the models that execute programs (predict.h, run.h) share:
// one protocol line through the shared codec as the controller reads it, for a robot with
// `num_joints` joint variables (kLineTooLong beyond 255 bytes);
Status parse_protocol_line(Command& cmd, const std::string& text, int num_joints);
// Whether a protocol program's line is the realtime stop alone ("!", blanks around it): a
// stream may hold one where its sender sends '!' (docs/protocol.md, "Realtime bytes").
bool is_stop_line(const std::string& text);
// a number as messages and notes print it (ostream's default, 6 significant digits: "12.5",
// "0.001"; protocol lines write theirs with protocol_number, blocks.h);
std::string number_text(double v);
// text without leading and trailing blanks;
std::string trim_blanks(const std::string& s);
// a protocol line as the arm acts on it: what comes before its comment (the core's
// comment_start), without blanks around it; "" for a blank line or a comment alone
// ("  L 0 10 # left" -> "L 0 10"). Python's articula.line_command and the page's engine call it;
std::string line_command(const std::string& line);
// the same for display: the whole line when it is a comment alone;
std::string command_text(const std::string& line);
// a note added to a record's notes, "; " between them (nothing for an empty one).
void append_note(std::string& notes, const std::string& note);

}  // namespace articula::host

#endif  // ARTICULA_HOST_PROGRAM_H
