// host/lib/experiment.cpp - see experiment.h.
#include "experiment.h"

#include <limits>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace articula::host {

namespace {

std::string mm_text(const Vec3<double>& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f) mm", v.x, v.y, v.z);
  return buf;
}

}  // namespace

AxisErrors axis_errors(const Vec3<double>& value, const Vec3<double>& reference) {
  AxisErrors e;
  for (int k = 0; k < 3; ++k) {
    const double ref = reference[k];
    e.mm[k] = std::fabs(value[k] - ref);
    e.pct[k] = std::fabs(ref) >= kPctMinMm ? e.mm[k] / std::fabs(ref) * 100.0 : std::nan("");
  }
  return e;
}

std::vector<Table4Row> table4(const std::vector<JointPoint>& points) {
  std::map<int, Table4Row> rows;
  std::map<int, double[3]> sums;
  for (const JointPoint& p : points) {
    Table4Row& r = rows[p.joint];
    if (r.poses == 0) {
      r.joint = p.joint;
      for (Table4Cell& c : r.axis) c.max_pct = std::nan("");
    }
    ++r.poses;
    const AxisErrors e = axis_errors(p.value, p.reference);
    for (int k = 0; k < 3; ++k) {
      Table4Cell& c = r.axis[k];
      c.max_mm = std::max(c.max_mm, e.mm[k]);
      if (!std::isnan(e.pct[k]) && (std::isnan(c.max_pct) || e.pct[k] > c.max_pct)) c.max_pct = e.pct[k];
      sums[p.joint][k] += e.mm[k];
    }
  }
  std::vector<Table4Row> out;
  for (auto& [joint, r] : rows) {
    for (int k = 0; k < 3; ++k) r.axis[k].avg_mm = sums[joint][k] / r.poses;
    out.push_back(r);
  }
  return out;
}

double distance_mm(const Vec3<double>& a, const Vec3<double>& b) { return norm(a - b); }

std::string measurement_question(const Vec3<double>& measured, const Vec3<double>& predicted, double reach_mm,
                                 double far_mm) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(measured[k]))
      return std::string(names[k]) + " is not a number: type the three coordinates in mm, digits like 235 or -12.5";
  const double d = distance_mm(measured, predicted);
  if (d > far_mm && distance_mm(10.0 * measured, predicted) < 0.2 * d)
    return mm_text(measured) + " looks like centimetres: the tool should be near " + mm_text(predicted) +
           ". Type millimetres (10 times the centimetres)";
  if (d > reach_mm)
    return mm_text(measured) + " is farther from where the tool should be, " + mm_text(predicted) +
           ", than the arm reaches: check the numbers and the axes (x forward, y left, z up, from the base)";
  if (d > far_mm) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.0f mm", d);
    return mm_text(measured) + " is " + buf + " from where the prediction puts the tool, " + mm_text(predicted) +
           ": is it right?";
  }
  return "";
}

std::vector<Table5Row> table5(const std::vector<ChainPoses>& chains) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  std::vector<Table5Row> out;
  for (const ChainPoses& c : chains) {
    Table5Row r;
    r.chain = c.chain;
    r.moves = c.moves;
    r.back_moves = c.back_moves;
    r.dest_error_mm = distance_mm(c.dest_quant, c.dest_ideal);
    r.return_error_mm = c.has_back ? distance_mm(c.back_quant, c.start) : none;
    r.measured_dest_mm = c.dest_measured ? distance_mm(c.dest_m, c.dest_quant) : none;
    r.measured_dest_ideal_mm = c.dest_measured ? distance_mm(c.dest_m, c.dest_ideal) : none;
    r.return_from_measured_start = c.start_measured;
    r.measured_return_mm = c.has_back && c.back_measured ? distance_mm(c.back_m, c.start_measured ? c.start_m : c.start) : none;
    out.push_back(r);
  }
  return out;
}

std::vector<TargetRow> tool_points(const std::vector<TargetPoses>& points) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  std::vector<TargetRow> out;
  for (const TargetPoses& p : points) {
    TargetRow r;
    r.line = p.line;
    r.model_from_target_mm = distance_mm(p.quant, p.target);
    r.ideal_from_target_mm = distance_mm(p.ideal, p.target);
    r.measured_from_target_mm = p.measured ? distance_mm(p.m, p.target) : none;
    r.measured_from_model_mm = p.measured ? distance_mm(p.m, p.quant) : none;
    out.push_back(r);
  }
  return out;
}

std::vector<RepeatChain> repeat_chains(const std::vector<PlanStep>& steps) {
  std::map<int, RepeatChain> chains;
  for (size_t i = 0; i < steps.size(); ++i) {
    const PlanStep& s = steps[i];
    if (s.chain < 0) continue;
    auto it = chains.find(s.chain);
    if (it == chains.end()) {
      RepeatChain c;
      c.chain = s.chain;
      c.line_before = i > 0 ? steps[i - 1].line : -1;
      it = chains.emplace(s.chain, c).first;
    }
    RepeatChain& c = it->second;
    if (s.back) {
      ++c.back_moves;
      c.line_back = s.line;
    } else {
      ++c.moves;
      c.line_out = s.line;
    }
  }
  std::vector<RepeatChain> out;
  for (const auto& [n, c] : chains)
    if (c.moves > 0) out.push_back(c);
  return out;
}

std::vector<JointVerdict> joint_verdicts(const std::vector<VerdictPoint>& points) {
  std::vector<JointPoint> measured, quant;
  for (const VerdictPoint& p : points) {
    quant.push_back({p.joint, p.quant, p.ideal});
    if (p.measured) measured.push_back({p.joint, p.m, p.quant});
  }
  const std::vector<Table4Row> m = table4(measured), q = table4(quant);
  auto worst = [](const Table4Row& r) { return std::max({r.axis[0].max_mm, r.axis[1].max_mm, r.axis[2].max_mm}); };
  auto mm2 = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return std::string(buf);
  };
  std::vector<JointVerdict> out;
  for (const Table4Row& qr : q) {
    JointVerdict v;
    v.joint = qr.joint;
    v.quant_mm = worst(qr);
    const auto mr = std::find_if(m.begin(), m.end(), [&](const Table4Row& r) { return r.joint == qr.joint; });
    v.measured = mr != m.end();
    if (!v.measured) {
      v.text = "not measured; whole steps alone leave up to " + mm2(v.quant_mm) + " mm.";
    } else {
      v.worst_mm = worst(*mr);
      v.within = v.worst_mm <= kVerdictMm;
      v.text = v.within ? "as simulated: the arm is within " + mm2(v.worst_mm) + " mm of the model on every axis (whole steps alone: " +
                              mm2(v.quant_mm) + " mm)."
                        : "differs from the model by up to " + mm2(v.worst_mm) + " mm (whole steps alone: " + mm2(v.quant_mm) +
                              " mm): check this joint's zero, gear and link lengths in the robot file, and the arm's play.";
    }
    out.push_back(v);
  }
  return out;
}

}  // namespace articula::host
