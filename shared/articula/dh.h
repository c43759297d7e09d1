// articula/dh.h - modified (Craig) Denavit-Hartenberg kinematics.
//
// A Model is the constant description of an arm; joint values live outside it (q[]), and
// the results go into caller-owned structs (Frames, a Jacobian array): no heap, fixed sizes
// chosen by template parameters.
//
// Row i holds a(i-1), alpha(i-1), d(i), theta(i) and gives (thesis eq. 2.1.1.1, Craig 3.6)
//     T_{i-1,i} = Rot_x(alpha(i-1)) * Trans_x(a(i-1)) * Rot_z(theta(i)) * Trans_z(d(i)).
// Any of theta, d and alpha in any row may be a joint variable (the original system let
// one row both rotate about z and twist about x). A DH parameter may instead be *linked*:
// a fixed linear function of the joint variables, the way the MK2 arm's parallelogram keeps
// its gripper level (theta4 = -(theta2 + theta3)).
//
// Units: lengths in millimetres, angles in radians. Interfaces convert from degrees.
#ifndef ARTICULA_DH_H
#define ARTICULA_DH_H

#include "transform.h"

namespace articula {

// Which DH parameter of a row a joint variable (or a link) drives.
enum DhParam : uint8_t { kParamTheta = 0, kParamD = 1, kParamAlpha = 2 };

template <typename Scalar>
struct DhRow {
  Scalar a;      // a(i-1), mm: along x(i-1)
  Scalar alpha;  // alpha(i-1), rad: about x(i-1)
  Scalar d;      // d(i), mm: along z(i)
  Scalar theta;  // theta(i), rad: about z(i)
};

// A joint variable: its value *is* the DH parameter it names (no hidden offset), so
// q = 90 deg on a theta variable means theta = 90 deg in the table.
template <typename Scalar>
struct JointSpec {
  uint8_t row;    // 0-based row index
  uint8_t param;  // DhParam
  Scalar lo, hi;  // limits, rad or mm; lo <= hi
};

// A linked (passive) DH parameter: value = offset + sum_j gain[j] * q[j].
template <typename Scalar, int MaxJoints>
struct LinkedParam {
  uint8_t row;
  uint8_t param;
  Scalar offset;
  Scalar gain[MaxJoints];
};

template <typename Scalar, int MaxJoints, int MaxRows>
struct Model {
  typedef Scalar ScalarType;
  static const int kMaxJoints = MaxJoints;
  static const int kMaxRows = MaxRows;

  uint8_t num_rows;
  uint8_t num_joints;
  uint8_t num_linked;
  DhRow<Scalar> rows[MaxRows];  // constants; variable and linked entries are overwritten
  JointSpec<Scalar> joints[MaxJoints];
  LinkedParam<Scalar, MaxJoints> linked[MaxRows];
  Transform<Scalar> T_last_tool;  // fixed tool transform after the last row
};

// The frames of one pose: T_base_frame[0] is the base (identity), T_base_frame[i] the frame
// of row i, and T_base_tool the tool frame.
template <typename Scalar, int MaxRows>
struct Frames {
  uint8_t count;  // rows + 1
  Transform<Scalar> T_base_frame[MaxRows + 1];
  Transform<Scalar> T_base_tool;
};

// Why a model is not usable; kModelOk when it is.
enum ModelError : uint8_t {
  kModelOk = 0,
  kModelTooManyRows,
  kModelTooManyJoints,
  kModelBadRow,       // a joint or link names a row that does not exist
  kModelBadParam,     // a param that is not theta, d or alpha
  kModelDuplicate,    // two joints/links drive the same parameter
  kModelBadLimits,    // lo > hi, or not finite
  kModelNotFinite,    // a NaN or inf among the constants
};

inline const char* model_error_text(ModelError e) {
  switch (e) {
    case kModelOk: return "ok";
    case kModelTooManyRows: return "more DH rows than this build supports";
    case kModelTooManyJoints: return "more joint variables than this build supports";
    case kModelBadRow: return "a joint variable names a row that does not exist";
    case kModelBadParam: return "a joint variable names a parameter other than theta, d or alpha";
    case kModelDuplicate: return "two joint variables drive the same DH parameter";
    case kModelBadLimits: return "joint limits inverted or not finite";
    case kModelNotFinite: return "a DH constant is NaN or infinite";
  }
  return "unknown model error";
}

namespace detail {
template <typename Scalar>
inline Scalar* param_slot(DhRow<Scalar>& row, uint8_t param) {
  return param == kParamTheta ? &row.theta : (param == kParamD ? &row.d : &row.alpha);
}
}  // namespace detail

template <typename S, int J, int R>
inline ModelError validate(const Model<S, J, R>& m) {
  if (m.num_rows > R) return kModelTooManyRows;
  if (m.num_joints > J || m.num_linked > R) return kModelTooManyJoints;
  for (int i = 0; i < m.num_rows; ++i) {
    const DhRow<S>& r = m.rows[i];
    if (!is_finite(r.a) || !is_finite(r.alpha) || !is_finite(r.d) || !is_finite(r.theta)) return kModelNotFinite;
  }
  // Each (row, param) pair may be driven by one joint or one link at most.
  for (int k = 0; k < m.num_joints + m.num_linked; ++k) {
    const uint8_t row = k < m.num_joints ? m.joints[k].row : m.linked[k - m.num_joints].row;
    const uint8_t param = k < m.num_joints ? m.joints[k].param : m.linked[k - m.num_joints].param;
    if (row >= m.num_rows) return kModelBadRow;
    if (param > kParamAlpha) return kModelBadParam;
    for (int l = 0; l < k; ++l) {
      const uint8_t row2 = l < m.num_joints ? m.joints[l].row : m.linked[l - m.num_joints].row;
      const uint8_t param2 = l < m.num_joints ? m.joints[l].param : m.linked[l - m.num_joints].param;
      if (row == row2 && param == param2) return kModelDuplicate;
    }
  }
  for (int j = 0; j < m.num_joints; ++j) {
    const JointSpec<S>& js = m.joints[j];
    if (!is_finite(js.lo) || !is_finite(js.hi) || js.lo > js.hi) return kModelBadLimits;
  }
  for (int k = 0; k < m.num_linked; ++k) {
    if (!is_finite(m.linked[k].offset)) return kModelNotFinite;
    for (int j = 0; j < m.num_joints; ++j)
      if (!is_finite(m.linked[k].gain[j])) return kModelNotFinite;
  }
  return kModelOk;
}

// The DH table at joint values q: constants with variables and links filled in.
template <typename S, int J, int R>
inline void dh_table(DhRow<S>* out, const Model<S, J, R>& m, const S* q) {
  for (int i = 0; i < m.num_rows; ++i) out[i] = m.rows[i];
  for (int j = 0; j < m.num_joints; ++j) *detail::param_slot(out[m.joints[j].row], m.joints[j].param) = q[j];
  for (int k = 0; k < m.num_linked; ++k) {
    const LinkedParam<S, J>& l = m.linked[k];
    S v = l.offset;
    for (int j = 0; j < m.num_joints; ++j) v += l.gain[j] * q[j];
    *detail::param_slot(out[l.row], l.param) = v;
  }
}

namespace detail {
// cos and sin of a DH angle. Most tables hold angles of 0, +-90 and 180 deg: those get
// their exact values without a call to the maths library (the host's forward kinematics
// spends most of its time in sin and cos). Exactly pi/2 is what deg_to_rad(90) gives, in
// double and in float alike; any other value takes the library's cos and sin.
template <typename S>
inline void dh_cos_sin(S angle, S& c, S& s) {
  const S right = pi<S>() / S(2);
  if (angle == S(0)) {
    c = S(1), s = S(0);
  } else if (angle == right || angle == -right) {
    c = S(0), s = angle > S(0) ? S(1) : S(-1);
  } else if (angle == pi<S>() || angle == -pi<S>()) {
    c = S(-1), s = S(0);
  } else {
    c = Math<S>::cos(angle), s = Math<S>::sin(angle);
  }
}
}  // namespace detail

// T_{i-1,i} of one row, in the matrix form of thesis eq. 2.1.1.2.
template <typename S>
inline Transform<S> dh_transform(const DhRow<S>& r) {
  S ct, st, ca, sa;
  detail::dh_cos_sin(r.theta, ct, st);
  detail::dh_cos_sin(r.alpha, ca, sa);
  Transform<S> t;
  t.R.m[0][0] = ct;      t.R.m[0][1] = -st;     t.R.m[0][2] = S(0);
  t.R.m[1][0] = st * ca; t.R.m[1][1] = ct * ca; t.R.m[1][2] = -sa;
  t.R.m[2][0] = st * sa; t.R.m[2][1] = ct * sa; t.R.m[2][2] = ca;
  t.p = make_vec3(r.a, -sa * r.d, ca * r.d);
  return t;
}

namespace detail {
// T_next = T_prev * dh_transform(r), one factor at a time: Rot_x(alpha) turns the y and z
// columns, Trans_x(a) moves along x, Rot_z(theta) turns x and y, Trans_z(d) moves along the
// new z. 30 multiplications instead of the 44 of building the row's matrix and multiplying;
// equal to the product up to rounding.
template <typename S>
inline void dh_chain(Transform<S>& next, const Transform<S>& prev, const DhRow<S>& r) {
  S ct, st, ca, sa;
  dh_cos_sin(r.theta, ct, st);
  dh_cos_sin(r.alpha, ca, sa);
  for (int k = 0; k < 3; ++k) {
    const S x = prev.R.m[k][0], y = prev.R.m[k][1], z = prev.R.m[k][2];
    const S y1 = ca * y + sa * z;
    const S z1 = ca * z - sa * y;
    next.R.m[k][0] = ct * x + st * y1;
    next.R.m[k][1] = ct * y1 - st * x;
    next.R.m[k][2] = z1;
    next.p[k] = prev.p[k] + r.a * x + r.d * z1;
  }
}
}  // namespace detail

template <typename S, int J, int R>
inline void forward_kinematics(Frames<S, R>& out, const Model<S, J, R>& m, const S* q) {
  DhRow<S> table[R];
  dh_table(table, m, q);
  out.count = uint8_t(m.num_rows + 1);
  out.T_base_frame[0] = Transform<S>::identity();
  for (int i = 0; i < m.num_rows; ++i) detail::dh_chain(out.T_base_frame[i + 1], out.T_base_frame[i], table[i]);
  out.T_base_tool = out.T_base_frame[m.num_rows] * m.T_last_tool;
}

// Tool position only: the same chain without keeping every frame.
template <typename S, int J, int R>
inline Vec3<S> tool_position(const Model<S, J, R>& m, const S* q) {
  Frames<S, R> f;
  forward_kinematics(f, m, q);
  return f.T_base_tool.p;
}

namespace detail {
// Adds gain * (the Jacobian column of one DH parameter) into column j.
template <typename S, int J, int R>
inline void add_param_column(S out[6][J], int j, S gain, uint8_t row, uint8_t param, const Frames<S, R>& f,
                             const Vec3<S>& p) {
  Vec3<S> lin, ang;
  if (param == kParamAlpha) {
    const Transform<S>& T = f.T_base_frame[row];  // frame i-1
    ang = T.R.col(0);
    lin = cross(ang, p - T.p);
  } else {
    const Transform<S>& T = f.T_base_frame[row + 1];  // frame i
    const Vec3<S> z = T.R.col(2);
    if (param == kParamTheta) {
      ang = z;
      lin = cross(z, p - T.p);
    } else {
      ang = make_vec3(S(0), S(0), S(0));
      lin = z;
    }
  }
  for (int k = 0; k < 3; ++k) {
    out[k][j] += gain * lin[k];
    out[k + 3][j] += gain * ang[k];
  }
}
}  // namespace detail

// Geometric Jacobian of the tool frame origin, in base coordinates: J[0..2][j] linear
// velocity (mm per unit of q[j]), J[3..5][j] angular velocity (rad per unit). One column per
// joint variable; a variable that also drives linked parameters collects their terms by
// the chain rule (gain * column of the linked parameter).
//   theta(i): rotation about z(i) through o(i):      [z_i x (p - o_i); z_i]
//   d(i):     translation along z(i):                [z_i; 0]
//   alpha(i-1): rotation about x(i-1) through o(i-1): [x_{i-1} x (p - o_{i-1}); x_{i-1}]
// (Rot_x(alpha) comes first in the row's product, so it turns everything after it.)
template <typename S, int J, int R>
inline void jacobian(S out[6][J], const Model<S, J, R>& m, const Frames<S, R>& f) {
  const Vec3<S> p = f.T_base_tool.p;
  for (int j = 0; j < m.num_joints; ++j)
    for (int r = 0; r < 6; ++r) out[r][j] = S(0);

  for (int j = 0; j < m.num_joints; ++j) detail::add_param_column(out, j, S(1), m.joints[j].row, m.joints[j].param, f, p);
  for (int k = 0; k < m.num_linked; ++k)
    for (int j = 0; j < m.num_joints; ++j)
      if (m.linked[k].gain[j] != S(0)) detail::add_param_column(out, j, m.linked[k].gain[j], m.linked[k].row, m.linked[k].param, f, p);
}

template <typename S, int J, int R>
inline bool within_limits(const Model<S, J, R>& m, const S* q) {
  for (int j = 0; j < m.num_joints; ++j)
    if (!(q[j] >= m.joints[j].lo && q[j] <= m.joints[j].hi)) return false;  // NaN fails too
  return true;
}

// The same model in another scalar type (Pinocchio's model.cast<NewScalar>()), so the
// float computation the Nano does can run beside the double reference on the host.
template <typename To, typename From, int J, int R>
inline Model<To, J, R> cast_model(const Model<From, J, R>& m) {
  Model<To, J, R> r;
  r.num_rows = m.num_rows;
  r.num_joints = m.num_joints;
  r.num_linked = m.num_linked;
  for (int i = 0; i < R; ++i) {
    const DhRow<From>& s = m.rows[i];
    DhRow<To> d = {To(s.a), To(s.alpha), To(s.d), To(s.theta)};
    r.rows[i] = d;
  }
  for (int j = 0; j < J; ++j) {
    r.joints[j].row = m.joints[j].row;
    r.joints[j].param = m.joints[j].param;
    r.joints[j].lo = To(m.joints[j].lo);
    r.joints[j].hi = To(m.joints[j].hi);
  }
  for (int k = 0; k < R; ++k) {
    r.linked[k].row = m.linked[k].row;
    r.linked[k].param = m.linked[k].param;
    r.linked[k].offset = To(m.linked[k].offset);
    for (int j = 0; j < J; ++j) r.linked[k].gain[j] = To(m.linked[k].gain[j]);
  }
  r.T_last_tool = cast<To>(m.T_last_tool);
  return r;
}

}  // namespace articula

#endif  // ARTICULA_DH_H
