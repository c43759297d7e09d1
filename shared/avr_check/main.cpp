#include "check_common.h"

volatile float g_in = 0.5f;
volatile long g_out;

int main() {
  check_platform();
  check_transform();
  check_dh();
  check_actuation();
  check_ik_ypp();
  check_status();
  check_protocol();
  check_articula();
  for (;;) {
  }
}
