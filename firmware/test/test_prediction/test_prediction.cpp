// The firmware on its virtual clock (firmware/sitl/) against the host's prediction
// (host/lib/predict.h, `articula predict`): every shipped protocol program, plan and stream,
// sent as `--sender rest` and `--sender stream` send them, gets the predicted reply on every
// line, makes the predicted steps, ends every move on the predicted tick exactly (the SITL
// machine's main loop takes no time, as the prediction assumes), and comes to rest on the
// predicted steps. Random programs too, with refused lines, '!'s of their own and timed ones
// (--stop-at): where the arm comes to rest after each. The figures are printed;
// ARTICULA_DUMP=1 prints every line's ticks on both sides. This is the oracle for the prediction to become
// the firmware itself (issue 39): it runs in milliseconds, where the emulated Nanos take
// seconds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "predict.h"
#include "queue.h"
#include "program.h"
#include "robot_file.h"

using namespace articula;

namespace {

const host::Robot& robot_file() {
  static const host::Robot r = host::load_robot_file(sim::robot_file());
  return r;
}

struct Case {
  const char* file;
  host::SenderModel::Kind sender;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.file << " --sender " << host::sender_name(c.sender);
}

std::string name_of(const ::testing::TestParamInfo<Case>& info) {
  std::string n = info.param.file;  // "hil/plans/x.arm": hil_plans_x
  n = n.substr(0, n.rfind('.'));
  for (char& c : n)
    if (!isalnum(static_cast<unsigned char>(c))) c = '_';
  return n + (info.param.sender == host::SenderModel::kRest ? "_rest" : "_stream");
}

class FirmwareMatchesThePrediction : public ::testing::TestWithParam<Case> {};

// A shipped program predicted and sent to a fresh machine as the case's sender sends it.
struct ShippedRun {
  host::SenderModel sender;
  host::Prediction p;
  std::vector<std::string> lines;
  uint64_t t0 = 0;            // the machine's tick when the first line went
  size_t coil_writes0 = 0;    // where the run starts in the coil log
  size_t actions0 = 0;        //   and in the action log
  std::vector<sitl::Exchange> got;
};

ShippedRun run_shipped(const Case& c) {
  const host::Robot& robot = robot_file();
  ShippedRun run;
  run.sender.kind = c.sender;
  run.p = host::predict_program(robot, host::load_program(std::string(ARTICULA_SOURCE_DIR) + "/" + c.file, robot), {},
                                run.sender);
  for (const host::PredictRecord& r : run.p.records)
    run.lines.push_back(r.stop ? "!" : r.protocol.empty() ? r.text : r.protocol);
  sim::boot();
  sim::status();  // the W:14 of a blank EEPROM, taken
  sim::take_lines();
  run.t0 = sitl::hw().now;
  run.coil_writes0 = sitl::hw().coil_log.size();
  run.actions0 = sitl::hw().actions.size();
  run.got = sitl::run_lines(run.lines, c.sender == host::SenderModel::kRest ? sitl::kAtRest : sitl::kStreamed);
  return run;
}

TEST_P(FirmwareMatchesThePrediction, RepliesStepsAndMoveEnds) {
  const Case c = GetParam();
  const ShippedRun run = run_shipped(c);
  const host::Prediction& p = run.p;
  const std::vector<std::string>& lines = run.lines;
  const uint64_t t0 = run.t0;
  const size_t coil_writes0 = run.coil_writes0;
  const std::vector<sitl::Exchange>& got = run.got;
  ASSERT_EQ(got.size(), p.records.size());

  // Every deadline at which a motor stepped, from the coil writes (decoded by the SITL HAL).
  std::vector<uint64_t> steps;
  for (size_t i = coil_writes0; i < sitl::hw().coil_log.size(); ++i) {
    const sitl::CoilWrite& w = sitl::hw().coil_log[i];
    if (w.step != 0 && (steps.empty() || steps.back() != w.tick - t0)) steps.push_back(w.tick - t0);
  }

  uint64_t predicted_steps = 0, worst = 0;
  size_t k = 0, moves = 0;
  for (size_t i = 0; i < p.records.size(); ++i) {
    const host::PredictRecord& r = p.records[i];
    const std::string want = r.stop ? "" : r.reply == kOk ? "ok" : "error:" + std::to_string(int(r.reply));
    EXPECT_EQ(got[i].reply, want) << c.file << " line " << r.line << ": " << lines[i];
    if (r.dominant_steps == 0) continue;
    ++moves;
    predicted_steps += r.dominant_steps;
    k += r.dominant_steps;
    if (k > steps.size()) break;
    const uint64_t end = steps[k - 1];
    worst = std::max<uint64_t>(worst, end > r.end_tick ? end - r.end_tick : r.end_tick - end);
    EXPECT_EQ(end, r.end_tick) << c.file << " line " << r.line << " (" << lines[i] << "): its last step";
  }
  EXPECT_EQ(steps.size(), predicted_steps) << c.file << ": the firmware made other steps than predicted";
  const host::PredictRecord& last = p.records.back();
  for (size_t m = 0; m < last.steps.size() && m < size_t(robot::kJoints); ++m)
    EXPECT_EQ(sitl::hw().position[m], last.steps[m]) << c.file << ": motor " << m << " at rest";
  EXPECT_EQ(sim::hal_errors(), "");
  std::printf("  %s, %s: %zu lines, %zu moves, %zu steps; last step at %.6f s (predicted %.6f s); worst move end %llu ticks\n",
              c.file, host::sender_name(c.sender), lines.size(), moves, steps.size(),
              steps.empty() ? 0.0 : double(steps.back()) / 2e6, double(p.total_ticks) / 2e6,
              static_cast<unsigned long long>(worst));
}

// When each queued action begins and ends, read from the firmware itself: the actions it took
// off its queue (hal::action_began) and when its step timer stopped (sitl::hw().actions, from
// `from`), against the prediction. Every record that queued something and was not cut by a
// '!': its first action began at its predicted start, of its kind, and its last one (a T's
// last segment) ended at its predicted end, the log's next entry. The times the host's
// prediction is to read from the running firmware (issue 39). Returns the records checked and
// the actions they account for.
std::pair<size_t, size_t> check_action_times(const host::Prediction& p, size_t from, uint64_t t0, const std::string& what) {
  const std::vector<sitl::ActionEvent> log(sitl::hw().actions.begin() + long(from), sitl::hw().actions.end());
  size_t j = 0, records = 0, actions = 0;
  for (const host::PredictRecord& r : p.records) {
    if (!r.queued || r.cut) continue;
    const uint8_t kind = r.action == host::PredictRecord::Action::kMove   ? uint8_t(queue::kMove)
                         : r.action == host::PredictRecord::Action::kHome ? uint8_t(queue::kHome)
                                                                          : uint8_t(queue::kDwell);  // or kGripper
    auto is = [&](const sitl::ActionEvent& e) {
      return e.kind == kind || (kind == queue::kDwell && e.kind == queue::kGripper);
    };
    while (j < log.size() && (log[j].kind == sitl::kTimerStopped || log[j].tick - t0 < r.start_tick)) ++j;
    if (j == log.size() || log[j].tick - t0 != r.start_tick || !is(log[j])) {
      ADD_FAILURE() << what << " line " << r.line << " (" << r.text << "): no action of its kind began at its start, "
                    << r.start_tick << (j < log.size() ? ", the next at " + std::to_string(log[j].tick - t0) : "");
      continue;
    }
    for (size_t n = r.segments.empty() ? 1 : r.segments.size(); n > 1; --n) {  // a T's further segments
      ++j;
      while (j < log.size() && log[j].kind == sitl::kTimerStopped) ++j;
    }
    if (j + 1 >= log.size()) {
      ADD_FAILURE() << what << " line " << r.line << ": the log ends inside its action";
      break;
    }
    EXPECT_EQ(log[j + 1].tick - t0, r.end_tick) << what << " line " << r.line << " (" << r.text << "): its end";
    ++j;
    ++records;
    actions += r.segments.empty() ? 1 : r.segments.size();
  }
  return {records, actions};
}

// Every time host::predict_program() gives, read here from a run of the firmware of its own:
// the records' starts and ends (check_action_times), when each line is in, the lines that
// queue nothing, the end of the program and the first step.
TEST_P(FirmwareMatchesThePrediction, EveryTimeOfTheScheduleReadFromTheFirmware) {
  const Case c = GetParam();
  const ShippedRun run = run_shipped(c);
  const host::Prediction& p = run.p;
  const uint64_t t0 = run.t0;
  const size_t from = run.actions0;
  const std::vector<sitl::Exchange>& got = run.got;
  ASSERT_EQ(got.size(), p.records.size());
  const std::pair<size_t, size_t> checked = check_action_times(p, from, t0, c.file);
  size_t begun = 0;
  uint64_t rest = 0;  // the last time the step timer stopped
  for (size_t i = from; i < sitl::hw().actions.size(); ++i) {
    begun += sitl::hw().actions[i].kind != sitl::kTimerStopped;
    if (sitl::hw().actions[i].kind == sitl::kTimerStopped) rest = sitl::hw().actions[i].tick - t0;
  }
  EXPECT_EQ(checked.second, begun) << c.file << ": the firmware began other actions than predicted";
  // The rest of what the prediction says: when each line is in; a line that queues nothing takes
  // no time there, or (a setting, Z) until its reply at rest; the end of the whole program;
  // the first step.
  for (size_t i = 0; i < p.records.size(); ++i) {
    const host::PredictRecord& r = p.records[i];
    EXPECT_EQ(got[i].in - t0, r.arrive_tick) << c.file << " line " << r.line << " (" << r.text << "): when it is in";
    if (r.queued) continue;
    const uint64_t at = (r.waits_for_rest ? got[i].answered : got[i].in) - t0;
    EXPECT_EQ(at, r.start_tick) << c.file << " line " << r.line << " (" << r.text << ")";
    EXPECT_EQ(at, r.end_tick) << c.file << " line " << r.line << " (" << r.text << ")";
  }
  EXPECT_EQ(std::max(rest, got.back().answered - t0), p.total_ticks) << c.file << ": the end";
  EXPECT_EQ(sitl::first_step() == 0 ? 0 : sitl::first_step() - t0, p.first_step_tick) << c.file << ": the first step";
  std::printf("  %s, %s: %zu lines in, %zu records' starts and ends, %zu actions; the end at %.6f s\n", c.file,
              host::sender_name(c.sender), got.size(), checked.first, begun, double(p.total_ticks) / 2e6);
}

const char* const kFiles[] = {
    "programs/demo.arm",           "programs/grasp-and-lift.arm",    "programs/push.arm",
    "programs/thesis-repeatability.arm", "programs/too-fast.arm",  "hil/plans/straight-lines.arm",
    "hil/plans/thesis-repeatability.arm", "hil/plans/thesis-single-joint.arm", "hil/plans/tool-points.arm",
    "hil/streams/circle.arm",      "hil/streams/collinear-split.arm", "hil/streams/lines.arm",
    "hil/streams/square.arm",      "hil/streams/stream-mixed.arm",   "hil/streams/zigzag.arm",
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const char* f : kFiles)
    for (host::SenderModel::Kind k : {host::SenderModel::kRest, host::SenderModel::kStream}) out.push_back(Case{f, k});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Shipped, FirmwareMatchesThePrediction, ::testing::ValuesIn(cases()), name_of);

// Random programs: every command the queue takes (L, M, P, T, S, G, D, H), settings that
// wait for rest ($0, $1, $6), lines the firmware refuses (a target beyond a limit or out of
// reach; the host refuses a program with a line the codec cannot read), a '!' of the program's
// own, and timed '!'s at random ticks after the first step; each seed sent both ways.
std::string random_program(uint32_t seed, int n) {
  uint32_t x = seed * 2654435761u + 12345u;
  auto next = [&x]() {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  };
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(next() % 100001) / 100000.0; };
  auto num = [&](double lo, double hi) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3f", uniform(lo, hi));
    return std::string(b);
  };
  std::string text;
  for (int i = 0; i < n; ++i) {
    const uint32_t k = next() % 100;
    std::string l;
    if (k < 18)
      l = "L " + std::to_string(next() % 3) + " " + num(-40, 40);
    else if (k < 36)
      l = "M " + num(-95, 95) + " " + num(30, 135) + " " + num(-48, 18);
    else if (k < 54)
      l = "P " + num(120, 320) + " " + num(-160, 160) + " " + num(10, 260);
    else if (k < 62)
      l = "T " + num(150, 300) + " " + num(-120, 120) + " " + num(40, 220) + " " + num(5, 90);
    else if (k < 68)
      l = "S " + std::to_string(next() % 2);
    else if (k < 73)
      l = "G " + num(0, 100);
    else if (k < 77)
      l = "D " + num(0, 0.4);
    else if (k < 79)
      l = "H";
    else if (k < 83)
      l = "$0=" + std::to_string(200 + next() % 3800);
    else if (k < 86)
      l = "$1=" + std::to_string(500 + next() % 20000);
    else if (k < 89)
      l = "$6=" + std::to_string(next() % 300);
    else if (k < 91)
      l = "!";
    else
      l = "L " + std::to_string(next() % 3) + " " + num(-5, 5);
    text += l + "\n";
  }
  return text;
}

struct RandomCase {
  uint32_t seed;
  host::SenderModel::Kind sender;
  int stops;  // timed '!'s
};

void PrintTo(const RandomCase& c, std::ostream* os) {
  *os << "seed " << c.seed << " --sender " << host::sender_name(c.sender) << ", " << c.stops << " timed stops";
}

class RandomProgramsMatchThePrediction : public ::testing::TestWithParam<RandomCase> {};

// Position of every motor at `tick` from the coil log (steps the motors made), from `from`.
std::vector<int64_t> position_at(uint64_t tick, size_t from) {
  std::vector<int64_t> pos(robot::kJoints, 0);
  for (size_t i = 0; i < from; ++i) pos[sitl::hw().coil_log[i].motor] += sitl::hw().coil_log[i].step;
  for (size_t i = from; i < sitl::hw().coil_log.size() && sitl::hw().coil_log[i].tick <= tick; ++i)
    pos[sitl::hw().coil_log[i].motor] += sitl::hw().coil_log[i].step;
  return pos;
}

TEST_P(RandomProgramsMatchThePrediction, RepliesStepsMoveEndsAndStops) {
  const RandomCase c = GetParam();
  const host::Robot& robot = robot_file();
  const host::Program program =
      host::parse_protocol_program(random_program(c.seed, 150), "seed " + std::to_string(c.seed), robot);
  host::SenderModel sender;
  sender.kind = c.sender;
  std::vector<uint64_t> stops;
  for (int i = 0; i < c.stops; ++i) stops.push_back(uint64_t(c.seed * 7919u + uint32_t(i) * 104729u) % (30 * 2000000u));
  sender.stop_ticks = stops;
  const host::Prediction p = host::predict_program(robot, program, {}, sender);

  std::vector<std::string> lines;
  std::vector<size_t> sent;  // the record of each line sent (timed '!'s are not lines)
  for (size_t i = 0; i < p.records.size(); ++i) {
    const host::PredictRecord& r = p.records[i];
    if (r.stop && r.stop_at >= 0) continue;
    lines.push_back(r.stop ? "!" : r.text);
    sent.push_back(i);
  }
  sim::boot();
  sim::status();
  sim::take_lines();
  const uint64_t t0 = sitl::hw().now;
  const size_t from = sitl::hw().coil_log.size(), actions_from = sitl::hw().actions.size();
  const std::vector<sitl::Exchange> got =
      sitl::run_lines(lines, c.sender == host::SenderModel::kRest ? sitl::kAtRest : sitl::kStreamed, stops);
  ASSERT_EQ(got.size(), lines.size());
  if (getenv("ARTICULA_DUMP"))
    for (size_t j = 0; j < lines.size(); ++j) {
      const host::PredictRecord& r = p.records[sent[j]];
      std::printf("%3d %-28s model arrive %9llu start %9llu end %9llu | sitl in %9llu answered %9llu %s\n", r.line,
                  lines[j].c_str(), (unsigned long long)r.arrive_tick, (unsigned long long)r.start_tick,
                  (unsigned long long)r.end_tick, (unsigned long long)(got[j].in - t0),
                  (unsigned long long)(got[j].answered - t0), got[j].reply.c_str());
    }
  int errors = 0, stopped = 0;
  for (size_t j = 0; j < lines.size(); ++j) {
    const host::PredictRecord& r = p.records[sent[j]];
    const std::string want = r.stop ? "" : r.reply == kOk ? "ok" : "error:" + std::to_string(int(r.reply));
    errors += want.rfind("error:", 0) == 0;
    stopped += want == "error:15";
    EXPECT_EQ(got[j].reply, want) << "line " << r.line << ": " << lines[j];
  }
  std::vector<uint64_t> steps;
  for (size_t i = from; i < sitl::hw().coil_log.size(); ++i) {
    const sitl::CoilWrite& w = sitl::hw().coil_log[i];
    if (w.step != 0 && (steps.empty() || steps.back() != w.tick - t0)) steps.push_back(w.tick - t0);
  }
  uint64_t predicted = 0;
  size_t k = 0, checked_ends = 0, checked_stops = 0;
  for (const host::PredictRecord& r : p.records) {
    if (r.stop && r.stop_at >= 0) {  // where the arm came to rest after it
      const std::vector<int64_t> at = position_at(t0 + r.end_tick, 0);
      for (size_t m = 0; m < r.steps.size() && m < size_t(robot::kJoints); ++m)
        EXPECT_EQ(at[m], r.steps[m]) << "the '!' at " << r.stop_at << ": motor " << m;
      ++checked_stops;
    }
    if (r.dominant_steps == 0) continue;
    predicted += r.dominant_steps;
    k += r.dominant_steps;
    if (r.cut || k > steps.size()) continue;
    EXPECT_EQ(steps[k - 1], r.end_tick) << "line " << r.line << " (" << r.text << "): its last step";
    ++checked_ends;
  }
  EXPECT_EQ(steps.size(), predicted) << "the firmware made other steps than predicted";
  const std::vector<int64_t> end = position_at(UINT64_MAX, 0);
  for (size_t m = 0; m < p.records.back().steps.size() && m < size_t(robot::kJoints); ++m)
    EXPECT_EQ(end[m], p.records.back().steps[m]) << "motor " << m << " at rest";
  EXPECT_EQ(sitl::stops_sent().size(), stops.size());
  EXPECT_EQ(sim::hal_errors(), "");
  const std::pair<size_t, size_t> timed = check_action_times(p, actions_from, t0, "seed " + std::to_string(c.seed));
  std::printf("  seed %u, %s, %d timed stops: %zu lines (%d refused, %d of them error:15), %zu steps, %zu move ends, "
              "%zu actions' starts and ends and %zu stops checked; %.3f s\n",
              c.seed, host::sender_name(c.sender), c.stops, lines.size(), errors, stopped, steps.size(), checked_ends,
              timed.first, checked_stops, steps.empty() ? 0.0 : double(steps.back()) / 2e6);
}

std::vector<RandomCase> random_cases() {
  std::vector<RandomCase> out;
  for (uint32_t seed = 1; seed <= 20; ++seed)
    for (host::SenderModel::Kind k : {host::SenderModel::kRest, host::SenderModel::kStream})
      out.push_back(RandomCase{seed, k, seed % 3 == 0 ? 0 : int(seed % 3) * 2});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Seeded, RandomProgramsMatchThePrediction, ::testing::ValuesIn(random_cases()),
                         [](const ::testing::TestParamInfo<RandomCase>& info) {
                           return "seed" + std::to_string(info.param.seed) +
                                  (info.param.sender == host::SenderModel::kRest ? "_rest" : "_stream");
                         });

}  // namespace

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
