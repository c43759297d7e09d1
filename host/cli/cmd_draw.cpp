// articula draw ROBOT (--text TEXT | --shape NAME) --width MM --at X,Y --z MM ... -o PROGRAM:
// a drawing for a pen held in the gripper, as a protocol program (host/lib/draw.h): placed on
// the paper, checked against the arm's reach (exit 2 with which way to move it when it does
// not fit), ordered to cut the travel, then predicted step by step as the Nano will draw it.
#include <cxxopts.hpp>
#include <iostream>

#include "blocks.h"
#include "cli_util.h"
#include "commands.h"
#include "draw.h"
#include "ik.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "robot_view.h"
#include "svg.h"

#include <fstream>

namespace articula::cli {
namespace {

double positive(const cxxopts::ParseResult& args, const char* name) {
  const double v = args[name].as<double>();
  if (!(v > 0) || !std::isfinite(v)) throw UsageError(std::string("--") + name + " must be a number > 0, not " + fmt(v, 3));
  return v;
}

// A pen setting's option: its key with '-' for '_' (--travel-speed).
std::string pen_option(const host::PenField& f) {
  std::string o = f.key;
  for (char& c : o)
    if (c == '_') c = '-';
  return o;
}

int run_draw(int argc, char** argv) {
  cxxopts::Options opts("articula draw",
                        "Writes the program that draws text or a shape with a pen held in the gripper: the strokes "
                        "placed on the paper, checked against the arm's reach, ordered to cut the travel, the pen "
                        "lifted between them; then predicts how far the steps keep the pen from the lines.");
  opts.custom_help("ROBOT (FILE.svg | --text TEXT | --shape square|circle|star) --width MM --at X,Y --z MM [options] "
                   "[-o PROGRAM.arm]");
  opts.add_options()("text", "text to write, in a single-stroke Hershey font ('\\n' in it starts a line)",
                     cxxopts::value<std::string>())(
      "shape", "a first lesson's shape: square, circle or star", cxxopts::value<std::string>())(
      "tolerance", "an SVG's curves as straight lines within this of the curve, mm", cxxopts::value<double>()->default_value("0.1"))(
      "width", "the drawing's width on the paper, mm", cxxopts::value<double>())(
      "at", "the drawing's centre on the table, x,y mm", cxxopts::value<std::string>())(
      "z", "the paper's height in the robot's base frame, mm", cxxopts::value<double>())(
      "rotate", "turn the drawing about its centre, degrees counterclockwise seen from above (90: upright for someone at +x facing the arm)",
      cxxopts::value<double>()->default_value("90"))(
      "line-spacing", "text: lines this many capital heights apart", cxxopts::value<double>()->default_value("1.6"))(
      "font", "a Hershey .jhf font", cxxopts::value<std::string>()->default_value(host::default_font_path()))(
      "paper", "the sheet: A4, A5 or Letter (the drawing must fit on it)", cxxopts::value<std::string>())(
      "microsteps", "predict with the motors in full steps (1) or half steps (2), whatever the robot file says",
      cxxopts::value<int>())(
      "svg-out", "also write the drawing and the line the arm will draw (the pen at every step) as SVG",
      cxxopts::value<std::string>())(
      "o,output", "write the program here (default: standard output, the report to standard error)",
      cxxopts::value<std::string>())("h,help", "this help")(
      "robot", "robot file or shipped robot name", cxxopts::value<std::string>())(
      "svg", "an SVG file to draw", cxxopts::value<std::string>());
  // The pen's settings: their names, defaults and ranges are draw.h's (kPenFields).
  for (const host::PenField& f : host::kPenFields)
    opts.add_options()(pen_option(f), std::string(f.what) + ", " + f.unit + " (" + (f.min_excluded ? "above " : "") +
                                          host::protocol_number(f.min) + " to " + host::protocol_number(f.max) + ")",
                       cxxopts::value<double>()->default_value(host::protocol_number(f.fallback)));
  opts.parse_positional({"robot", "svg"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "The pen hangs straight down from the tool point (the MK2's gripper stays level), so the tool\n"
                 "goes --pen mm above each point of the paper. Every stroke is drawn with T (straight lines, pen\n"
                 "down); between strokes the pen lifts --lift mm and travels with T. A drawing the pen cannot\n"
                 "reach exits with code 2 and says which way and how far to move it.\n"
                 "Example: articula draw mk2plus --text Hello --width 60 --at 250,0 --z 0 --pen 120 -o hello.arm\n"
                 "Then: articula predict mk2plus hello.arm\n";
    return 0;
  }
  if (!args.count("robot")) throw UsageError("no robot given");
  if (args.count("text") + args.count("shape") + args.count("svg") != 1)
    throw UsageError("give one of an SVG file, --text and --shape");
  for (const char* req : {"width", "at", "z"})
    if (!args.count(req)) throw UsageError(std::string("--") + req + " is needed");
  const std::vector<double> at = parse_number_list(args["at"].as<std::string>(), "--at");
  if (at.size() != 2) throw UsageError("--at takes x,y (mm), not " + std::to_string(at.size()) + " numbers");
  host::DrawRequest req;
  if (args.count("text")) {
    const std::string text = args["text"].as<std::string>();
    for (size_t i = 0; i < text.size(); ++i) {  // "\n" typed in a shell starts a line
      if (text[i] == '\\' && i + 1 < text.size() && text[i + 1] == 'n') req.text += '\n', ++i;
      else req.text += text[i];
    }
  } else if (args.count("shape")) {
    req.shape = args["shape"].as<std::string>();
  } else {
    const std::string path = args["svg"].as<std::string>();
    std::ifstream f(path, std::ios::binary | std::ios::ate);
    if (!f) throw UsageError("cannot read " + path);
    const auto size = static_cast<size_t>(f.tellg());
    if (size > host::kMaxSvgBytes) throw UsageError(path + ": " + std::to_string(size / 1024) + " KB: a drawing is at most 5 MB");
    f.seekg(0);
    req.svg.assign(size, '\0');
    f.read(req.svg.data(), std::streamsize(size));
    if (req.svg.empty()) throw UsageError(path + ": empty: not an SVG file");
    req.svg_name = path;
  }
  req.tolerance_mm = positive(args, "tolerance");
  if (args.count("paper")) req.paper = args["paper"].as<std::string>();
  req.font_path = args["font"].as<std::string>();
  req.line_spacing = positive(args, "line-spacing");
  req.width_mm = positive(args, "width");
  req.x = at[0], req.y = at[1];
  req.rotation_deg = args["rotate"].as<double>();
  req.pen.paper_z = args["z"].as<double>();
  double* pen[] = {&req.pen.pen_mm, &req.pen.lift_mm, &req.pen.speed, &req.pen.travel_speed};  // kPenFields' order
  for (size_t i = 0; i < std::size(host::kPenFields); ++i) {
    const host::PenField& f = host::kPenFields[i];
    *pen[i] = args[pen_option(f)].as<double>();
    const std::string problem = host::pen_value_problem(f, *pen[i]);
    if (!problem.empty()) throw UsageError("--" + problem);
  }

  host::Robot robot = host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>()));
  if (args.count("microsteps")) {
    try {
      robot = host::with_microsteps(robot, args["microsteps"].as<int>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  const host::InverseKinematics ik(robot);
  host::Drawing d;
  try {
    d = host::make_drawing(robot, ik, req);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  } catch (const host::SvgError& e) {
    throw UsageError(e.what());
  }
  std::ostream& report = args.count("output") ? std::cout : std::cerr;
  report << d.what << ": " << fmt(d.width_mm, 1) << " mm wide, " << fmt(d.height_mm, 1) << " mm high, centred at ("
         << fmt(at[0], 1) << ", " << fmt(at[1], 1) << ") mm, " << d.strokes.size()
         << (d.strokes.size() == 1 ? " stroke" : " strokes") << std::endl;
  if (!d.reach.fits) {
    std::cerr << "articula draw: " << d.reach.advice << "\n";
    return 2;
  }
  report << "reach: the pen reaches all " << d.reach.points << " points checked (every 2 mm along the strokes)\n";
  report << "order: the pen travels " << fmt(d.travel_mm, 0) << " mm between strokes (" << fmt(d.travel_unordered_mm, 0)
         << " mm in the order given)\n";
  const std::string& program = d.program;
  if (robot.has_motors) {
    const host::Program p = host::parse_program(program, "drawing.arm", robot);
    const host::Prediction pred = host::predict_program(robot, p, {}, {}, true);
    for (const host::PredictRecord& r : pred.records)
      if (r.reply != kOk) {
        std::cerr << "articula draw: the arm would refuse line " << r.line << " (" << r.text << "): error:" << int(r.reply)
                  << " " << status_text(r.reply) << "\n";
        return 2;
      }
    // the line the arm will draw: the pen's tip at every step, on the paper
    const host::PredictedInk ink = host::predicted_ink(d, pred, req.pen);
    report << "prediction: " << pred.records.size() << " lines, " << fmt(pred.total_s(), 1) << " s; on the paper the pen "
           << "stays within " << fmt(ink.worst_mm, 2) << " mm of the drawing at every step (" << ink.steps
           << " steps; the worst on line " << ink.worst_line << ", at (" << fmt(ink.worst_at.x, 1) << ", "
           << fmt(ink.worst_at.y, 1) << ") mm)\n";
    if (args.count("svg-out")) {
      write_output(args["svg-out"].as<std::string>(), host::drawing_svg(d, ink, d.what + " on " + robot.name));
      report << "wrote " << args["svg-out"].as<std::string>() << ": the drawing (blue) and the line the arm will draw (orange)\n";
    }
  }
  write_output(args.count("output") ? args["output"].as<std::string>() : "", program);
  if (args.count("output")) report << "wrote " << args["output"].as<std::string>() << "\n";
  return 0;
}

}  // namespace

int cmd_draw(int argc, char** argv) { return run_draw(argc, argv); }

}  // namespace articula::cli
