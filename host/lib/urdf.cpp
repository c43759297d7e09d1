// host/lib/urdf.cpp - URDF export (urdf.h).
#include "urdf.h"

#include "xml_text.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace articula::host {
namespace {

constexpr double kMetresPerMm = 0.001;

// A number in the URDF written out: metres and radians to 12 significant digits, so a robot
// converted to URDF and back keeps its DH table to well under a micrometre (not a protocol
// number: URDF has its own units).
std::string xml_number(double v) {
  if (std::fabs(v) < 1e-15) v = 0;
  std::ostringstream o;
  o << std::setprecision(12) << v;
  return o.str();
}

// Free text inside an XML comment: escaped, and no "--" (which XML forbids there).
std::string comment(const std::string& s) {
  std::string out = xml_text(s);
  for (size_t at = out.find("--"); at != std::string::npos; at = out.find("--", at)) out.replace(at, 2, "- -");
  return out;
}

// A URDF name from free text: letters, digits and '_'.
std::string ident(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out.empty() ? "robot" : out;
}

std::string origin(const Transform<double>& T) {
  const Vec3<double> rpy = matrix_to_rpy(T.R);
  return "<origin xyz=\"" + xml_number(T.p.x * kMetresPerMm) + " " + xml_number(T.p.y * kMetresPerMm) + " " +
         xml_number(T.p.z * kMetresPerMm) + "\" rpy=\"" + xml_number(rpy.x) + " " + xml_number(rpy.y) + " " + xml_number(rpy.z) + "\"/>";
}

struct Writer {
  const Robot& robot;
  std::ostringstream xml;
  std::vector<std::string> notes;
  std::string parent = "base";
  Transform<double> pending = Transform<double>::identity();  // constant transform not yet emitted
  int dummy = 0;

  void link(const std::string& name) { xml << "  <link name=\"" << name << "\"/>\n"; }

  // A joint from `parent` to a new link `child`, at the pending transform.
  void joint(const std::string& name, const std::string& type, const std::string& child, const std::string& axis,
             const std::string& extra) {
    xml << "  <joint name=\"" << name << "\" type=\"" << type << "\">\n"
        << "    <parent link=\"" << parent << "\"/>\n    <child link=\"" << child << "\"/>\n    " << origin(pending)
        << "\n";
    if (!axis.empty()) xml << "    <axis xyz=\"" << axis << "\"/>\n";
    xml << extra << "  </joint>\n";
    pending = Transform<double>::identity();
    parent = child;
  }

  // One elementary transform of a row: constant, a joint variable, or linked.
  void element(int row, uint8_t param, double constant) {
    const HostModel& m = robot.model;
    const bool angle = param != kParamD;
    const char* axis = param == kParamAlpha ? "1 0 0" : "0 0 1";
    auto constant_transform = [&](double v) {
      if (param == kParamAlpha) return make_transform(rot_x(v), make_vec3(0.0, 0.0, 0.0));
      if (param == kParamTheta) return make_transform(rot_z(v), make_vec3(0.0, 0.0, 0.0));
      return make_transform(identity3<double>(), make_vec3(0.0, 0.0, v));
    };
    for (int j = 0; j < m.num_joints; ++j) {
      if (m.joints[j].row != row || m.joints[j].param != param) continue;
      const double scale = angle ? 1.0 : kMetresPerMm;
      std::ostringstream limit;
      limit << "    <limit lower=\"" << xml_number(m.joints[j].lo * scale) << "\" upper=\"" << xml_number(m.joints[j].hi * scale)
            << "\" effort=\"10\" velocity=\"1\"/>\n";
      const std::string name = ident(robot.joint_names[j]);
      link(name + "_link");
      joint(name, angle ? "revolute" : "prismatic", name + "_link", axis, limit.str());
      return;
    }
    for (int k = 0; k < m.num_linked; ++k) {
      const auto& l = m.linked[k];
      if (l.row != row || l.param != param) continue;
      // value = offset + sum gain_j q_j: the offset as a constant, then one mimic a term.
      pending = pending * constant_transform(l.offset);
      int terms = 0;
      for (int j = 0; j < m.num_joints; ++j) {
        if (l.gain[j] == 0) continue;
        // mimic: value = multiplier * q_j (+ offset), in the joints' own units (rad, m).
        const bool joint_angle = m.joints[j].param != kParamD;
        double mult = l.gain[j];
        if (angle && !joint_angle) mult /= kMetresPerMm;  // rad per mm -> rad per m
        if (!angle && joint_angle) mult *= kMetresPerMm;  // mm per rad -> m per rad
        const std::string name = "row" + std::to_string(row + 1) + "_linked_" + std::to_string(terms++) + "_" +
                                 ident(robot.joint_names[j]);
        // A mimic joint still needs limits; they are wide enough never to bind.
        const std::string extra = "    <limit lower=\"-100\" upper=\"100\" effort=\"10\" velocity=\"1\"/>\n"
                                  "    <mimic joint=\"" + ident(robot.joint_names[j]) + "\" multiplier=\"" + xml_number(mult) +
                                  "\" offset=\"0\"/>\n";
        link(name + "_link");
        joint(name, angle ? "revolute" : "prismatic", name + "_link", axis, extra);
      }
      if (terms > 1)
        notes.push_back("row " + std::to_string(row + 1) + ": a linked parameter of " + std::to_string(terms) +
                        " joints is " + std::to_string(terms) + " mimic joints in series about one axis");
      return;
    }
    pending = pending * constant_transform(constant);
  }

  void visuals(int frame) {
    for (const LinkGeometry& lg : robot.links) {
      if (lg.frame != frame) continue;
      for (const Shape& s : lg.shapes) {
        std::ostringstream g;
        const double k = kMetresPerMm;
        switch (s.type) {
          case Shape::Type::kBox:
            g << "<box size=\"" << xml_number(s.size[0] * k) << " " << xml_number(s.size[1] * k) << " " << xml_number(s.size[2] * k) << "\"/>";
            break;
          case Shape::Type::kCylinder:
          case Shape::Type::kCapsule:
            g << "<cylinder radius=\"" << xml_number(s.size[0] * k) << "\" length=\"" << xml_number(s.size[1] * k) << "\"/>";
            break;
          case Shape::Type::kSphere: g << "<sphere radius=\"" << xml_number(s.size[0] * k) << "\"/>"; break;
          case Shape::Type::kMesh:
            g << "<mesh filename=\"" << xml_text(s.mesh) << "\" scale=\"0.001 0.001 0.001\"/>";
            break;
        }
        xml << "    <visual>\n      " << origin(s.T_frame_shape) << "\n      <geometry>" << g.str()
            << "</geometry>\n    </visual>\n";
      }
    }
  }

  void frame_link(int frame) {
    const std::string name = "frame_" + std::to_string(frame);
    xml << "  <link name=\"" << name << "\">\n";
    visuals(frame);
    xml << "  </link>\n";
  }
};

}  // namespace

UrdfExport export_urdf(const Robot& robot) {
  Writer w{robot, {}, {}, "base", Transform<double>::identity(), 0};
  const HostModel& m = robot.model;
  w.xml << "<?xml version=\"1.0\"?>\n<!-- " << comment(robot.name) << ", exported by articula export-urdf from "
        << comment(robot.source) << ". Metres and radians. -->\n<robot name=\"" << ident(robot.name) << "\">\n";
  w.xml << "  <link name=\"base\">\n";
  w.visuals(0);
  w.xml << "  </link>\n";
  for (int i = 0; i < m.num_rows; ++i) {
    const DhRow<double>& r = m.rows[i];
    w.element(i, kParamAlpha, r.alpha);
    w.pending = w.pending * make_transform(identity3<double>(), make_vec3(r.a, 0.0, 0.0));
    w.element(i, kParamTheta, r.theta);
    w.element(i, kParamD, r.d);
    w.frame_link(i + 1);
    w.joint("frame_" + std::to_string(i + 1) + "_fixed", "fixed", "frame_" + std::to_string(i + 1), "", "");
  }
  w.pending = m.T_last_tool;
  w.link("tool");
  w.joint("tool_fixed", "fixed", "tool", "", "");
  w.xml << "</robot>\n";
  if (robot.has_motors)
    w.notes.push_back("motors, gear ratios and the coupling have no URDF equivalent; limits are the DH joints'");
  return {w.xml.str(), w.notes};
}

}  // namespace articula::host
