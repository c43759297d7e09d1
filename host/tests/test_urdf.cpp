// Tests host/lib/urdf.cpp: every shipped robot exports to a URDF that urdfdom's check_urdf
// accepts, and whose joint chain, evaluated here independently of the core (parsed back from
// the XML), puts the tool where the DH forward kinematics does, mimic joints included.
#include <articula/dh.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>

#include "robot_file.h"
#include "urdf.h"

using namespace articula;
using namespace articula::host;

namespace {

struct UJoint {
  std::string name, type, parent, child, mimic;
  double xyz[3] = {0, 0, 0}, rpy[3] = {0, 0, 0}, axis[3] = {0, 0, 0}, multiplier = 1;
};

std::vector<double> numbers(const std::string& s) {
  std::vector<double> v;
  std::istringstream in(s);
  double x;
  while (in >> x) v.push_back(x);
  return v;
}

std::vector<UJoint> parse_joints(const std::string& xml) {
  std::vector<UJoint> out;
  const std::regex joint_re("<joint name=\"([^\"]+)\" type=\"([^\"]+)\">([\\s\\S]*?)</joint>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), joint_re); it != std::sregex_iterator(); ++it) {
    UJoint j;
    j.name = (*it)[1];
    j.type = (*it)[2];
    const std::string body = (*it)[3];
    std::smatch m;
    if (std::regex_search(body, m, std::regex("<parent link=\"([^\"]+)\"/>"))) j.parent = m[1];
    if (std::regex_search(body, m, std::regex("<child link=\"([^\"]+)\"/>"))) j.child = m[1];
    if (std::regex_search(body, m, std::regex("<origin xyz=\"([^\"]+)\" rpy=\"([^\"]+)\"/>"))) {
      const auto a = numbers(m[1]), b = numbers(m[2]);
      for (int k = 0; k < 3; ++k) j.xyz[k] = a[k], j.rpy[k] = b[k];
    }
    if (std::regex_search(body, m, std::regex("<axis xyz=\"([^\"]+)\"/>"))) {
      const auto a = numbers(m[1]);
      for (int k = 0; k < 3; ++k) j.axis[k] = a[k];
    }
    if (std::regex_search(body, m, std::regex("<mimic joint=\"([^\"]+)\" multiplier=\"([^\"]+)\""))) {
      j.mimic = m[1];
      j.multiplier = std::stod(m[2]);
    }
    out.push_back(j);
  }
  return out;
}

// The tool pose (mm) of the URDF chain base -> tool for named joint values (rad, m).
Transform<double> urdf_tool(const std::vector<UJoint>& joints, const std::map<std::string, double>& value) {
  std::map<std::string, const UJoint*> by_parent;
  for (const auto& j : joints) by_parent[j.parent] = &j;
  Transform<double> T = Transform<double>::identity();
  std::string link = "base";
  while (link != "tool") {
    const UJoint& j = *by_parent.at(link);
    T = T * make_transform(rpy_to_matrix(j.rpy[0], j.rpy[1], j.rpy[2]),
                           make_vec3(j.xyz[0] * 1000, j.xyz[1] * 1000, j.xyz[2] * 1000));
    const double v = j.mimic.empty() ? (value.count(j.name) ? value.at(j.name) : 0) : j.multiplier * value.at(j.mimic);
    const Vec3<double> axis = make_vec3(j.axis[0], j.axis[1], j.axis[2]);
    if (j.type == "revolute") {
      T = T * make_transform(axis.x != 0 ? rot_x(v) : rot_z(v), make_vec3(0.0, 0.0, 0.0));
    } else if (j.type == "prismatic") {
      T = T * make_transform(identity3<double>(), (v * 1000) * axis);
    }
    link = j.child;
  }
  return T;
}

std::string ident(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

}  // namespace

TEST(Urdf, EveryShippedRobotLoadsInUrdfdomAndMatchesTheDhChain) {
  int robots = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(ARTICULA_SOURCE_DIR) + "/robots")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "robot.schema.json") continue;
    const Robot r = load_robot_file(entry.path().string());
    const UrdfExport u = export_urdf(r);
    const std::string file = testing::TempDir() + "/" + entry.path().stem().string() + ".urdf";
    std::ofstream(file) << u.xml;
    // urdfdom's parser, as ROS tools use it.
    const int rc = std::system(("check_urdf " + file + " > /dev/null").c_str());
    EXPECT_EQ(rc, 0) << r.name << ": check_urdf rejected " << file;

    const std::vector<UJoint> joints = parse_joints(u.xml);
    std::mt19937 rng(3);
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<double> q(r.model.num_joints);
      std::map<std::string, double> values;
      for (int j = 0; j < r.model.num_joints; ++j) {
        q[j] = std::uniform_real_distribution<double>(r.model.joints[j].lo, r.model.joints[j].hi)(rng);
        values[ident(r.joint_names[j])] = r.model.joints[j].param == kParamD ? q[j] / 1000 : q[j];
      }
      HostFrames f;
      forward_kinematics(f, r.model, q.data());
      const Transform<double> T = urdf_tool(joints, values);
      ASSERT_LT(norm(T.p - f.T_base_tool.p), 1e-6) << r.name << " trial " << trial;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) ASSERT_NEAR(T.R.m[a][b], f.T_base_tool.R.m[a][b], 1e-9) << r.name;
    }
    ++robots;
  }
  EXPECT_GE(robots, 5);
}

TEST(Urdf, Mk2LevelRowIsTwoMimicJoints) {
  const Robot r = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  const UrdfExport u = export_urdf(r);
  EXPECT_NE(u.xml.find("<mimic joint=\"shoulder\" multiplier=\"-1\""), std::string::npos);
  EXPECT_NE(u.xml.find("<mimic joint=\"elbow\" multiplier=\"-1\""), std::string::npos);
  ASSERT_FALSE(u.notes.empty());
  EXPECT_NE(u.notes[0].find("2 mimic joints in series"), std::string::npos);
}
