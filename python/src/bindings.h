// python/src/bindings.h - what the binding files share: the robot as Python holds it, numpy
// arrays in and out, units at the door (mm and degrees outside, radians inside), and the
// JSON form of records (host/lib/records_json.h) as Python objects.
#ifndef ARTICULA_PYTHON_BINDINGS_H
#define ARTICULA_PYTHON_BINDINGS_H

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ik.h"
#include "predict.h"
#include "program.h"
#include "robot.h"

namespace articula::python {

namespace nb = nanobind;
using host::Robot;

// A robot as Python holds it: the loaded robot (shared with the simulations made from it),
// its IK prepared once on first use, and what an import left out.
struct PyRobot {
  std::shared_ptr<const Robot> robot;
  std::vector<std::string> import_notes;  // Robot.from_legacy: what has no place in a robot file
  mutable std::shared_ptr<const host::InverseKinematics> ik_cache;

  const Robot& r() const { return *robot; }
  const host::InverseKinematics& ik() const {
    if (!ik_cache) ik_cache = std::make_shared<const host::InverseKinematics>(*robot);
    return *ik_cache;
  }
};

// numpy arrays made here, owned by Python.
using Array = nb::ndarray<nb::numpy, double>;
using Array44 = nb::ndarray<nb::numpy, double, nb::shape<4, 4>>;
// An array of the given shape with uninitialised data; write through data().
Array new_array(std::initializer_list<size_t> shape);
Array44 new_array44();
// A transform (mm) into a 4x4 homogeneous matrix at out[0..15], row-major.
void write_transform(double* out, const Transform<double>& T);
Array44 transform_array(const Transform<double>& T);

// Joint values from Python (a list, tuple or 1-D array of the robot's number of joint
// variables, deg or mm) into model units, checked: a wrong count, a value that is not a
// number, a NaN or an infinity raise ValueError naming the joint. `what` names the argument.
void read_joints(double* q_model, nb::handle values, const Robot& robot, const char* what);
// A finite vector of any length (targets, weights).
std::vector<double> read_vector(nb::handle values, const char* what);
// A C-contiguous float64 array of at least one dimension (numpy converts anything array-like).
nb::ndarray<const double, nb::c_contig, nb::device::cpu> read_array(nb::handle values, const char* what);

// A program given as an articula.Program (its text and source) or a file path, read for the
// robot (ProgramError naming the line otherwise).
host::Program program_from(nb::handle program, const Robot& robot);
// Controller settings as {0: 800, 1: 3000}, "0=800,1=3000" or None, checked as `$n=v` lines.
host::ControllerSettings settings_from(nb::handle settings, const Robot& robot);

// JSON into Python: dicts, lists, numbers, strings, None. A JSON object at the top level
// becomes an articula.Record (attribute access over the same fields).
nb::object json_to_python(const nlohmann::json& j);
nb::object record(const nlohmann::json& j);

nb::class_<PyRobot> bind_robot(nb::module_& m);
// Programs: articula._core.detect_format, and Robot.predict / run / quantize / check_program.
void bind_program(nb::module_& m, nb::class_<PyRobot>& robot);
void bind_sim(nb::module_& m);

}  // namespace articula::python

#endif  // ARTICULA_PYTHON_BINDINGS_H
