// python/src/module.cpp - the native part of `import articula` (articula._core): the
// exceptions, and what the binding files share (arrays in and out). The Python package
// (python/articula/) re-exports it; docs/python.md is the tutorial.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>
#include <cstring>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include "bindings.h"
#include "cell_file.h"
#include "robot_view.h"
#include "legacy.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "svg.h"
#include "scene.h"

namespace articula::python {

// numpy's C API lives in this file only (import_array in the module's init).
namespace {
template <typename T>
NumpyArray<T> make_numpy(int type, int ndim, const npy_intp* dims) {
  PyObject* a = PyArray_SimpleNew(ndim, const_cast<npy_intp*>(dims), type);
  if (!a) throw nb::python_error();
  NumpyArray<T> out;
  out.obj = nb::steal(a);
  out.ptr = static_cast<T*>(PyArray_DATA(reinterpret_cast<PyArrayObject*>(a)));
  return out;
}
}  // namespace

Array new_array(std::initializer_list<size_t> shape) {
  npy_intp dims[8];
  int n = 0;
  for (size_t s : shape) dims[n++] = npy_intp(s);
  return make_numpy<double>(NPY_DOUBLE, n, dims);
}

IntArray new_int_array(size_t n) {
  const npy_intp dims[1] = {npy_intp(n)};
  return make_numpy<int32_t>(NPY_INT32, 1, dims);
}

Array44 new_array44() {
  static const npy_intp dims[2] = {4, 4};
  return make_numpy<double>(NPY_DOUBLE, 2, dims);
}

void write_transform(double* out, const Transform<double>& T) {
  for (int i = 0; i < 3; ++i) {
    out[4 * i + 0] = T.R.m[i][0];
    out[4 * i + 1] = T.R.m[i][1];
    out[4 * i + 2] = T.R.m[i][2];
    out[4 * i + 3] = T.p[i];
  }
  out[12] = out[13] = out[14] = 0;
  out[15] = 1;
}

Array44 transform_array(const Transform<double>& T) {
  Array44 a = new_array44();
  write_transform(a.data(), T);
  return a;
}

void read_joints(double* q, nb::handle values, const Robot& robot, const char* what) {
  const size_t n = size_t(robot.model.num_joints);
  // The fast path: a contiguous 1-D float64 numpy array.
  if (PyArray_Check(values.ptr())) {
    PyArrayObject* a = reinterpret_cast<PyArrayObject*>(values.ptr());
    if (PyArray_TYPE(a) == NPY_DOUBLE && PyArray_NDIM(a) == 1 && PyArray_IS_C_CONTIGUOUS(a)) {
      host::joints_in(robot, static_cast<const double*>(PyArray_DATA(a)), size_t(PyArray_DIM(a, 0)), what, q);
      return;
    }
  }
  // Another array (other dtype, 2-D, strided) or something numpy can read: as float64, 1-D.
  if (nb::ndarray_check(values) || !PySequence_Check(values.ptr())) {
    nb::object a = nb::module_::import_("numpy").attr("asarray")(values, "float64");
    const nb::object ndim = a.attr("ndim"), shape = a.attr("shape");
    if (PyLong_AsLong(ndim.ptr()) != 1)
      throw nb::value_error((std::string(what) + " must be one joint value per joint variable (a 1-D list or array), got shape " +
                             std::string(nb::str(shape).c_str()))
                                .c_str());
    a = nb::module_::import_("numpy").attr("ascontiguousarray")(a);
    read_joints(q, a, robot, what);
    return;
  }
  PyObject* seq = PySequence_Fast(values.ptr(), "");
  if (!seq) throw nb::python_error();
  nb::object owner = nb::steal(seq);
  const size_t got = size_t(PySequence_Fast_GET_SIZE(seq));
  double v[host::kMaxJoints];
  if (got != n) host::joints_in(robot, v, got, what, q);  // refused: the count, in the shared words
  PyObject** items = PySequence_Fast_ITEMS(seq);
  for (size_t j = 0; j < n; ++j) {
    v[j] = PyFloat_AsDouble(items[j]);
    if (v[j] == -1.0 && PyErr_Occurred()) {
      PyErr_Clear();
      throw nb::type_error((std::string(what) + "[" + std::to_string(j) + "] (" + robot.joint_names[j] +
                            ") is not a number: " + std::string(nb::repr(nb::handle(items[j])).c_str()))
                               .c_str());
    }
  }
  host::joints_in(robot, v, n, what, q);
}

ArrayView read_array(nb::handle values, const char* what) {
  nb::object obj = nb::borrow(values);
  PyArrayObject* a = PyArray_Check(obj.ptr()) ? reinterpret_cast<PyArrayObject*>(obj.ptr()) : nullptr;
  if (!a || PyArray_TYPE(a) != NPY_DOUBLE || !PyArray_IS_C_CONTIGUOUS(a)) {
    PyObject* c = PyArray_FROMANY(obj.ptr(), NPY_DOUBLE, 0, 8, NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
    if (!c) {
      PyErr_Clear();
      throw nb::type_error((std::string(what) + " must be numbers (a list or an array)").c_str());
    }
    obj = nb::steal(c);
    a = reinterpret_cast<PyArrayObject*>(c);
  }
  ArrayView v;
  v.keep = obj;
  v.ptr = static_cast<const double*>(PyArray_DATA(a));
  v.rank = size_t(PyArray_NDIM(a));
  for (size_t k = 0; k < v.rank; ++k) v.dims[k] = size_t(PyArray_DIM(a, int(k)));
  return v;
}

std::vector<double> read_vector(nb::handle values, const char* what) {
  auto arr = read_array(values, what);
  if (arr.ndim() != 1)
    throw nb::value_error((std::string(what) + " must be a flat list of numbers (1-D), not " +
                           std::to_string(arr.ndim()) + "-D")
                              .c_str());
  std::vector<double> v(arr.data(), arr.data() + arr.shape(0));
  host::check_finite(v.data(), v.size(), what);
  return v;
}

nb::object json_to_python(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return nb::none();
    case nlohmann::json::value_t::boolean: return nb::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return nb::int_(j.get<int64_t>());
    case nlohmann::json::value_t::number_unsigned: return nb::int_(j.get<uint64_t>());
    case nlohmann::json::value_t::number_float: return nb::float_(j.get<double>());
    case nlohmann::json::value_t::string: return nb::str(j.get_ref<const std::string&>().c_str());
    case nlohmann::json::value_t::array: {
      nb::list l;
      for (const auto& e : j) l.append(json_to_python(e));
      return l;
    }
    case nlohmann::json::value_t::object: {
      nb::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[nb::str(it.key().c_str())] = json_to_python(it.value());
      return d;
    }
    default: return nb::none();
  }
}

nb::object record(const nlohmann::json& j) {
  static nb::object cls;
  if (!cls.is_valid()) cls = nb::module_::import_("articula._records").attr("Record");
  return cls(json_to_python(j));
}

namespace {

// Exceptions with the loader's parts as attributes, all of them ValueErrors.
PyObject* g_robot_file_error = nullptr;
PyObject* g_program_error = nullptr;
PyObject* g_scene_error = nullptr;
PyObject* g_cell_error = nullptr;
PyObject* g_legacy_error = nullptr;

void raise_with(PyObject* type, const char* message, std::initializer_list<std::pair<const char*, nb::object>> attrs) {
  nb::object exc = nb::steal(PyObject_CallFunction(type, "s", message));
  if (!exc.is_valid()) return;  // the call set its own error
  for (const auto& [k, v] : attrs) nb::setattr(exc, k, v);
  PyErr_SetObject(type, exc.ptr());
}

PyObject* new_error(nb::module_& m, const char* name, const char* doc) {
  const std::string full = std::string("articula.") + name;
  PyObject* t = PyErr_NewExceptionWithDoc(full.c_str(), doc, PyExc_ValueError, nullptr);
  m.attr(name) = nb::handle(t);
  return t;
}

}  // namespace

}  // namespace articula::python

using namespace articula;
using namespace articula::python;

namespace {
// numpy's import_array is a macro that returns on failure: its own function.
bool import_numpy() {
  import_array1(false);
  return true;
}
}  // namespace

NB_MODULE(_core, m) {
  if (!import_numpy()) throw nb::python_error();
  m.doc() = "The native part of articula: the host library (host/lib, host/physics) over the portable core.";

  g_robot_file_error = new_error(m, "RobotFileError",
                                 "A robot file that cannot be used. The message names the file, the JSON path and the "
                                 "problem; so do the attributes file, json_path and problem.");
  g_program_error = new_error(m, "ProgramError", "A program that cannot be read: '<file>:<line>: <problem>' for "
                                                 "each line that cannot be read; the attribute line is the first's, "
                                                 "problems every (line, problem).");
  g_scene_error = new_error(m, "SceneError", "A scene file that cannot be used: file, JSON path and problem.");
  g_cell_error = new_error(m, "CellError", "A cell file that cannot be used: the file, the JSON path and the problem.");
  g_legacy_error = new_error(m, "LegacyError", "A legacy (thesis appendix C) robot file that cannot be read.");
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const host::RobotFileError& e) {
      raise_with(g_robot_file_error, e.what(),
                 {{"file", nb::str(e.file().c_str())}, {"json_path", nb::str(e.json_path().c_str())},
                  {"problem", nb::str(e.problem().c_str())}});
    } catch (const host::ProgramError& e) {
      nb::list problems;  // every line that cannot be read: (line, problem)
      for (const auto& q : e.problems()) problems.append(nb::make_tuple(q.line, nb::str(q.problem.c_str())));
      raise_with(g_program_error, e.what(), {{"line", nb::int_(e.line())}, {"problems", problems}});
    } catch (const host::SceneError& e) {
      raise_with(g_scene_error, e.what(), {{"json_path", nb::str(e.json_path().c_str())}});
    } catch (const host::CellError& e) {
      raise_with(g_cell_error, e.what(),
                 {{"json_path", nb::str(e.json_path().c_str())}, {"problem", nb::str(e.problem().c_str())}});
    } catch (const host::LegacyError& e) {
      raise_with(g_legacy_error, e.what(), {});
    } catch (const host::PredictError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const host::SvgError& e) {  // a drawing refused, with its reason: bad input, as for a program
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  m.def(
      "rpy_deg",
      [](nb::handle T_in) {
        const ArrayView T = read_array(T_in, "T");
        if (!((T.ndim() == 2 && T.shape(0) >= 3 && T.shape(1) >= 3)))
          throw nb::value_error("T must be a 3x3 rotation or a 4x4 pose");
        const size_t cols = T.shape(1);
        Mat3<double> R;
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) R.m[i][k] = T.data()[size_t(i) * cols + size_t(k)];
        const Vec3<double> rpy = matrix_to_rpy(R);
        return nb::make_tuple(rad_to_deg(rpy.x), rad_to_deg(rpy.y), rad_to_deg(rpy.z));
      },
      "T",
      "Roll, pitch, yaw (fixed X-Y-Z, R = Rz(yaw) Ry(pitch) Rx(roll)) in degrees of a rotation or pose, as "
      "`articula fk` prints them.");

  auto robot = bind_robot(m);
  bind_program(m, robot);
  bind_sim(m);
  bind_cell(m);
  bind_protocol(m);
  bind_experiment(m);
}
