// The sizes the firmware uses: float, three joints, four DH rows (the MK2 arm).
#ifndef ARTICULA_AVR_CHECK_COMMON_H
#define ARTICULA_AVR_CHECK_COMMON_H
typedef float Real;
static const int kJoints = 3;
static const int kRows = 4;
// Each check_*.cpp defines one of these; the generated main of its ELF calls it, so the
// instantiations are compiled and linked.
void check_platform();
void check_transform();
void check_dh();
void check_actuation();
void check_ik_ypp();
void check_status();
void check_protocol();
void check_motion();
void check_servo();
void check_drive();
void check_articula();
void check_config();
void check_planner();
void check_settings();
void check_line();
// Inputs and outputs the optimiser cannot see through.
extern volatile float g_in;
extern volatile long g_out;
#endif
