// firmware/test/test_report/test_report.cpp - when the status report is built and when it
// goes out (src/report.h): the rules the Nano's serial interrupts follow, here one event at a
// time, including those an instant transmitter (the SITL HAL's) never meets: a '?' while a
// report is going out, and a report's LF gone before the next build returns.
#include <gtest/gtest.h>

#include "report.h"

namespace {

// Built, and its first byte (and `more` after it) gone out.
void build_and_start(report::Schedule& r) {
  ASSERT_TRUE(r.due(true, false));
  r.begin_build();
  r.end_build();
  EXPECT_FALSE(r.on_report_byte(false));  // '<'
}

TEST(Report, OneReportAnswersEveryQuestionUntilItStartsGoingOut) {
  report::Schedule r;
  r.on_request(false);
  EXPECT_TRUE(r.requested);
  r.on_request(false);  // a second '?' before the build: the same report
  r.begin_build();
  r.on_request(false);  // while it is built
  EXPECT_FALSE(r.requested);
  r.end_build();
  EXPECT_FALSE(r.build_again());
  r.on_request(true);  // built, waiting for a line boundary
  EXPECT_FALSE(r.requested);
  EXPECT_FALSE(r.again);
}

TEST(Report, AQuestionWhileItGoesOutGetsExactlyOneMore) {
  report::Schedule r;
  r.on_request(false);
  build_and_start(r);
  EXPECT_TRUE(r.sending);
  r.on_request(true);
  r.on_request(true);  // two '?' while it goes out: one more report, not two
  EXPECT_TRUE(r.again);
  EXPECT_FALSE(r.requested);
  EXPECT_FALSE(r.on_report_byte(false));
  EXPECT_TRUE(r.on_report_byte(true));  // its LF: the next is due
  EXPECT_FALSE(r.sending);
  EXPECT_TRUE(r.requested);
  EXPECT_TRUE(r.due(true, false));
  build_and_start(r);
  EXPECT_FALSE(r.on_report_byte(true));  // and no third
  EXPECT_FALSE(r.requested);
}

TEST(Report, NeverBeforeTheFirmwareStartsNorWithinTheStepComputation) {
  report::Schedule r;
  r.on_request(false);
  EXPECT_FALSE(r.due(false, false));
  EXPECT_FALSE(r.due(true, true));
  EXPECT_TRUE(r.due(true, false));
  r.begin_build();
  EXPECT_FALSE(r.due(true, false));  // one build at a time
}

TEST(Report, ItGoesOnlyAtALineBoundaryAndKeepsTheNextForItself) {
  report::Schedule r;
  EXPECT_FALSE(r.report_next(false, true));  // mid-line: the line first
  EXPECT_TRUE(r.report_next(true, true));
  EXPECT_FALSE(r.report_next(true, false));  // nothing written yet
  EXPECT_TRUE(r.queue_may_send(true));
  r.on_request(false);
  EXPECT_FALSE(r.queue_may_send(true));  // asked for: the boundary waits for it
  EXPECT_TRUE(r.queue_may_send(false));  // (a line under way goes on)
  r.begin_build();
  EXPECT_FALSE(r.queue_may_send(true));
  r.end_build();
  EXPECT_FALSE(r.on_report_byte(false));
  EXPECT_TRUE(r.report_next(false, true));  // going out: its bytes until its LF
  EXPECT_FALSE(r.on_report_byte(true));
  EXPECT_TRUE(r.queue_may_send(true));
}

TEST(Report, ALineFeedGoneBeforeTheBuildReturnsBuildsTheNextAtOnce) {
  // The report goes out as it is written: its bytes leave while the build still runs.
  report::Schedule r;
  r.on_request(false);
  ASSERT_TRUE(r.due(true, false));
  r.begin_build();
  EXPECT_FALSE(r.on_report_byte(false));  // '<' gone, the build going on
  r.on_request(true);                     // a '?' while it goes out
  EXPECT_TRUE(r.on_report_byte(true));    // its LF gone before the build returned
  EXPECT_FALSE(r.due(true, false));       // (the TX-complete interrupt cannot build: one is running)
  r.end_build();
  EXPECT_TRUE(r.build_again());  // so the build runs again at once
  r.begin_build();
  r.end_build();
  EXPECT_FALSE(r.build_again());
  r.reset();
  EXPECT_FALSE(r.requested || r.building || r.sending || r.again);
}

}  // namespace
