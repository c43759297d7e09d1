// Tests host/lib/experiment.h: the thesis's Table 4 from appendix K's own errors, the per
// cent rule, and the questions a typed measurement raises.
#include <gtest/gtest.h>

#include <cmath>

#include "experiment.h"

using namespace articula;
using namespace articula::host;

namespace {

Vec3<double> v3(double x, double y, double z) { return make_vec3(x, y, z); }

// Appendix K, "Changing Joint 0": per pose the absolute errors (cm) and the errors in per
// cent of the coordinate, per axis. A reference of err / pct and a value err beyond it give
// back those errors.
struct KRow {
  double err_cm[3], pct[3];
};
const KRow kJoint0[] = {
    {{0.0095, 0.0479, 0.04975}, {0.678571429, 0.303164557, 6.21875}},
    {{0.017874615, 0.0479, 0.04835335}, {1.44150121, 0.303164557, 4.6945}},
    {{0.005534722, 0.0479, 0.027489348}, {0.683299074, 0.303164557, 1.977650899}},
    {{0.26575, 0.1525, 0.04975}, {3.321875, 1.837349398, 6.21875}},
    {{0.38375, 0.07365, 0.20175}, {21.31944444, 0.466139241, 20.175}},
    {{0.0095, 0.0479, 0.04975}, {-0.678571429, 0.303164557, 6.21875}},
};

JointPoint point_of(int joint, const KRow& k) {
  double ref[3], val[3];
  for (int a = 0; a < 3; ++a) {
    const double err_mm = k.err_cm[a] * 10;
    ref[a] = err_mm / (k.pct[a] / 100);  // the sign of the per cent: the coordinate's
    val[a] = ref[a] + err_mm;
  }
  return JointPoint{joint, make_vec3(val[0], val[1], val[2]), make_vec3(ref[0], ref[1], ref[2])};
}

}  // namespace

TEST(Experiment, Table4FromAppendixKsJoint0) {
  std::vector<JointPoint> points;
  for (const KRow& k : kJoint0) points.push_back(point_of(0, k));
  const std::vector<Table4Row> t = table4(points);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].joint, 0);
  EXPECT_EQ(t[0].poses, 6);
  // The thesis's Table 4, joint 0: max % 21.3, 1.84, 20.2; max cm 0.38, 0.15, 0.2; average cm
  // 0.11, 0.07, 0.07 (rounded there; appendix K's figures here).
  const double max_pct[3] = {21.31944444, 1.837349398, 20.175};
  const double max_mm[3] = {3.8375, 1.525, 2.0175};
  const double avg_cm[3] = {0.115318223, 0.069625, 0.07114045};  // appendix K's "avg" row
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(t[0].axis[a].max_pct, max_pct[a], 1e-6) << a;
    EXPECT_NEAR(t[0].axis[a].max_mm, max_mm[a], 1e-9) << a;
    EXPECT_NEAR(t[0].axis[a].avg_mm, avg_cm[a] * 10, 1e-6) << a;
  }
}

TEST(Experiment, PerCentNeedsACoordinateAwayFromZero) {
  const AxisErrors e = axis_errors(make_vec3(10.5, 0.4, -201.0), make_vec3(10.0, 0.5, -200.0));
  EXPECT_NEAR(e.mm[0], 0.5, 1e-12);
  EXPECT_NEAR(e.pct[0], 5.0, 1e-12);
  EXPECT_NEAR(e.mm[1], 0.1, 1e-12);
  EXPECT_TRUE(std::isnan(e.pct[1])) << "0.5 mm from 0: no per cent";
  EXPECT_NEAR(e.pct[2], 0.5, 1e-12);
  // A joint whose every y is near 0 has no y per cent at all in Table 4.
  const std::vector<Table4Row> t = table4({JointPoint{2, v3(1, 0.2, 1), v3(2, 0.1, 2)}});
  EXPECT_TRUE(std::isnan(t[0].axis[1].max_pct));
  EXPECT_NEAR(t[0].axis[1].max_mm, 0.1, 1e-12);
}

TEST(Experiment, JointsComeInOrder) {
  const std::vector<Table4Row> t = table4({JointPoint{2, v3(0, 0, 0), v3(0, 0, 0)},
                                           JointPoint{0, v3(1, 1, 1), v3(0, 0, 0)},
                                           JointPoint{2, v3(3, 0, 0), v3(0, 0, 0)}});
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].joint, 0);
  EXPECT_EQ(t[1].joint, 2);
  EXPECT_EQ(t[1].poses, 2);
  EXPECT_NEAR(t[1].axis[0].avg_mm, 1.5, 1e-12);
  EXPECT_NEAR(distance_mm(v3(0, 3, 0), v3(4, 0, 0)), 5, 1e-12);
}

TEST(Experiment, ATypedMeasurementIsQuestioned) {
  const Vec3<double> predicted = make_vec3(235.0, 0.0, 213.0);
  EXPECT_EQ(measurement_question(make_vec3(236.0, -1.5, 212.0), predicted, 370), "");
  EXPECT_NE(measurement_question(v3(std::nan(""), 0, 213), predicted, 370).find("x is not a number"),
            std::string::npos);
  EXPECT_NE(measurement_question(v3(235, INFINITY, 213), predicted, 370).find("y is not a number"),
            std::string::npos);
  // 23.5 cm, 0, 21.3 cm: typed in cm
  EXPECT_NE(measurement_question(v3(23.5, 0, 21.3), predicted, 370).find("looks like centimetres"),
            std::string::npos);
  // far beyond what the arm reaches
  EXPECT_NE(measurement_question(v3(2350, 0, 213), predicted, 370).find("than the arm reaches"),
            std::string::npos);
  // within reach, but far from the prediction: asked, not refused
  const std::string q = measurement_question(v3(235, 80, 213), predicted, 370);
  EXPECT_NE(q.find("80 mm from where the prediction puts the tool"), std::string::npos) << q;
}

TEST(Experiment, Table5MeasuresTheReturnFromTheMeasuredStartWhenThereIsOne) {
  ChainPoses c;
  c.chain = 3;
  c.moves = c.back_moves = 2;
  c.start = v3(300, 0, 150);
  c.dest_quant = v3(253, 64, 150);
  c.dest_ideal = v3(250, 60, 150);  // 5 mm of whole steps
  c.has_back = true;
  c.back_quant = v3(300, 0, 150);  // back exactly
  std::vector<Table5Row> t = table5({c});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].chain, 3);
  EXPECT_DOUBLE_EQ(t[0].dest_error_mm, 5.0);
  EXPECT_DOUBLE_EQ(t[0].return_error_mm, 0.0);
  EXPECT_TRUE(std::isnan(t[0].measured_dest_mm) && std::isnan(t[0].measured_return_mm));
  c.dest_measured = c.back_measured = true;
  c.dest_m = v3(253, 64, 153);     // 3 mm from the model, sqrt(9 + 16 + 9) from the exact angles
  c.back_m = v3(300, 4, 153);      // 5 mm from the model's start
  t = table5({c});
  EXPECT_DOUBLE_EQ(t[0].measured_dest_mm, 3.0);
  EXPECT_DOUBLE_EQ(t[0].measured_dest_ideal_mm, std::sqrt(34.0));
  EXPECT_DOUBLE_EQ(t[0].measured_return_mm, 5.0);
  EXPECT_FALSE(t[0].return_from_measured_start);
  c.start_measured = true;
  c.start_m = v3(300, 4, 150);     // measured where it came back to, but 3 mm higher
  t = table5({c});
  EXPECT_DOUBLE_EQ(t[0].measured_return_mm, 3.0);
  EXPECT_TRUE(t[0].return_from_measured_start);
  c.has_back = false;
  EXPECT_TRUE(std::isnan(table5({c})[0].return_error_mm));
}

TEST(Experiment, ToolPointsMeasureFromTheTargetAndFromTheModel) {
  TargetPoses p;
  p.line = 14;
  p.target = v3(171, 120, 185);
  p.quant = v3(171, 123, 189);  // 5 mm away: whole steps
  p.ideal = v3(171, 120, 185);
  std::vector<TargetRow> t = tool_points({p});
  EXPECT_EQ(t[0].line, 14);
  EXPECT_DOUBLE_EQ(t[0].model_from_target_mm, 5.0);
  EXPECT_DOUBLE_EQ(t[0].ideal_from_target_mm, 0.0);
  EXPECT_TRUE(std::isnan(t[0].measured_from_target_mm) && std::isnan(t[0].measured_from_model_mm));
  p.measured = true;
  p.m = v3(171, 120, 187);
  t = tool_points({p});
  EXPECT_DOUBLE_EQ(t[0].measured_from_target_mm, 2.0);
  EXPECT_DOUBLE_EQ(t[0].measured_from_model_mm, std::sqrt(9.0 + 4.0));
}
