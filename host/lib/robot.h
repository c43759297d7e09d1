// host/lib/robot.h - a robot as the host tools see it: the core's structures (double)
// plus names, home pose, link geometry and gripper from the robot file.
#ifndef ARTICULA_HOST_ROBOT_H
#define ARTICULA_HOST_ROBOT_H

#include <articula/actuation.h>
#include <articula/dh.h>
#include <articula/drive.h>

#include <array>
#include <string>
#include <vector>

namespace articula::host {

// What one host binary supports; more in a robot file is a load error.
inline constexpr int kMaxJoints = 12;
inline constexpr int kMaxRows = 16;

using HostModel = Model<double, kMaxJoints, kMaxRows>;
using HostActuation = Actuation<double, kMaxJoints>;
using HostFrames = Frames<double, kMaxRows>;

// A collision/drawing primitive attached to the frame of one DH row (row 0 = the base).
struct Shape {
  enum class Type { kBox, kCylinder, kCapsule, kSphere, kMesh };
  Type type = Type::kBox;
  std::array<double, 3> size{};  // box: x y z; cylinder/capsule: radius, length, 0; sphere: radius, 0, 0 (mm)
  std::string mesh;              // kMesh: path relative to the robot file
  Transform<double> T_frame_shape = Transform<double>::identity();  // pose in the row's frame (mm, rad)
  double mass = 0;     // kg; 0 = from density
  double density = 0;  // kg/m^3; used when mass is 0
};

struct LinkGeometry {
  int frame = 0;  // index into Frames::T_base_frame
  std::vector<Shape> shapes;
};

struct Gripper {
  bool present = false;
  double max_opening_mm = 0;    // finger gap when fully open
  double finger_length_mm = 0;  // for drawing and physics
  double finger_thickness_mm = 8;  // physics: each finger's size across the opening
  double finger_height_mm = 20;    //   and along the tool's z
  double servo_open_deg = 0;    // servo angle for fully open
  double servo_closed_deg = 0;  // servo angle for fully closed
};

// The range RoboSim's `l` command may set a row's a(i-1) to (robot file: "a" as
// {"value", "min", "max"}); rows with a plain number are not adjustable.
struct LengthRange {
  bool adjustable = false;
  double min = 0, max = 0;  // mm
};

// What a stepper can deliver (robot file: a motor's "torque"; docs/stall.md). Empty
// pull_out: not given, nothing to check against.
struct MotorTorque {
  // Pull-out torque against the full-step rate: (full steps/s, N*m) pairs, rates strictly
  // ascending from 0; linear in between, 0 beyond the last rate. The value at 0 is the
  // holding torque.
  std::vector<std::array<double, 2>> pull_out;
  double rotor_inertia = 0;  // kg*m^2, of the rotor (and pinion) about the motor shaft

  bool given() const { return !pull_out.empty(); }
};

// How one motor is driven (robot file: a motor's "driver"; robots/README.md "Drive").
struct MotorDriver {
  DriveKind kind = kDriveL298n;
  int chip = 0;  // kDriveStepDir: index into articula::kStepDirChip
  // kDriveServo: the signal pin (index into board::kHeaderPin), the pulse widths it may be
  // given, the two calibration points [pulse us, deg] and the speed and acceleration a move
  // ramps the pulse at.
  int pin = -1;
  double pulse_min_us = 0, pulse_max_us = 0;
  std::array<std::array<double, 2>, 2> at{};
  double speed_deg_s = 0, accel_deg_s2 = 0;
  // kDriveServo: what the physics models (the servo's own position loop): its dead band (us)
  // and its top speed (deg/s).
  double deadband_us = 5, top_speed_deg_s = 300;
};

// The board and every motor's driver: what the firmware build and the wiring follow. A file
// that names neither (given false) describes an arm the host's firmware runs with as many
// motors as it has, wired to nothing; its wiring, when asked for, is the thesis's.
struct Drive {
  bool given = false;               // the file names a board or a driver
  int board = 0;                    // index into board::kBoardInfo (0: the Nano)
  std::vector<MotorDriver> motors;  // one per motor (L298N when the file says nothing)
};

// A digital I/O pin of the arm's board that the robot file names, for signals to and from other
// arms and the world's devices (a cell's wires, cells/README.md): a free header pin, checked
// against the board's one pin table with everything else the arm wires (wiring.h).
enum IoMode { kIoOutput, kIoInput, kIoInputPullup };
constexpr int kMaxIoPins = 4;  // a robot file names at most this many
struct IoPin {
  std::string name;  // as programs and wires name it: "ready"
  int pin = -1;      // index into board::kHeaderPin
  IoMode mode = kIoOutput;
  bool input() const { return mode != kIoOutput; }
};
// "output", "input", "input_pullup": as the robot file writes a mode.
const char* io_mode_id(IoMode m);

struct Robot {
  std::string name;
  std::string description;
  std::string source;  // the file it was loaded from

  HostModel model{};
  std::vector<std::string> joint_names;  // one per joint variable, in model order

  bool has_motors = false;  // false: a purely kinematic robot (no steps, no prediction)
  HostActuation actuation{};
  std::vector<std::string> motor_names;
  std::vector<MotorTorque> motor_torque;  // one per motor (empty curves when not given)
  Drive drive;                            // the board and the motors' drivers

  std::vector<double> home;  // joint variables, rad or mm, in model order

  std::vector<LengthRange> length_ranges;  // one per DH row

  std::vector<LinkGeometry> links;
  Gripper gripper;
  std::vector<IoPin> io;  // the named I/O pins, in file order

  // The I/O pin of that name, or null.
  const IoPin* io_pin(const std::string& name) const {
    for (const IoPin& p : io)
      if (p.name == name) return &p;
    return nullptr;
  }
};

// How the arm's motors are driven: the first motor's driver (the loader has every motor of one
// family: L298N, ULN2003, STEP/DIR or servo), an L298N's when the file names none.
inline DriveKind arm_drive(const Robot& robot) {
  return robot.drive.motors.empty() ? kDriveL298n : robot.drive.motors[0].kind;
}

// A servo motor's 0.5 us ticks per degree of its output: its steps are those ticks, and the
// loader puts its calibration in its MotorSpec as 360 steps a turn through the gear num/den.
inline double servo_ticks_per_deg(const MotorSpec& m) { return double(m.gear_num) / double(m.gear_den); }

// A joint variable is an angle (theta or alpha: degrees in files and at the interfaces,
// radians in the model) or a length (d: mm everywhere).
inline bool joint_is_angle(const Robot& robot, int joint) { return robot.model.joints[joint].param != kParamD; }
inline const char* joint_unit(const Robot& robot, int joint) { return joint_is_angle(robot, joint) ? "deg" : "mm"; }
// A joint value in file units (deg or mm) in model units (rad or mm), and back.
inline double joint_to_model(const Robot& robot, int joint, double value) {
  return joint_is_angle(robot, joint) ? deg_to_rad(value) : value;
}
inline double joint_from_model(const Robot& robot, int joint, double value) {
  return joint_is_angle(robot, joint) ? rad_to_deg(value) : value;
}

// RoboSim's l: a(i-1) of every row with an allowed length range, in row order (mm). Values
// beyond the number of adjustable rows are ignored; the caller checks them against
// length_ranges (program.cpp does for programs).
inline void set_link_lengths(Robot& robot, const std::vector<double>& values) {
  size_t k = 0;
  for (int row = 0; row < robot.model.num_rows && row < int(robot.length_ranges.size()); ++row)
    if (robot.length_ranges[size_t(row)].adjustable && k < values.size()) robot.model.rows[row].a = values[k++];
}

}  // namespace articula::host

#endif  // ARTICULA_HOST_ROBOT_H
