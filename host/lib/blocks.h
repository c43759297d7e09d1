// host/lib/blocks.h - the studio's blocks as programs, and programs as blocks: the actions a
// workspace unrolls into (the student's units: joint values as the sliders show them, mm,
// percent; studio/web/src/blocks/unroll.ts) become protocol lines and RoboSim, with the blocks
// whose values the arm would refuse and why; a program's text becomes actions again. And the
// one writer of protocol lines and of their numbers every tool here uses (the page's moves,
// its IK's straight lines, the experiment's start, the blocks, the drawings, the prediction's
// lines for RoboSim, the harness's random plans and fuzz through the Python binding); the
// numbers are the firmware's own writer's (shared/articula/protocol.h).
//
// One home for these rules, so the page, Python and the tests agree: the joint and motor
// limits are the robot's (robot_view.h), the speed is the settings table's $0
// (shared/articula/settings.h) and RoboSim's s (program.h), the IK is ik.h's.
#ifndef ARTICULA_HOST_BLOCKS_H
#define ARTICULA_HOST_BLOCKS_H

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "ik.h"
#include "robot.h"

namespace articula::host {

// A number as a protocol line writes it: rounded to thousandths (the protocol's resolution) and
// written by the firmware's own number writer (articula::detail::write_fixed, which writes its
// reports), without trailing zeros ("12.5", "0", "-0.001"), or with all three decimals when
// `every_decimal` ("12.500": exact commanded millidegrees, as the prediction writes them). A
// value beyond what a line carries (not finite, or over 2,000,000) is written as
// number_text() would, for a message.
std::string protocol_number(double v, bool every_decimal = false);

// One protocol line: the command `word` ('M', 'P', 'T', 'G', 'L', 'D', '$', ...) with its
// values, as the command table (shared/articula/protocol.h) reads them: `M` one per actuator
// (motors, or joint variables for a robot without), `$` the setting's number and its value
// ("$0=600"). Throws std::invalid_argument for a word the protocol lacks, a wrong count, a
// non-finite value, or a magnitude the parser refuses (above 1,000,000).
std::string protocol_line(const Robot& robot, char word, const std::vector<double>& values,
                          bool every_decimal = false);

// The line that moves the arm to joint values q (deg or mm, one per joint variable): `M` with
// the motors' angles for a robot with motors, else with the joint values.
std::string move_line(const Robot& robot, const std::vector<double>& q);

// The program of a list of actions (JSON: [{"op", "block", ...}], the ops of unroll.ts):
// {"text": the protocol program, "robosim": the same in RoboSim, "lines": the block of each
// protocol line (index = line - 1 of the text, "" for the header), "problems": [{"block",
// "message"}] for values the arm would refuse (beyond a joint's or a motor's range, a point
// out of reach, a speed, a gripper)}. An action that cannot become a line at all (a joint the
// robot lacks, a wrong count of values) gives {"error": {"block", "message"}} instead.
// Poses follow the actions from power-up (every motor at zero) or, without motors, the home
// pose; a refused move leaves the pose where it was.
// The pen's actions (draw.h): "pen" {pen, z} says how long the pen is and where the paper is;
// then "pen_down" and "pen_up" (a straight line down to the paper, or up by the lift, where the
// tool is), "pen_to" {xy} (a straight line at the pen's height), "write" {text, width, at} and
// "shape" {shape, width, at} (the drawing's strokes, pen down along each, up between).
nlohmann::json blocks_program_json(const Robot& robot, const InverseKinematics& ik, const nlohmann::json& ops);

// A program's text as actions, for blocks: {"ops": [{"op", ...}], "format": "protocol" or
// "robosim"}; its comments kept, in order. Throws ProgramError (program.h) as the parser does.
nlohmann::json program_actions_json(const Robot& robot, const std::string& text, const std::string& name);

// Where the toolbox's blocks point for this arm, so that a block taken from it is one the arm
// can do (a class's meArm reaches about 228 mm, the MK2 370): {"tool": [x, y, z] (a point the
// tool reaches, below the home pose's), "line_to": [x, y, z] (a straight line from there the
// tool follows), "pen": mm, "paper_z": mm, "draw_at": [x, y], "draw_width": mm (a pen that long
// draws a square that wide there, as check_reach finds; "fits" false when none was found and
// the MK2's are given)}. Round numbers: 10 mm where they reach, else 1 mm.
nlohmann::json example_places_json(const Robot& robot, const InverseKinematics& ik);

}  // namespace articula::host

#endif  // ARTICULA_HOST_BLOCKS_H
