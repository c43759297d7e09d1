#include "records_json.h"
#include "robot_view.h"

#include <algorithm>
#include <cctype>

#include <cmath>
#include <stdexcept>

namespace articula::host {
namespace {

nlohmann::json vec_json(const Vec3<double>& p) { return {p.x, p.y, p.z}; }

nlohmann::json gripper_json(int percent) { return percent < 0 ? nlohmann::json(nullptr) : nlohmann::json(percent); }

// The fields every record starts with: where it is, what it says, the reply.
nlohmann::json reply_json(int line, const std::string& text, Status reply) {
  nlohmann::json j = {{"line", line}, {"command", command_text(text)}, {"reply", reply == kOk ? "ok" : "error"},
                      {"code", int(reply)}};
  if (reply != kOk) j["error"] = status_text(reply);
  return j;
}

}  // namespace

std::string reply_text(Status s) { return s == kOk ? "ok" : "error:" + std::to_string(int(s)); }

nlohmann::json predict_record_json(const PredictRecord& r) {
  nlohmann::json j = reply_json(r.line, r.text, r.reply);
  if (r.stop) {  // '!': never answered
    j["reply"] = "none";
    j["stop"] = true;
  }
  if (r.cut) j["cut"] = true;
  if (r.stop_at >= 0) j["stop_at_tick"] = r.stop_at;
  if (!r.protocol.empty()) j["protocol"] = r.protocol;
  if (!r.note.empty()) j["note"] = r.note;
  j["steps"] = r.steps;
  nlohmann::json cmd = nlohmann::json::array();
  for (Millideg c : r.commanded) cmd.push_back(c / 1000.0);
  j["commanded_deg"] = cmd;
  j["actuator_deg"] = r.actuator_deg;
  j["joints"] = r.joints;
  j["joints_ideal"] = r.joints_ideal;
  j["tool_ideal_mm"] = vec_json(r.tool_ideal);
  j["tool_quantized_mm"] = vec_json(r.tool_quantized);
  j["error_mm"] = r.error_mm;
  j["gripper_percent"] = gripper_json(r.gripper_percent);
  if (r.has_target) {
    j["target_mm"] = vec_json(r.target);
    j["target_error_mm"] = r.target_error_mm;
  }
  if (!r.ik_status.empty()) j["ik_status"] = r.ik_status;
  if (r.line_error_mm >= 0) {  // T: its segments, and the tool's worst distance from the line
    j["line_error_mm"] = r.line_error_mm;
    nlohmann::json segs = nlohmann::json::array();
    for (const auto& s : r.segments)
      segs.push_back({{"delta_steps", s.delta_steps}, {"dominant_steps", s.dominant_steps}, {"cruise4", s.cruise4}});
    j["segments"] = segs;
  }
  if (!r.path.empty()) {
    nlohmann::json path = nlohmann::json::array();
    for (const Vec3<double>& v : r.path) path.push_back(vec_json(v));
    j["path_mm"] = path;
  }
  j["queued"] = r.queued;
  j["dominant_steps"] = r.dominant_steps;
  j["ticks"] = r.ticks;
  j["start_tick"] = r.start_tick;
  j["end_tick"] = r.end_tick;
  j["seconds"] = r.seconds();
  j["start_s"] = r.start_s();
  j["end_s"] = r.end_s();
  return j;
}

nlohmann::json prediction_json(const Robot& robot, const Program& program, const Prediction& p) {
  nlohmann::json j;
  j["robot"] = robot.name;
  j["robot_file"] = robot.source;
  j["program"] = program.source;
  j["format"] = program.format == Program::Format::kRoboSim ? "robosim" : "protocol";
  j["tick_hz"] = kStepTickHz;
  nlohmann::json s;
  for (int i = 0; i < ControllerSettings::kCount; ++i) s["$" + std::to_string(i)] = p.settings.value[size_t(i)];
  j["settings"] = s;
  j["motors"] = robot.motor_names;
  j["joints"] = robot.joint_names;
  j["records"] = nlohmann::json::array();
  for (const auto& r : p.records) j["records"].push_back(predict_record_json(r));
  j["summary"] = {{"commands", p.records.size()},
                  {"rejected", p.rejected},
                  {"worst_error_mm", p.worst_error_mm},
                  {"total_ticks", p.total_ticks},
                  {"first_step_tick", p.first_step_tick},
                  {"total_s", p.total_s()}};
  return j;
}

nlohmann::json run_record_json(const RunRecord& r) {
  nlohmann::json e = reply_json(r.line, r.text, r.reply);
  if (!r.note.empty()) e["note"] = r.note;
  e["joints"] = r.joints;
  nlohmann::json R = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) R.push_back({r.tool.R.m[i][0], r.tool.R.m[i][1], r.tool.R.m[i][2]});
  e["tool"] = {{"position", vec_json(r.tool.p)}, {"rpy", vec_json(r.rpy_deg)}, {"rotation", R}};
  e["gripper_percent"] = gripper_json(r.gripper_percent);
  if (r.has_target) {
    e["target_mm"] = vec_json(r.target);
    e["target_error_mm"] = r.target_error_mm;
    if (!r.ik_status.empty()) e["ik_status"] = r.ik_status;
  }
  if (!r.via_joints.empty()) {  // T: each segment's end (joint values) and how far along the line
    e["line_length_mm"] = r.line_length_mm;
    e["speed_mm_s"] = r.line_speed;
    nlohmann::json segs = nlohmann::json::array();
    for (size_t k = 0; k < r.via_joints.size(); ++k) segs.push_back({{"joints", r.via_joints[k]}, {"along_mm", r.via_mm[k]}});
    e["segments"] = segs;
  }
  return e;
}

nlohmann::json run_json(const Robot& robot, const Program& program, const std::vector<RunRecord>& records) {
  nlohmann::json j;
  j["robot"] = robot.name;
  j["robot_file"] = robot.source;
  j["program"] = program.source;
  j["format"] = program.format == Program::Format::kRoboSim ? "robosim" : "protocol";
  j["joints"] = robot.joint_names;
  j["records"] = nlohmann::json::array();
  int rejected = 0;
  for (const auto& r : records) {
    j["records"].push_back(run_record_json(r));
    rejected += r.reply != kOk;
  }
  j["summary"] = {{"commands", records.size()}, {"rejected", rejected}};
  return j;
}

nlohmann::json ik_result_json(const Robot& robot, const IkResult& res) {
  nlohmann::json q = nlohmann::json::array();
  for (size_t k = 0; k < res.q.size(); ++k) q.push_back(joint_from_model(robot, int(k), res.q[k]));
  const Vec3<double> rpy = matrix_to_rpy(res.tool.R);
  nlohmann::json j = {{"status", ik_status_name(res.status)},
                      {"solver", ik_method_name(res.method)},
                      {"q", q},
                      {"tool", vec_json(res.tool.p)},
                      {"tool_rpy", {rad_to_deg(rpy.x), rad_to_deg(rpy.y), rad_to_deg(rpy.z)}},
                      {"position_error_mm", res.position_error_mm},
                      {"orientation_error_deg", rad_to_deg(res.orientation_error_rad)},
                      {"iterations", res.iterations},
                      {"attempts", res.attempts}};
  if (!res.reached()) j["why"] = ik_miss_words(robot, res);
  if (!res.limited_joints.empty()) {
    nlohmann::json names = nlohmann::json::array();
    for (int k : res.limited_joints) names.push_back(robot.joint_names[size_t(k)]);
    j["limited_by"] = names;
  }
  if (!res.limited_motors.empty()) {
    nlohmann::json names = nlohmann::json::array();
    for (int k : res.limited_motors) names.push_back(robot.motor_names[size_t(k)]);
    j["limited_by_motors"] = names;
  }
  return j;
}

nlohmann::json quantize_record_json(const Robot& robot, const QuantizeRecord& q) {
  nlohmann::json j = {{"line", q.text}, {"reply", q.reply == kOk ? "ok" : "error"}, {"code", int(q.reply)}};
  if (q.reply != kOk) j["error"] = status_text(q.reply);
  if (q.moved()) {
    j["motor"] = robot.motor_names[size_t(q.motor)];
    j["commanded_deg"] = q.commanded_deg;
    j["steps"] = q.steps;
    j["reached_deg"] = q.reached_deg;
    j["error_deg"] = q.reached_deg - q.commanded_deg;
  }
  j["all_steps"] = q.all_steps;
  j["tool_ideal_mm"] = vec_json(q.tool_ideal);
  j["tool_quantized_mm"] = vec_json(q.tool_quantized);
  j["tool_error_mm"] = q.tool_error_mm;
  return j;
}

}  // namespace articula::host

namespace articula::host {

nlohmann::json program_json(const Robot& robot, const Program& program, const std::string& text) {
  using nlohmann::json;
  json statements = json::array();
  for (const Statement& st : program.statements) {
    json s = {{"line", st.line}};
    if (st.kind != Statement::Kind::kProtocol) {
      s["kind"] = std::string(1, robosim_letter(st.kind));
      s["values"] = st.values;
      statements.push_back(s);
      continue;
    }
    s["kind"] = "protocol";
    s["text"] = command_text(st.text);
    Command cmd{};
    json args = json::array();
    std::string letter;
    const int actuators = robot.has_motors ? robot.actuation.num_motors : robot.model.num_joints;
    if (parse_protocol_line(cmd, st.text, actuators) == kOk) {
      // The arguments as written: the command table says which are numbers held in
      // thousandths and which are whole (joint indices, bits, setting numbers).
      for (const CommandSpec& spec : kCommandTable) {
        if (spec.type != cmd.type) continue;
        letter = std::string(1, spec.word);
        std::string kinds;
        for (const char* k = spec.args; *k; ++k) {
          if (k[1] == '*') {
            kinds.append(static_cast<size_t>(actuators), *k);
            ++k;
          } else {
            kinds += *k == 's' ? std::string("jn") : std::string(1, *k);
          }
        }
        for (size_t i = 0; i < kinds.size() && i < cmd.argc; ++i)
          args.push_back(in_thousandths(kinds[i]) ? cmd.arg[i] / 1000.0 : double(cmd.arg[i]));
        break;
      }
    }
    s["command"] = letter;
    s["args"] = args;
    statements.push_back(s);
  }
  json comments = json::array();
  for (const Comment& c : program_comments(text))
    comments.push_back({{"line", c.line}, {"text", c.text}, {"whole_line", c.whole_line}});
  return {{"format", program.format == Program::Format::kRoboSim ? "robosim" : "protocol"},
          {"source", program.source},
          {"statements", statements},
          {"comments", comments}};
}

namespace {
nlohmann::json number_or_null(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

Vec3<double> vec3_of_json(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3) throw std::invalid_argument(what + " must be three numbers [x, y, z]");
  double v[3];
  for (int k = 0; k < 3; ++k) {
    if (!j[size_t(k)].is_number()) throw std::invalid_argument(what + " must be three numbers [x, y, z]");
    v[k] = j[size_t(k)].get<double>();
  }
  return make_vec3(v[0], v[1], v[2]);
}
}  // namespace

nlohmann::json plan_json(const Plan& p) {
  nlohmann::json cmds = nlohmann::json::array();
  for (const auto& c : p.commands) {
    const std::string word = c.text.empty() ? "" : std::string(1, char(std::toupper(static_cast<unsigned char>(c.text[0]))));
    const std::string kind = c.joint >= 0 ? "single-joint" : c.chain >= 0 ? "repeat-" + c.leg : word == "P" ? "target" : "";
    cmds.push_back({{"line", c.line},
                    {"text", c.text},
                    {"expect", c.expect},
                    {"timeout_s", c.timeout_s > 0 ? nlohmann::json(c.timeout_s) : nlohmann::json(nullptr)},
                    {"single_joint", c.joint >= 0 ? nlohmann::json::array({c.joint, c.thesis_angle}) : nlohmann::json(nullptr)},
                    {"repeat", c.chain >= 0 ? nlohmann::json::array({c.chain, c.leg}) : nlohmann::json(nullptr)},
                    {"kind", kind}});
  }
  return {{"name", p.name}, {"title", p.title}, {"notes", p.notes}, {"commands", cmds}};
}

nlohmann::json nano_config_json(const NanoConfig& c) {
  return {{"name", c.arm.name}, {"checksum", c.checksum}, {"lines", c.lines}, {"has_point", c.arm.has_point}};
}

nlohmann::json axis_errors_json(const AxisErrors& e) {
  nlohmann::json pct = nlohmann::json::array();
  for (double p : e.pct) pct.push_back(number_or_null(p));
  return {{"mm", {e.mm[0], e.mm[1], e.mm[2]}}, {"pct", pct}};
}

nlohmann::json table4_json(const std::vector<Table4Row>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const Table4Row& r : rows) {
    nlohmann::json axes = nlohmann::json::array();
    for (const Table4Cell& c : r.axis)
      axes.push_back({{"max_pct", number_or_null(c.max_pct)}, {"max_mm", c.max_mm}, {"avg_mm", c.avg_mm}});
    out.push_back({{"joint", r.joint}, {"poses", r.poses}, {"axes", axes}});
  }
  return out;
}

std::vector<JointPoint> joint_points_of_json(const nlohmann::json& points) {
  if (!points.is_array()) throw std::invalid_argument("the points must be a list");
  std::vector<JointPoint> out;
  for (size_t i = 0; i < points.size(); ++i) {
    const nlohmann::json& p = points[i];
    const std::string where = "point " + std::to_string(i);
    if (!p.is_object() || !p.contains("joint") || !p["joint"].is_number_integer())
      throw std::invalid_argument(where + " must be {joint, value, reference} with a whole joint number");
    out.push_back(JointPoint{p["joint"].get<int>(), vec3_of_json(p.value("value", nlohmann::json()), where + "'s value"),
                             vec3_of_json(p.value("reference", nlohmann::json()), where + "'s reference")});
  }
  return out;
}

nlohmann::json repeat_chains_json(const std::vector<RepeatChain>& chains) {
  auto line = [](int l) { return l < 0 ? nlohmann::json(nullptr) : nlohmann::json(l); };
  nlohmann::json out = nlohmann::json::array();
  for (const RepeatChain& c : chains)
    out.push_back({{"chain", c.chain}, {"moves", c.moves}, {"back_moves", c.back_moves}, {"line_before", line(c.line_before)},
                   {"line_out", line(c.line_out)}, {"line_back", line(c.line_back)}});
  return out;
}

std::vector<PlanStep> plan_steps_of_json(const nlohmann::json& commands) {
  if (!commands.is_array()) throw std::invalid_argument("the plan's commands must be a list");
  std::vector<PlanStep> out;
  for (size_t i = 0; i < commands.size(); ++i) {
    const nlohmann::json& c = commands[i];
    const std::string where = "command " + std::to_string(i);
    if (!c.is_object() || !c.contains("line") || !c["line"].is_number_integer())
      throw std::invalid_argument(where + " must be {line, repeat} with a whole line number");
    PlanStep s;
    s.line = c["line"].get<int>();
    const nlohmann::json r = c.value("repeat", nlohmann::json());
    if (!r.is_null()) {
      if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_string() ||
          (r[1] != "out" && r[1] != "back") || r[0].get<int>() < 0)
        throw std::invalid_argument(where + "'s repeat must be [chain, \"out\" or \"back\"]");
      s.chain = r[0].get<int>();
      s.back = r[1] == "back";
    }
    out.push_back(s);
  }
  return out;
}

nlohmann::json joint_verdicts_json(const std::vector<JointVerdict>& v) {
  nlohmann::json out = nlohmann::json::array();
  for (const JointVerdict& j : v)
    out.push_back({{"joint", j.joint}, {"measured", j.measured}, {"worst_mm", j.worst_mm}, {"quant_mm", j.quant_mm},
                   {"within", j.within}, {"text", j.text}});
  return out;
}

std::vector<VerdictPoint> verdict_points_of_json(const nlohmann::json& points) {
  if (!points.is_array()) throw std::invalid_argument("the points must be a list");
  std::vector<VerdictPoint> out;
  for (size_t i = 0; i < points.size(); ++i) {
    const nlohmann::json& p = points[i];
    const std::string where = "point " + std::to_string(i);
    if (!p.is_object() || !p.contains("joint") || !p["joint"].is_number_integer())
      throw std::invalid_argument(where + " must be {joint, ideal, quant, measured} with a whole joint number");
    VerdictPoint v;
    v.joint = p["joint"].get<int>();
    v.ideal = vec3_of_json(p.value("ideal", nlohmann::json()), where + "'s ideal");
    v.quant = vec3_of_json(p.value("quant", nlohmann::json()), where + "'s quant");
    const nlohmann::json m = p.value("measured", nlohmann::json());
    v.measured = !m.is_null();
    if (v.measured) v.m = vec3_of_json(m, where + "'s measured");
    out.push_back(v);
  }
  return out;
}

namespace {
// A CSV cell as JavaScript's String() writes a number (shortest round trip), "" for null, and
// text quoted when it holds a comma, a quote or a line break.
std::string csv_cell(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isnan(d)) return "";
    if (d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(static_cast<long long>(d));
    return v.dump();
  }
  const std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}
std::string csv_row(const std::vector<nlohmann::json>& cells) {
  std::string out;
  for (size_t i = 0; i < cells.size(); ++i) out += (i ? "," : "") + csv_cell(cells[i]);
  return out + "\n";
}
// Three cells of an [x, y, z] (null: three empty cells).
void xyz_cells(std::vector<nlohmann::json>& row, const nlohmann::json& v) {
  for (int k = 0; k < 3; ++k) row.push_back(v.is_array() && v.size() == 3 ? v[size_t(k)] : nlohmann::json());
}
const nlohmann::json& list_of(const nlohmann::json& e, const char* key) {
  static const nlohmann::json empty = nlohmann::json::array();
  const auto it = e.find(key);
  return it != e.end() && it->is_array() ? *it : empty;
}
}  // namespace

std::string experiment_csv(const nlohmann::json& e) {
  using nlohmann::json;
  if (!e.is_object()) throw std::invalid_argument("the experiment must be an object");
  const json& points = list_of(e, "points");
  const json& chains = list_of(e, "chains");
  const json& targets = list_of(e, "targets");
  const std::string plan = e.value("plan", "");
  std::string out = "# " + e.value("title", "") + "; robot " + e.value("robot", "") + "; " + e.value("when", "") + "\n";
  // every measurement, by the plan line it was taken after (a pose measured once counts once)
  out += "plan,plan_line,x_mm,y_mm,z_mm\n";
  std::vector<int> seen;
  auto measurement = [&](const json& line, const json& xyz) {
    if (!line.is_number() || !xyz.is_array() || xyz.size() != 3) return;
    const int n = line.get<int>();
    if (std::find(seen.begin(), seen.end(), n) != seen.end()) return;
    seen.push_back(n);
    out += csv_row({plan, n, xyz[0], xyz[1], xyz[2]});
  };
  for (const json& p : points) measurement(p.value("line", json()), p.value("measured", json()));
  for (const json& c : chains) {
    measurement(c.value("line_before", json()), c.value("start_measured", json()));
    measurement(c.value("line_out", json()), c.value("dest_measured", json()));
    measurement(c.value("line_back", json()), c.value("back_measured", json()));
  }
  for (const json& t : targets) measurement(t.value("line", json()), t.value("measured", json()));

  // the single-joint poses and their errors
  std::vector<VerdictPoint> vp;
  out += "\npose,joint,thesis_deg,line,command,ideal_x,ideal_y,ideal_z,model_x,model_y,model_z,measured_x,measured_y,"
         "measured_z,err_x_mm,err_y_mm,err_z_mm,err_x_pct,err_y_pct,err_z_pct,quant_err_mm\n";
  std::vector<JointPoint> quant_ideal, meas_quant, meas_ideal;
  for (size_t i = 0; i < points.size(); ++i) {
    const json& p = points[i];
    const std::string where = "points[" + std::to_string(i) + "]";
    const int joint = p.value("joint", 0);
    const Vec3<double> ideal = vec3_of_json(p.value("ideal", json()), where + ".ideal");
    const Vec3<double> quant = vec3_of_json(p.value("quant", json()), where + ".quant");
    const json measured = p.value("measured", json());
    std::vector<json> row = {json(i + 1), joint, p.value("angle", json()), p.value("line", json()), p.value("command", json())};
    xyz_cells(row, p.value("ideal", json()));
    xyz_cells(row, p.value("quant", json()));
    xyz_cells(row, measured);
    quant_ideal.push_back({joint, quant, ideal});
    if (!measured.is_null()) {
      const Vec3<double> m = vec3_of_json(measured, where + ".measured");
      meas_quant.push_back({joint, m, quant});
      meas_ideal.push_back({joint, m, ideal});
      const AxisErrors a = axis_errors(m, quant);
      for (double v : a.mm) row.push_back(v);
      for (double v : a.pct) row.push_back(number_or_null(v));
    } else {
      for (int k = 0; k < 6; ++k) row.push_back(json());
    }
    const AxisErrors q = axis_errors(quant, ideal);
    row.push_back(std::hypot(q.mm[0], q.mm[1], q.mm[2]));
    out += csv_row(row);
  }
  out += "\ntable,joint,axis,poses,max_pct,max_mm,avg_mm\n";
  const char* const axes[3] = {"x", "y", "z"};
  const std::pair<const char*, const std::vector<JointPoint>*> tables[] = {
      {"measured_vs_model", &meas_quant}, {"measured_vs_ideal", &meas_ideal}, {"model_vs_ideal", &quant_ideal}};
  for (const auto& [name, pts] : tables)
    for (const Table4Row& r : table4(*pts))
      for (int k = 0; k < 3; ++k)
        out += csv_row({name, r.joint, axes[k], r.poses, number_or_null(r.axis[k].max_pct), r.axis[k].max_mm, r.axis[k].avg_mm});
  if (!chains.empty()) {
    const std::vector<Table5Row> t5 = table5(chain_poses_of_json(chains));
    out += "\nchain,moves,back_moves,line_out,line_back,dest_error_mm,return_error_mm,steps_back,measured_dest_mm,"
           "measured_dest_ideal_mm,measured_return_mm,return_from_measured_start\n";
    for (size_t i = 0; i < chains.size() && i < t5.size(); ++i) {
      const json& c = chains[i];
      const Table5Row& r = t5[i];
      out += csv_row({c.value("chain", json()), c.value("moves", json()), c.value("back_moves", json()), c.value("line_out", json()),
                      c.value("line_back", json()), number_or_null(r.dest_error_mm), number_or_null(r.return_error_mm),
                      c.value("steps_back", json()), number_or_null(r.measured_dest_mm), number_or_null(r.measured_dest_ideal_mm),
                      number_or_null(r.measured_return_mm), r.return_from_measured_start});
    }
  }
  if (!targets.empty()) {
    const std::vector<TargetRow> tp = tool_points(target_poses_of_json(targets));
    out += "\ntarget_line,command,target_x,target_y,target_z,model_x,model_y,model_z,measured_x,measured_y,measured_z,"
           "model_from_target_mm,ideal_from_target_mm,measured_from_target_mm,measured_from_model_mm\n";
    for (size_t i = 0; i < targets.size() && i < tp.size(); ++i) {
      const json& t = targets[i];
      std::vector<json> row = {t.value("line", json()), t.value("command", json())};
      xyz_cells(row, t.value("target", json()));
      xyz_cells(row, t.value("quant", json()));
      xyz_cells(row, t.value("measured", json()));
      row.push_back(number_or_null(tp[i].model_from_target_mm));
      row.push_back(number_or_null(tp[i].ideal_from_target_mm));
      row.push_back(number_or_null(tp[i].measured_from_target_mm));
      row.push_back(number_or_null(tp[i].measured_from_model_mm));
      out += csv_row(row);
    }
  }
  return out;
}

nlohmann::json table5_json(const std::vector<Table5Row>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const Table5Row& r : rows)
    out.push_back({{"chain", r.chain},
                   {"moves", r.moves},
                   {"back_moves", r.back_moves},
                   {"dest_error_mm", number_or_null(r.dest_error_mm)},
                   {"return_error_mm", number_or_null(r.return_error_mm)},
                   {"measured_dest_mm", number_or_null(r.measured_dest_mm)},
                   {"measured_dest_ideal_mm", number_or_null(r.measured_dest_ideal_mm)},
                   {"measured_return_mm", number_or_null(r.measured_return_mm)},
                   {"return_from_measured_start", r.return_from_measured_start}});
  return out;
}

std::vector<ChainPoses> chain_poses_of_json(const nlohmann::json& chains) {
  if (!chains.is_array()) throw std::invalid_argument("the chains must be a list");
  std::vector<ChainPoses> out;
  for (size_t i = 0; i < chains.size(); ++i) {
    const nlohmann::json& c = chains[i];
    const std::string where = "chain " + std::to_string(i);
    const auto whole = [&](const char* key) {
      if (!c.is_object() || !c.contains(key) || !c[key].is_number_integer())
        throw std::invalid_argument(where + "'s " + key + " must be a whole number");
      return c[key].get<int>();
    };
    const auto optional = [&](const char* key, bool& has, Vec3<double>& v) {
      has = c.contains(key) && !c[key].is_null();
      if (has) v = vec3_of_json(c[key], where + "'s " + key);
    };
    ChainPoses p;
    p.chain = whole("chain");
    p.moves = whole("moves");
    p.back_moves = whole("back_moves");
    p.start = vec3_of_json(c.value("start", nlohmann::json()), where + "'s start");
    p.dest_quant = vec3_of_json(c.value("dest_quant", nlohmann::json()), where + "'s dest_quant");
    p.dest_ideal = vec3_of_json(c.value("dest_ideal", nlohmann::json()), where + "'s dest_ideal");
    optional("back_quant", p.has_back, p.back_quant);
    optional("start_measured", p.start_measured, p.start_m);
    optional("dest_measured", p.dest_measured, p.dest_m);
    optional("back_measured", p.back_measured, p.back_m);
    out.push_back(p);
  }
  return out;
}

nlohmann::json tool_points_json(const std::vector<TargetRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const TargetRow& r : rows)
    out.push_back({{"line", r.line},
                   {"model_from_target_mm", number_or_null(r.model_from_target_mm)},
                   {"ideal_from_target_mm", number_or_null(r.ideal_from_target_mm)},
                   {"measured_from_target_mm", number_or_null(r.measured_from_target_mm)},
                   {"measured_from_model_mm", number_or_null(r.measured_from_model_mm)}});
  return out;
}

std::vector<TargetPoses> target_poses_of_json(const nlohmann::json& points) {
  if (!points.is_array()) throw std::invalid_argument("the tool points must be a list");
  std::vector<TargetPoses> out;
  for (size_t i = 0; i < points.size(); ++i) {
    const nlohmann::json& p = points[i];
    const std::string where = "tool point " + std::to_string(i);
    if (!p.is_object() || !p.contains("line") || !p["line"].is_number_integer())
      throw std::invalid_argument(where + " must be {line, target, quant, ideal, measured} with a whole line number");
    TargetPoses t;
    t.line = p["line"].get<int>();
    t.target = vec3_of_json(p.value("target", nlohmann::json()), where + "'s target");
    t.quant = vec3_of_json(p.value("quant", nlohmann::json()), where + "'s quant");
    t.ideal = vec3_of_json(p.value("ideal", nlohmann::json()), where + "'s ideal");
    t.measured = p.contains("measured") && !p["measured"].is_null();
    if (t.measured) t.m = vec3_of_json(p["measured"], where + "'s measured");
    out.push_back(t);
  }
  return out;
}

}  // namespace articula::host
