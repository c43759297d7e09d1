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

// A numpy array made here (numpy's C API, module.cpp: a fraction of the cost of a general
// ndarray export, which matters for a 4x4 pose returned a million times), owned by Python.
template <typename T>
struct NumpyArray {
  nb::object obj;
  T* ptr = nullptr;
  T* data() const { return ptr; }
};
using Array = NumpyArray<double>;
using Array44 = Array;
using IntArray = NumpyArray<int32_t>;
// Arrays of the given shape with uninitialised data; write through data().
Array new_array(std::initializer_list<size_t> shape);
IntArray new_int_array(size_t n);
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
// Numbers from Python as a C-contiguous float64 array: a numpy array of that kind is read in
// place, anything else array-like is converted by numpy (kept alive by the view).
struct ArrayView {
  nb::object keep;
  const double* ptr = nullptr;
  size_t dims[8] = {};
  size_t rank = 0;
  size_t ndim() const { return rank; }
  size_t shape(size_t k) const { return dims[k]; }
  const double* data() const { return ptr; }
  size_t size() const {
    size_t n = 1;
    for (size_t k = 0; k < rank; ++k) n *= dims[k];
    return n;
  }
};
ArrayView read_array(nb::handle values, const char* what);

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
void bind_cell(nb::module_& m);
// The protocol: articula._core.parse_arm_line, first_interval_s, _status_table.
void bind_protocol(nb::module_& m);
void bind_experiment(nb::module_& m);

}  // namespace articula::python

// Arrays go to Python as they are, typed for the stubs as numpy arrays.
namespace nanobind::detail {
template <typename T>
struct numpy_array_name;
template <>
struct numpy_array_name<double> {
  static constexpr auto name = const_name("numpy.typing.NDArray[numpy.float64]");
};
template <>
struct numpy_array_name<int32_t> {
  static constexpr auto name = const_name("numpy.typing.NDArray[numpy.int32]");
};
template <typename T>
struct type_caster<articula::python::NumpyArray<T>> {
  using Array = articula::python::NumpyArray<T>;
  NB_TYPE_CASTER(Array, numpy_array_name<T>::name)
  bool from_python(handle, uint8_t, cleanup_list*) noexcept { return false; }
  static handle from_cpp(const articula::python::NumpyArray<T>& a, rv_policy, cleanup_list*) noexcept {
    return a.obj.inc_ref();
  }
};
}  // namespace nanobind::detail

#endif  // ARTICULA_PYTHON_BINDINGS_H
