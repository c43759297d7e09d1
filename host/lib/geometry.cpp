#include "geometry.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace articula::host {

std::vector<LinkGeometry> arm_geometry(const Robot& robot) {
  std::vector<LinkGeometry> links = robot.links;
  if (links.empty()) {
    const HostModel& m = robot.model;
    double reach = 0;
    std::vector<Vec3<double>> seg(m.num_rows);
    for (int i = 0; i < m.num_rows; ++i) {
      const DhRow<double>& r = m.rows[i];
      bool d_variable = false;
      for (int j = 0; j < m.num_joints; ++j) d_variable = d_variable || (m.joints[j].row == i && m.joints[j].param == kParamD);
      for (int k = 0; k < m.num_linked; ++k) d_variable = d_variable || (m.linked[k].row == i && m.linked[k].param == kParamD);
      const double d = d_variable ? 0 : r.d;
      seg[size_t(i)] = make_vec3(r.a, -std::sin(r.alpha) * d, std::cos(r.alpha) * d);
      reach += norm(seg[size_t(i)]);
    }
    reach += norm(m.T_last_tool.p);
    const double radius = std::clamp(0.06 * reach, 5.0, 40.0);
    for (int i = 0; i < m.num_rows; ++i) {
      const Vec3<double> v = seg[size_t(i)];
      const double len = norm(v);
      if (len < 1) continue;
      Shape s;
      s.type = Shape::Type::kCapsule;
      s.size = {radius, len, 0};
      // z along v: a rotation taking (0, 0, 1) to v / len.
      const Vec3<double> z = (1.0 / len) * v;
      Vec3<double> x = std::fabs(z.x) < 0.9 ? make_vec3(1.0, 0.0, 0.0) : make_vec3(0.0, 1.0, 0.0);
      x = x - dot(x, z) * z;
      x = (1.0 / norm(x)) * x;
      const Vec3<double> y = cross(z, x);
      Mat3<double> R;
      for (int k = 0; k < 3; ++k) {
        const double cx[3] = {x.x, x.y, x.z}, cy[3] = {y.x, y.y, y.z}, cz[3] = {z.x, z.y, z.z};
        R.m[k][0] = cx[k], R.m[k][1] = cy[k], R.m[k][2] = cz[k];
      }
      s.T_frame_shape = make_transform(R, 0.5 * v);
      links.push_back({i, {s}});
    }
  }
  std::stable_sort(links.begin(), links.end(), [](const LinkGeometry& a, const LinkGeometry& b) { return a.frame < b.frame; });
  return links;
}

std::string mesh_path(const Robot& robot, const Shape& s) {
  const std::filesystem::path p(s.mesh);
  if (p.is_absolute() || robot.source.empty()) return p.string();
  return (std::filesystem::path(robot.source).parent_path() / p).string();
}

Transform<double> finger_pose(const Gripper& gripper, const Transform<double>& T_base_tool, double opening_mm, int side) {
  const double y = side * (opening_mm + gripper.finger_thickness_mm) / 2;
  return T_base_tool * make_transform(identity3<double>(), make_vec3(gripper.finger_length_mm / 2, y, 0.0));
}

}  // namespace articula::host
