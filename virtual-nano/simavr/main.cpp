// virtual-nano/simavr/main.cpp - articula-vnano: the Nano firmware's ELF in simavr, on a pseudo-terminal
// (or stdin/stdout), measured. See hil/README.md and `articula-vnano --help`.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>

#include "vnano.h"

#ifndef VNANO_DEFAULT_ELF
#define VNANO_DEFAULT_ELF "build/avr/firmware/articula-nano.elf"
#endif

namespace {

volatile sig_atomic_t g_signal = 0;
void on_signal(int sig) { g_signal = sig; }

const char kHelp[] =
    "usage: articula-vnano [options] [ELF]\n"
    "\n"
    "The virtual Nano: runs the Nano firmware's ELF (the very file `make` builds for the\n"
    "board, unmodified) in simavr, puts its serial port on a pseudo-terminal that opens like\n"
    "a real one, watches the motors, servo and interrupts, and reports what it measured.\n"
    "Everything is timed in CPU cycles (16 MHz), never by the wall clock; the simulation runs\n"
    "as fast as it can (faster than real time when the firmware is idle) unless --realtime.\n"
    "\n"
    "options:\n"
    "  --elf FILE           the firmware (default " VNANO_DEFAULT_ELF ")\n"
    "  --pty-link PATH      make PATH a symbolic link to this run's pseudo-terminal (removed\n"
    "                       at exit); its name is printed on stdout first, as `pty: /dev/pts/N`\n"
    "  --stdio              no pseudo-terminal: the serial line is stdin (to the Nano) and\n"
    "                       stdout (from it); at EOF on stdin the run ends once every byte is\n"
    "                       delivered and the firmware is quiet (step timer off, no output\n"
    "                       for 50 ms of simulated time)\n"
    "  --report FILE        write the measurements as JSON at exit (hil/README.md: fields)\n"
    "  --seconds N          stop after N seconds of simulated time (default: no limit; the run\n"
    "                       ends on SIGINT, SIGTERM or SIGHUP, or at EOF with --stdio)\n"
    "  --endstop M:STEPS    motor M's switch (0: D2, 1: D12, 2: A4) is closed (pin low) while\n"
    "                       the motor's decoded step position is <= STEPS (every motor starts\n"
    "                       at step 0); repeat for several motors\n"
    "  --input PIN:LEVEL[@S]  from S seconds of simulated time (default 0) header pin PIN (A0,\n"
    "                       D12) is driven to LEVEL (0 or 1) from outside: a wire from another\n"
    "                       arm or a device, for the firmware's W (before it, the pin reads its\n"
    "                       pull-up); repeat for more changes, in time order\n"
    "  --output PIN         follow header pin PIN's level (the firmware's O): the report's io\n"
    "                       gives each change and its time; repeat for more pins\n"
    "  --half-step M        count motor M in half steps from the start (default: a motor is\n"
    "                       counted in half steps once it shows a one-coil pattern)\n"
    "  --uln2003            the motors are unipolar (28BYJ-48s) on ULN2003 boards: their inputs\n"
    "                       follow that half-step table (default: bipolar motors on L298Ns)\n"
    "  --cnc                the ELF is the build for a CNC shield (articula-cnc.elf): the motors\n"
    "                       are on STEP/DIR drivers in sockets X, Y, Z (STEP D2..D4, DIR D5..D7,\n"
    "                       EN D8), the endstops on D9..D11, the servo on A3; the report gives\n"
    "                       each driver's shortest STEP pulse and DIR setup time\n"
    "  --servo M:PIN:US     the ELF is the servo build (articula-servo.elf): motor M is a hobby\n"
    "                       servo on header pin PIN (D9), US its pulse at step 0 (the robot\n"
    "                       file's first calibration point); its steps are its pulse's 0.5 us\n"
    "                       ticks. Repeat for each servo; the gripper's servo stays on D3\n"
    "  --gripper CLOSED:OPEN  servo angles in degrees of the closed and open gripper (the\n"
    "                       robot file's servo_closed, servo_open), to report the aperture\n"
    "  --trace-steps FILE   CSV of every coil event: cycle,motor,steps,pattern,event,time_us\n"
    "                       (and of every line's LF in: motor -1, event line)\n"
    "  --paced              lines go in one at a time: each starts on the wire when the reply to\n"
    "                       the one before has been sent whole (a host that waits for each reply,\n"
    "                       taking no time itself: `articula predict --sender stream`); a line\n"
    "                       of realtime bytes only (\"!\") goes out alone, without its LF\n"
    "  --stop-at S          send '!' S seconds after the first step, whatever the lines are\n"
    "                       doing (repeat it for more; `articula predict --stop-at`)\n"
    "  --realtime           never run ahead of the wall clock (for a person at a terminal)\n"
    "  --quiet              no summary on stderr at exit\n"
    "  -h, --help           this text\n"
    "\n"
    "examples:\n"
    "  articula-vnano --pty-link /tmp/nano &      then: python3 -m serial.tools.miniterm /tmp/nano 115200\n"
    "  printf 'I\\nM 10 100 5\\n' | articula-vnano --stdio --report run.json\n"
    "\n"
    "exit status: 0 after a normal end, 1 when the firmware crashed or stopped, 2 for a bad\n"
    "command line or an ELF that cannot run.\n";

struct Args {
  vnano::Config config;
  std::string pty_link, report, trace;
  bool stdio = false, realtime = false, quiet = false;
  double seconds = 0;
};

[[noreturn]] void usage_error(const std::string& msg) {
  std::fprintf(stderr, "articula-vnano: %s (see --help)\n", msg.c_str());
  std::exit(2);
}

bool parse_int(const std::string& s, long long& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  v = std::strtoll(s.c_str(), &end, 10);
  return errno == 0 && end && *end == '\0';
}

bool parse_double(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && std::isfinite(v);
}

Args parse_args(int argc, char** argv) {
  Args a;
  a.config.elf.clear();
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    std::string value;
    bool has_value = false;
    const size_t eq = arg.find('=');
    if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      has_value = true;
    }
    auto need = [&](const char* name) -> std::string {
      if (has_value) return value;
      if (i + 1 >= argc) usage_error(std::string(name) + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kHelp, stdout);
      std::exit(0);
    } else if (arg == "--elf") {
      a.config.elf = need("--elf");
    } else if (arg == "--pty-link") {
      a.pty_link = need("--pty-link");
    } else if (arg == "--stdio") {
      a.stdio = true;
    } else if (arg == "--paced") {
      a.config.paced = true;
    } else if (arg == "--stop-at") {
      double v = 0;
      if (!parse_double(need("--stop-at"), v) || v < 0 ||
          (!a.config.stop_at_s.empty() && v < a.config.stop_at_s.back()))
        usage_error("--stop-at: seconds, 0 or more, each no earlier than the one before");
      a.config.stop_at_s.push_back(v);
    } else if (arg == "--report") {
      a.report = need("--report");
    } else if (arg == "--seconds") {
      if (!parse_double(need("--seconds"), a.seconds) || a.seconds <= 0) usage_error("--seconds: a positive number");
    } else if (arg == "--endstop") {
      const std::string v = need("--endstop");
      const size_t c = v.find(':');
      long long m = 0, steps = 0;
      if (c == std::string::npos || !parse_int(v.substr(0, c), m) || !parse_int(v.substr(c + 1), steps) || m < 0 ||
          m >= vnano::VirtualNano::kMotors)
        usage_error("--endstop M:STEPS, M a motor 0 to 2, STEPS a whole number: not " + v);
      a.config.endstops.push_back({int(m), steps});
    } else if (arg == "--input") {
      // PIN:LEVEL[@S], e.g. A0:0@1.5
      const std::string v = need("--input");
      const size_t c = v.find(':'), at = v.find('@');
      const int pin = c == std::string::npos ? -1 : vnano::header_pin(v.substr(0, c));
      long long level = -1;
      double s = 0;
      const std::string lv = c == std::string::npos ? "" : v.substr(c + 1, at == std::string::npos ? std::string::npos : at - c - 1);
      if (pin < 0 || !parse_int(lv, level) || (level != 0 && level != 1) ||
          (at != std::string::npos && (!parse_double(v.substr(at + 1), s) || s < 0)) ||
          (!a.config.inputs.empty() && s < a.config.inputs.back().at_s))
        usage_error("--input PIN:LEVEL[@S], PIN a header pin (D2..D13, A0..A5), LEVEL 0 or 1, S seconds (0 or more, "
                    "each no earlier than the one before): not " + v);
      a.config.inputs.push_back({pin, int(level), s});
    } else if (arg == "--output") {
      const std::string v = need("--output");
      const int pin = vnano::header_pin(v);
      if (pin < 0) usage_error("--output PIN, a header pin (D2..D13, A0..A5): not " + v);
      a.config.outputs.push_back(pin);
    } else if (arg == "--half-step") {
      long long m = 0;
      if (!parse_int(need("--half-step"), m) || m < 0 || m >= vnano::VirtualNano::kMotors)
        usage_error("--half-step M, M a motor 0 to 2");
      a.config.half_step_motors.push_back(int(m));
    } else if (arg == "--uln2003") {
      a.config.unipolar = true;
    } else if (arg == "--cnc") {
      a.config.cnc_shield = true;
    } else if (arg == "--servo") {
      // M:PIN:ZERO_US, e.g. 0:D9:1500
      const std::string v = need("--servo");
      const size_t c1 = v.find(':'), c2 = c1 == std::string::npos ? c1 : v.find(':', c1 + 1);
      long long m = -1;
      double zero_us = 0;
      int pin = -1;
      if (c2 != std::string::npos) {
        const std::string name = v.substr(c1 + 1, c2 - c1 - 1);
        pin = vnano::header_pin(name);
      }
      if (c2 == std::string::npos || !parse_int(v.substr(0, c1), m) || m < 0 || m >= vnano::VirtualNano::kMotors ||
          pin < 0 || !parse_double(v.substr(c2 + 1), zero_us) || zero_us <= 0)
        usage_error("--servo M:PIN:US, M a motor 0 to 2, PIN a header pin (D2..D13, A0..A5), US its pulse at step 0: not " + v);
      a.config.servos.push_back({int(m), pin, (long long)(zero_us * 2 + 0.5)});
    } else if (arg == "--gripper") {
      const std::string v = need("--gripper");
      const size_t c = v.find(':');
      if (c == std::string::npos || !parse_double(v.substr(0, c), a.config.servo_closed_deg) ||
          !parse_double(v.substr(c + 1), a.config.servo_open_deg) ||
          a.config.servo_closed_deg == a.config.servo_open_deg)
        usage_error("--gripper CLOSED:OPEN, two different angles in degrees: not " + v);
      a.config.gripper_range = true;
    } else if (arg == "--trace-steps") {
      a.trace = need("--trace-steps");
    } else if (arg == "--realtime") {
      a.realtime = true;
    } else if (arg == "--quiet") {
      a.quiet = true;
    } else if (!arg.empty() && arg[0] == '-') {
      usage_error("unknown option " + arg);
    } else if (a.config.elf.empty()) {
      a.config.elf = arg;
    } else {
      usage_error("one ELF only");
    }
    if (has_value && arg != "--elf" && arg != "--pty-link" && arg != "--report" && arg != "--seconds" &&
        arg != "--endstop" && arg != "--half-step" && arg != "--gripper" && arg != "--trace-steps" && arg != "--input" &&
        arg != "--output")
      usage_error(arg + " takes no value");
  }
  if (a.config.elf.empty()) a.config.elf = VNANO_DEFAULT_ELF;
  if (a.stdio && !a.pty_link.empty()) usage_error("--stdio and --pty-link exclude each other");
  return a;
}

// The pseudo-terminal: a new /dev/pts/N each run. We keep the slave side open ourselves, in
// raw mode, so that a program opening and closing it (a terminal, pyserial) never makes
// the master side fail, and no echo ever sends the firmware's output back to it.
struct Pty {
  int master = -1, slave = -1;
  std::string name;
};

bool open_pty(Pty& p, std::string& error) {
  p.master = posix_openpt(O_RDWR | O_NOCTTY);
  if (p.master < 0 || grantpt(p.master) != 0 || unlockpt(p.master) != 0) {
    error = std::string("cannot make a pseudo-terminal: ") + std::strerror(errno);
    return false;
  }
  char buf[128];
  if (ptsname_r(p.master, buf, sizeof buf) != 0) {
    error = "ptsname failed";
    return false;
  }
  p.name = buf;
  p.slave = open(buf, O_RDWR | O_NOCTTY);
  if (p.slave < 0) {
    error = "cannot open " + p.name + ": " + std::strerror(errno);
    return false;
  }
  termios t;
  if (tcgetattr(p.slave, &t) == 0) {
    cfmakeraw(&t);
    cfsetispeed(&t, B115200);
    cfsetospeed(&t, B115200);
    tcsetattr(p.slave, TCSANOW, &t);
  }
  fcntl(p.master, F_SETFL, fcntl(p.master, F_GETFL) | O_NONBLOCK);
  return true;
}

bool make_link(const std::string& link, const std::string& target, std::string& error) {
  const std::string tmp = link + ".vnano-" + std::to_string(getpid());
  unlink(tmp.c_str());
  if (symlink(target.c_str(), tmp.c_str()) != 0 || rename(tmp.c_str(), link.c_str()) != 0) {
    error = "cannot make the link " + link + ": " + std::strerror(errno);
    unlink(tmp.c_str());
    return false;
  }
  return true;
}

void remove_link(const std::string& link, const std::string& target) {
  char buf[256];
  const ssize_t n = readlink(link.c_str(), buf, sizeof buf - 1);
  if (n <= 0) return;
  buf[n] = '\0';
  if (target == buf) unlink(link.c_str());  // only our own link
}

bool write_report(const std::string& path, const nlohmann::json& j) {
  const std::string tmp = path + ".tmp-" + std::to_string(getpid());
  FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) return false;
  const std::string s = j.dump(2) + "\n";
  const bool ok = std::fwrite(s.data(), 1, s.size(), f) == s.size();
  if (std::fclose(f) != 0 || !ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Args args = parse_args(argc, argv);

  FILE* trace = nullptr;
  if (!args.trace.empty()) {
    trace = std::fopen(args.trace.c_str(), "w");
    if (!trace) usage_error("cannot write " + args.trace + ": " + std::strerror(errno));
    args.config.trace = trace;
  }
  vnano::VirtualNano nano;
  std::string error;
  if (access(args.config.elf.c_str(), R_OK) != 0) {
    std::fprintf(stderr, "articula-vnano: no firmware ELF at %s (build it: make firmware)\n", args.config.elf.c_str());
    return 2;
  }
  if (!nano.load(args.config, error)) {
    std::fprintf(stderr, "articula-vnano: %s\n", error.c_str());
    return 2;
  }

  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
  // A harness that dies (a test killed on its timeout) ends its virtual Nano too, as a SIGTERM:
  // orphaned, it would run on at full speed for ever.
  const pid_t parent = getppid();
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) g_signal = SIGTERM;  // the parent went before the line above

  // The serial line's two ends on our side.
  Pty pty;
  int in_fd = 0, out_fd = 1;
  int in_flags = -1, out_flags = -1;
  if (args.stdio) {
    in_flags = fcntl(0, F_GETFL);
    out_flags = fcntl(1, F_GETFL);
    if (in_flags >= 0) fcntl(0, F_SETFL, in_flags | O_NONBLOCK);
    if (out_flags >= 0) fcntl(1, F_SETFL, out_flags | O_NONBLOCK);
  } else {
    if (!open_pty(pty, error)) {
      std::fprintf(stderr, "articula-vnano: %s\n", error.c_str());
      return 2;
    }
    if (!args.pty_link.empty() && !make_link(args.pty_link, pty.name, error)) {
      std::fprintf(stderr, "articula-vnano: %s\n", error.c_str());
      return 2;
    }
    in_fd = out_fd = pty.master;
    std::printf("pty: %s\n", pty.name.c_str());
    std::fflush(stdout);
  }

  const auto wall_start = std::chrono::steady_clock::now();
  const uint64_t freq = nano.frequency();
  const uint64_t slice = freq / 1000;  // 1 ms of simulated time between looks at the outside
  const uint64_t quiet = freq / 20;    // 50 ms: "the firmware is quiet" at EOF
  const uint64_t limit = args.seconds > 0 ? uint64_t(args.seconds * double(freq)) : 0;
  const size_t kMaxBuffered = 1 << 20;
  bool eof = false, out_closed = false;
  uint64_t output_dropped = 0;
  std::string reason;

  auto flush_output = [&]() {
    std::string& out = nano.output();
    if (out.empty()) return;
    if (out_closed) {
      out.clear();
      return;
    }
    while (!out.empty()) {
      const ssize_t n = write(out_fd, out.data(), out.size());
      if (n > 0) {
        out.erase(0, size_t(n));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && args.stdio) out_closed = true;  // reader gone
      break;
    }
    if (out.size() > kMaxBuffered) {  // nobody reads: keep the newest, like a full USB buffer
      output_dropped += out.size() - kMaxBuffered;
      out.erase(0, out.size() - kMaxBuffered);
    }
  };
  auto read_input = [&]() {
    char buf[4096];
    for (;;) {
      const ssize_t n = read(in_fd, buf, sizeof buf);
      if (n > 0) {
        nano.host_send(buf, size_t(n));
        continue;
      }
      if (n == 0 && args.stdio) eof = true;
      break;  // EAGAIN, or (pty) no client: nothing now
    }
  };

  int exit_code = 0;
  for (;;) {
    if (g_signal) {
      reason = g_signal == SIGINT ? "SIGINT" : g_signal == SIGTERM ? "SIGTERM" : "SIGHUP";
      break;
    }
    uint64_t target = nano.cycle() + slice;
    if (limit && target > limit) target = limit;
    nano.run_until(target);
    flush_output();
    if (!eof) read_input();
    if (nano.halted()) {
      reason = std::string("firmware ") + nano.cpu_state();
      exit_code = 1;
      break;
    }
    if (limit && nano.cycle() >= limit) {
      reason = "time limit";
      break;
    }
    if (eof && nano.host_pending() == 0 && !nano.awaiting_reply() && nano.serial_idle() && !nano.step_timer_led() &&
        nano.output().empty() && nano.cycle() - nano.last_activity() >= quiet) {
      reason = "end of input";
      break;
    }
    if (args.realtime) {
      const double sim_s = double(nano.cycle()) / double(freq);
      const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      if (sim_s > wall_s + 0.001) {
        pollfd p{in_fd, POLLIN, 0};
        poll(&p, 1, int((sim_s - wall_s) * 1000.0));
      }
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // Last output: up to half a second for a slow reader.
  for (int i = 0; i < 50 && !nano.output().empty() && !out_closed; ++i) {
    flush_output();
    if (nano.output().empty()) break;
    pollfd p{out_fd, POLLOUT, 0};
    poll(&p, 1, 10);
  }

  nano.finish();
  nlohmann::json report = nano.report();
  report["exit_reason"] = reason;
  report["wall_s"] = vnano::Stat::round3(wall_s);
  const double sim_s = double(nano.cycle()) / double(freq);
  const double speed = wall_s > 0 ? sim_s / wall_s : 0.0;
  report["speed_x_realtime"] = wall_s > 0 ? nlohmann::json(vnano::Stat::round3(speed)) : nlohmann::json(nullptr);
  report["serial"] = args.stdio ? "stdio" : pty.name;
  report["uart"]["output_dropped"] = output_dropped;
  if (!args.report.empty() && !write_report(args.report, report)) {
    std::fprintf(stderr, "articula-vnano: cannot write the report %s\n", args.report.c_str());
    exit_code = exit_code ? exit_code : 1;
  }
  if (!args.quiet) {
    std::fprintf(stderr, "articula-vnano: %.3f s simulated in %.3f s (%.1fx real time), ended by %s\n", sim_s, wall_s,
                 speed, reason.c_str());
    std::fputs(nano.summary().c_str(), stderr);
  }

  if (trace) std::fclose(trace);
  if (args.stdio) {
    if (in_flags >= 0) fcntl(0, F_SETFL, in_flags);
    if (out_flags >= 0) fcntl(1, F_SETFL, out_flags);
  } else {
    if (!args.pty_link.empty()) remove_link(args.pty_link, pty.name);
    close(pty.slave);
    close(pty.master);
  }
  return exit_code;
}
