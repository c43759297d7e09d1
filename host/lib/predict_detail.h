// host/lib/predict_detail.h - what the firmware's run of a program (predict_run.cpp) describes
// a record with (predict.cpp): its state's angles, joints and tool positions, the tool along
// its moves, the notes on a refusal. Descriptions only: no firmware rule lives here.
#ifndef ARTICULA_HOST_PREDICT_DETAIL_H
#define ARTICULA_HOST_PREDICT_DETAIL_H

#include <string>
#include <vector>

#include "predict.h"

namespace articula::host {

// A record's state fields for the controller's steps and commanded angles, `offset` the
// physical step less the counted one (only Z makes them differ): the angles the steps give,
// the joint values, the ideal and the quantized tool, its error and, for a target, the
// distance to it.
void describe_state(const Robot& robot, PredictRecord& r, const int32_t* steps, const Millideg* commanded,
                    const int32_t* offset);
// error:9's note: which motor a target takes beyond its range, and the range, in degrees.
std::string limit_note(const Robot& robot, const int32_t* target_millideg);
// The tool (mm) after every dominant step of `moves` from `steps` + `offset`, each move's
// steps spread as the arm spreads them (LineStepper); empty beyond 8 motors.
std::vector<Vec3<double>> tool_path(const Robot& robot, const int32_t* steps, const int32_t* offset,
                                    const std::vector<const std::vector<int32_t>*>& moves);
// The worst distance (mm) of the points from the segment a-b.
double distance_from_segment(const std::vector<Vec3<double>>& points, const Vec3<double>& a, const Vec3<double>& b);

}  // namespace articula::host

#endif  // ARTICULA_HOST_PREDICT_DETAIL_H
