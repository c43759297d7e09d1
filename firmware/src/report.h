// firmware/src/report.h - when the status report is built and when it goes out: the rules
// the Nano's serial interrupts follow (hal_avr.cpp) and the SITL HAL follows too
// (firmware/sitl/hal_sitl.cpp), so that the firmware on the PC runs the Nano's own scheduling. No I/O
// and no registers: the HAL says what happened (a '?' came, a byte of the report went out),
// asks what may happen now (build, send the report's next byte, send a queued byte), and does
// it. The HAL calls it with interrupts off (the flags are shared with the interrupts).
//
// The rules: one report answers every '?' until its first byte goes out; a '?' that comes while
// it goes out gets one more after it. A report goes out only at a line boundary of the other
// output, and a report on its way (asked for, or being built) keeps the next line boundary for
// itself. A report is built with interrupts enabled, from an interrupt's end, never within the
// step computation, and never before the firmware has started.
#ifndef ARTICULA_FIRMWARE_REPORT_H
#define ARTICULA_FIRMWARE_REPORT_H

namespace report {

struct Schedule {
  volatile bool requested = false;  // a '?' that no report being built or waiting answers
  volatile bool building = false;   // status_line() is running
  volatile bool sending = false;    // its first byte has gone out, its LF not yet
  bool again = false;               // a '?' came while it was going out: one more after it

  // A '?' came. `waiting`: a report is built (or being written) and has not started going out.
  void on_request(bool waiting) {
    if (sending)
      again = true;
    else if (!building && !waiting)
      requested = true;
  }

  // Whether the requested report may be built now: none being built or going out, the firmware
  // `started`, and not `in_step` (within the step computation).
  bool due(bool started, bool in_step) const { return requested && !building && !sending && started && !in_step; }

  void begin_build() {
    requested = false;
    building = true;
  }
  void end_build() { building = false; }
  // After a build: another is due at once (a '?' came while the report went out, and its LF
  // went before the build returned).
  bool build_again() const { return requested && !sending; }

  // Whether the transmitter's next byte is the report's: one is going out, or one `waiting`
  // (its first byte written) at a line boundary of the other output (`line_start`).
  bool report_next(bool line_start, bool waiting) const { return sending || (line_start && waiting); }
  // Whether the next queued byte may go: not at a line boundary a report on its way keeps.
  bool queue_may_send(bool line_start) const { return !(line_start && (requested || building)); }

  // A byte of the report went out (`lf`: its last). True when another report is due now (a
  // '?' came while it went out): the HAL builds it once the LF's frame is complete.
  bool on_report_byte(bool lf) {
    if (!lf) {
      sending = true;
      return false;
    }
    sending = false;
    if (!again) return false;
    again = false;
    requested = true;
    return true;
  }

  void reset() { requested = building = sending = again = false; }
};

}  // namespace report

#endif  // ARTICULA_FIRMWARE_REPORT_H
