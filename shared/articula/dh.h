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
// The DhParam as an index 0..2, anything else (validate() rejects it) as alpha, like
// param_slot.
inline uint8_t param_index(uint8_t param) { return param < kParamAlpha ? param : uint8_t(kParamAlpha); }
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
// The DH angles whose cos and sin are exact: 0, +90, -90 and +-180 deg. Most tables hold
// them as constants; they get their exact values without trigonometry (and the chain below
// turns them into exchanges of columns). Exactly pi/2 is what deg_to_rad(90) gives, in
// double and in float alike.
enum DhAngleKind : uint8_t { kAngle0 = 0, kAnglePlus90, kAngleMinus90, kAngle180, kAngleOther };

// By exact comparison; for IEEE binary64 and binary32 (8 and 4 bytes) on the bits, the
// same answer in fewer instructions (equal bits are equal values but for +-0, NaN is
// never equal) and the usual case, kAngleOther, decided first.
template <typename S, int Size = sizeof(S)>
struct DhAngleKindOf {
  static uint8_t get(S angle) {
    const S right = pi<S>() / S(2);
    if (angle == S(0)) return kAngle0;
    if (angle == right) return kAnglePlus90;
    if (angle == -right) return kAngleMinus90;
    if (angle == pi<S>() || angle == -pi<S>()) return kAngle180;
    return kAngleOther;
  }
};
template <typename S, typename U>
struct DhAngleKindBits {
  static uint8_t get(S angle) {
    const U bits = bit_copy<U>(angle);
    const U size = bits & ~(U(1) << (sizeof(U) * 8 - 1));  // without the sign
    const U right = bit_copy<U>(pi<S>() / S(2)), half_turn = bit_copy<U>(pi<S>());
    if (size == right) return bits == right ? kAnglePlus90 : kAngleMinus90;
    if (size == 0) return kAngle0;
    if (size == half_turn) return kAngle180;
    return kAngleOther;
  }
};
template <typename S>
struct DhAngleKindOf<S, 8> : DhAngleKindBits<S, uint64_t> {};
template <typename S>
struct DhAngleKindOf<S, 4> : DhAngleKindBits<S, uint32_t> {};

template <typename S>
inline uint8_t dh_angle_kind(S angle) {
  return DhAngleKindOf<S>::get(angle);
}

// cos and sin of a DH angle: exact for the angles above, Math<S>::sincos for any other.
template <typename S>
inline void dh_cos_sin(S angle, S& c, S& s) {
  switch (dh_angle_kind(angle)) {
    case kAngle0: c = S(1), s = S(0); break;
    case kAnglePlus90: c = S(0), s = S(1); break;
    case kAngleMinus90: c = S(0), s = S(-1); break;
    case kAngle180: c = S(-1), s = S(0); break;
    default: Math<S>::sincos(angle, s, c); break;
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
// cos and sin of one DH angle from its kind: exact, or cs (kAngleOther).
template <typename S>
ARTICULA_INLINE void dh_cos_sin_of(int kind, const S (&cs)[2], S& c, S& s) {
  switch (kind) {
    case kAngle0: c = S(1), s = S(0); break;
    case kAnglePlus90: c = S(0), s = S(1); break;
    case kAngleMinus90: c = S(0), s = S(-1); break;
    case kAngle180: c = S(-1), s = S(0); break;
    default: c = cs[0], s = cs[1]; break;
  }
}

// A plane rotation of one row of M by an angle of the given kind: (u, v) becomes
// (c u + s v, c v - s u). Rot_x(alpha) turns the (y, z) entries, Rot_z(theta) the (x, y).
// For the kinds with exact cos and sin it is an exchange of entries and signs: the values
// the multiplications by 0 and +-1 give.
template <int Kind>
struct DhRot {  // kAngleOther
  template <typename S>
  static void apply(S u, S v, const S& c, const S& s, S& u1, S& v1) {
    u1 = c * u + s * v;
    v1 = c * v - s * u;
  }
};
template <>
struct DhRot<kAngle0> {
  template <typename S>
  static void apply(S u, S v, const S&, const S&, S& u1, S& v1) {
    u1 = u, v1 = v;
  }
};
template <>
struct DhRot<kAnglePlus90> {
  template <typename S>
  static void apply(S u, S v, const S&, const S&, S& u1, S& v1) {
    u1 = v, v1 = -u;
  }
};
template <>
struct DhRot<kAngleMinus90> {
  template <typename S>
  static void apply(S u, S v, const S&, const S&, S& u1, S& v1) {
    u1 = -v, v1 = u;
  }
};
template <>
struct DhRot<kAngle180> {
  template <typename S>
  static void apply(S u, S v, const S&, const S&, S& u1, S& v1) {
    u1 = -u, v1 = -v;
  }
};

// The frame being chained, carried in local variables (registers on the host): the
// rows of M and the entries of p.
template <typename S>
struct DhFrame {
  S M[3][3], p[3];

  ARTICULA_INLINE void set(const S (&M0)[3][3], const S (&p0)[3]) {
    ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) M[k][0] = M0[k][0], M[k][1] = M0[k][1], M[k][2] = M0[k][2], p[k] = p0[k];
  }
  ARTICULA_INLINE void get(S (&M0)[3][3], S (&p0)[3]) const {
    ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) M0[k][0] = M[k][0], M0[k][1] = M[k][1], M0[k][2] = M[k][2], p0[k] = p[k];
  }
  ARTICULA_INLINE void store(Transform<S>& T) const {
    ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) T.R.m[k][0] = M[k][0], T.R.m[k][1] = M[k][1], T.R.m[k][2] = M[k][2];
    T.p = make_vec3(p[0], p[1], p[2]);
  }
  // T_next = T_prev * dh_transform(r), one factor at a time: Rot_x(alpha) turns the y and
  // z columns, Trans_x(a) moves along x, Rot_z(theta) turns x and y, Trans_z(d) moves
  // along the new z. At most 30 multiplications instead of the 44 of building the row's
  // matrix and multiplying; fewer for the angles of exact kinds, and a zero a or d adds
  // nothing.
  template <int AlphaKind, int ThetaKind>
  ARTICULA_INLINE void step(S a, S d, const S& ct, const S& st, const S& ca, const S& sa) {
    if (a != S(0)) {
      ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) p[k] += a * M[k][0];
    }
    ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) {
      S y1;
      DhRot<AlphaKind>::apply(M[k][1], M[k][2], ca, sa, y1, M[k][2]);
      DhRot<ThetaKind>::apply(M[k][0], y1, ct, st, M[k][0], M[k][1]);
    }
    if (d != S(0)) {
      ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) p[k] += d * M[k][2];
    }
  }
};

// One row of the chain, given the kinds of its angles as kind(alpha) * 5 + kind(theta) and
// their cos and sin, trig = {{cos theta, sin theta}, {cos alpha, sin alpha}}: a version of
// the step for each pair of kinds (25, chosen by one jump; the frame stays in registers,
// and cos and sin are read only where an angle has none exact).
template <typename F, typename S>
ARTICULA_INLINE void dh_chain_row(F& frame, S a, S d, uint8_t kinds, const S (&trig)[2][2]) {
  const S &ct = trig[0][0], &st = trig[0][1], &ca = trig[1][0], &sa = trig[1][1];
#define ARTICULA_DH_STEP(A, T) \
  case A * 5 + T: frame.template step<A, T>(a, d, ct, st, ca, sa); break;
#define ARTICULA_DH_STEPS(A)                                                                    \
  ARTICULA_DH_STEP(A, kAngle0) ARTICULA_DH_STEP(A, kAnglePlus90) ARTICULA_DH_STEP(A, kAngleMinus90) \
  ARTICULA_DH_STEP(A, kAngle180) ARTICULA_DH_STEP(A, kAngleOther)
  switch (kinds) {
    ARTICULA_DH_STEPS(kAngle0)
    ARTICULA_DH_STEPS(kAnglePlus90)
    ARTICULA_DH_STEPS(kAngleMinus90)
    ARTICULA_DH_STEPS(kAngle180)
    ARTICULA_DH_STEPS(kAngleOther)
  }
#undef ARTICULA_DH_STEPS
#undef ARTICULA_DH_STEP
}

// The tool frame: T_base_last * T_last_tool (T_base_last as M, p), with a shortcut for a
// tool that only moves the origin (identity rotation: the same result).
template <typename S>
ARTICULA_INLINE void dh_tool(Transform<S>& tool, const S (&M)[3][3], const S (&p)[3], const Transform<S>& T_last_tool) {
  const S(&T)[3][3] = T_last_tool.R.m;
  const Vec3<S>& v = T_last_tool.p;
  if (T[0][0] == S(1) && T[1][1] == S(1) && T[2][2] == S(1) && T[0][1] == S(0) && T[0][2] == S(0) &&
      T[1][0] == S(0) && T[1][2] == S(0) && T[2][0] == S(0) && T[2][1] == S(0)) {
    ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) tool.R.m[k][0] = M[k][0], tool.R.m[k][1] = M[k][1], tool.R.m[k][2] = M[k][2];
  } else {
    ARTICULA_UNROLL3 for (int k = 0; k < 3; ++k) {
      ARTICULA_UNROLL3 for (int j = 0; j < 3; ++j) tool.R.m[k][j] = M[k][0] * T[0][j] + M[k][1] * T[1][j] + M[k][2] * T[2][j];
    }
  }
  // R * v + p, as operator*(Transform, Transform) computes it
  tool.p = make_vec3(M[0][0] * v.x + M[0][1] * v.y + M[0][2] * v.z + p[0], M[1][0] * v.x + M[1][1] * v.y + M[1][2] * v.z + p[1],
                     M[2][0] * v.x + M[2][1] * v.y + M[2][2] * v.z + p[2]);
}

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

// forward_kinematics in two versions with the same values (the tests compare them; only
// the sign of a zero may differ):
// Fast = false, compact, for the Nano: the table, then the chain row by row as above.
// Fast = true, for the host (1.7x to 1.9x faster on the Panda, bench/README.md): only the
// variable parameters copied; the angles' kinds found once; the angles without exact cos
// and sin through Math<S>::sincos2 two at a time (SIMD lanes) as they are found; the
// frame carried in registers with a version of the step for each pair of kinds
// (dh_chain_row); row 1 and the tool written directly.
template <bool Fast>
struct ForwardKinematics {
  template <typename S, int J, int R>
  static void run(Frames<S, R>& out, const Model<S, J, R>& m, const S* q) {
    DhRow<S> table[R];
    dh_table(table, m, q);
    out.count = uint8_t(m.num_rows + 1);
    out.T_base_frame[0] = Transform<S>::identity();
    for (int i = 0; i < m.num_rows; ++i) dh_chain(out.T_base_frame[i + 1], out.T_base_frame[i], table[i]);
    out.T_base_tool = out.T_base_frame[m.num_rows] * m.T_last_tool;
  }
};

template <>
struct ForwardKinematics<true> {
  template <typename S, int J, int R>
  static void run(Frames<S, R>& out, const Model<S, J, R>& m, const S* q) {
    const int n = m.num_rows;
    // The row parameters at q, as dh_table() gives them, but only those that can vary (a
    // is always the model's): theta, d and alpha, indexed by DhParam.
    S var[3][R];
    for (int i = 0; i < n; ++i) {
      var[kParamTheta][i] = m.rows[i].theta;
      var[kParamD][i] = m.rows[i].d;
      var[kParamAlpha][i] = m.rows[i].alpha;
    }
    for (int j = 0; j < m.num_joints; ++j) var[param_index(m.joints[j].param)][m.joints[j].row] = q[j];
    for (int k = 0; k < m.num_linked; ++k) {
      const LinkedParam<S, J>& l = m.linked[k];
      S v = l.offset;
      for (int j = 0; j < m.num_joints; ++j) v += l.gain[j] * q[j];
      var[param_index(l.param)][l.row] = v;
    }
    // The kinds of every theta and alpha; the cos and sin of the angles without exact ones
    // go into trig, two angles at a time (Math<S>::sincos2: in the lanes of SIMD registers
    // for double). The exact ones are never stored: the steps use them as constants.
    uint8_t kinds[R];
    S trig[R][2][2];  // row i: {cos theta, sin theta}, {cos alpha, sin alpha}
    S waiting = S(0);  // an angle waiting for a second one, and where its cos and sin go
    S* waiting_cs = 0;
    for (int i = 0; i < n; ++i) {
      const uint8_t kt = dh_angle_kind(var[kParamTheta][i]), ka = dh_angle_kind(var[kParamAlpha][i]);
      kinds[i] = uint8_t(ka * 5 + kt);
      for (int k = 0; k < 2; ++k) {
        if ((k == 0 ? kt : ka) != kAngleOther) continue;
        const S x = var[k == 0 ? kParamTheta : kParamAlpha][i];
        S* cs = trig[i][k];
        if (waiting_cs) {
          Math<S>::sincos2(waiting, x, waiting_cs[1], waiting_cs[0], cs[1], cs[0]);
          waiting_cs = 0;
        } else {
          waiting = x, waiting_cs = cs;
        }
      }
    }
    if (waiting_cs) Math<S>::sincos(waiting, waiting_cs[1], waiting_cs[0]);

    out.count = uint8_t(n + 1);
    out.T_base_frame[0] = Transform<S>::identity();
    S M[3][3] = {{S(1), S(0), S(0)}, {S(0), S(1), S(0)}, {S(0), S(0), S(1)}}, p[3] = {S(0), S(0), S(0)};
    if (n > 0) {
      // Row 1 starts from the identity: its matrix as in dh_transform (the same values the
      // chain would give). Then the frame is carried along and stored row by row.
      S ct, st, ca, sa;
      dh_cos_sin_of(kinds[0] % 5, trig[0][0], ct, st);
      dh_cos_sin_of(kinds[0] / 5, trig[0][1], ca, sa);
      const S d = var[kParamD][0];
      M[0][0] = ct, M[0][1] = -st, M[0][2] = S(0);
      M[1][0] = st * ca, M[1][1] = ct * ca, M[1][2] = -sa;
      M[2][0] = st * sa, M[2][1] = ct * sa, M[2][2] = ca;
      p[0] = m.rows[0].a, p[1] = -sa * d, p[2] = ca * d;
      DhFrame<S> frame;
      frame.set(M, p);
      frame.store(out.T_base_frame[1]);
      for (int i = 1; i < n; ++i) {
        dh_chain_row(frame, m.rows[i].a, var[kParamD][i], kinds[i], trig[i]);
        frame.store(out.T_base_frame[i + 1]);
      }
      frame.get(M, p);
    }
    dh_tool(out.T_base_tool, M, p, m.T_last_tool);
  }
};
}  // namespace detail

// The frames of every row and the tool at joint values q.
template <typename S, int J, int R>
inline void forward_kinematics(Frames<S, R>& out, const Model<S, J, R>& m, const S* q) {
  detail::ForwardKinematics<kFastHost>::run(out, m, q);
}

// Tool position only: the same chain without keeping every frame.
template <typename S, int J, int R>
inline Vec3<S> tool_position(const Model<S, J, R>& m, const S* q) {
  Frames<S, R> f;
  forward_kinematics(f, m, q);
  return f.T_base_tool.p;
}

namespace detail {
// The Jacobian column of one DH parameter: its linear (lin) and angular (ang) parts.
template <typename S, int R>
ARTICULA_INLINE void param_column(Vec3<S>& lin, Vec3<S>& ang, uint8_t row, uint8_t param, const Frames<S, R>& f,
                                  const Vec3<S>& p) {
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
}

// Adds gain * (the Jacobian column of one DH parameter) into column j.
template <typename S, int J, int R>
inline void add_param_column(S out[6][J], int j, S gain, uint8_t row, uint8_t param, const Frames<S, R>& f,
                             const Vec3<S>& p) {
  Vec3<S> lin, ang;
  param_column(lin, ang, row, param, f, p);
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
// Each variable drives one parameter, whose column the host writes directly (what adding
// it to zeros gives; the Nano keeps the smaller code that does that); the linked
// parameters' terms are added after.
template <typename S, int J, int R>
inline void jacobian(S out[6][J], const Model<S, J, R>& m, const Frames<S, R>& f) {
  const Vec3<S> p = f.T_base_tool.p;
  for (int j = 0; j < m.num_joints; ++j) {
    if (kFastHost) {
      Vec3<S> lin, ang;
      detail::param_column(lin, ang, m.joints[j].row, m.joints[j].param, f, p);
      out[0][j] = lin.x, out[1][j] = lin.y, out[2][j] = lin.z;
      out[3][j] = ang.x, out[4][j] = ang.y, out[5][j] = ang.z;
    } else {
      for (int r = 0; r < 6; ++r) out[r][j] = S(0);
      detail::add_param_column(out, j, S(1), m.joints[j].row, m.joints[j].param, f, p);
    }
  }
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
